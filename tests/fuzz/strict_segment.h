// The proxies a segment must reach whatever the float rounding: what both fuzz targets demand of RayCast
// where its answer cannot be compared with b2DynamicTree's test exactly.
//
// b2DynamicTree::RayCast's test (separating axis along the segment's normal, in float) rounds in proportion
// to the magnitudes involved: a few ulps of the largest coordinate or extent. Within 65,536 m of the origin
// that is under 0.03 m, below b2_aabbExtension, and both targets compare RayCast with that test exactly.
// Beyond, a giant box (seen: 1e14 m tall) may pass the float test though the segment misses it by kilometres;
// quadphase's cell walk, which follows the segment's true path, then skips it, and stock's tree may skip it
// too (its test on a large ancestor rounds the other way). There the targets demand only: every box the
// segment crosses with a margin (StrictlyCrosses) is reported, and nothing the float test rejects.
#pragma once

#include <algorithm>
#include <cmath>

#include "quadphase/box.h"
#include "quadphase/ray.h"

namespace quadphase
{
namespace fuzz
{

/// Largest coordinate magnitude for which the targets compare RayCast with the float test exactly.
constexpr float kExactRayLimit = 65536.0f;

/// True when the segment p1 -> p1 + maxFraction (p2 - p1), computed in double, crosses `box` shrunk on every
/// side by 1e-5 of the largest magnitude involved (about 80 float ulps): far beyond any rounding of the float
/// test.
inline bool StrictlyCrosses(const Box& box, const RayInput& ray)
{
    const double p[2] = {double(ray.p1.x), double(ray.p1.y)};
    const double d[2] = {double(ray.p2.x) - p[0], double(ray.p2.y) - p[1]};
    double magnitude = 0.0;
    for (double v : {p[0], p[1], double(ray.p2.x), double(ray.p2.y), double(box.minX), double(box.minY),
                     double(box.maxX), double(box.maxY)})
    {
        magnitude = std::max(magnitude, std::fabs(v));
    }
    if (!std::isfinite(magnitude))
    {
        return false;
    }
    const double margin = 1.0e-5 * magnitude + 1.0e-6;
    const double lo[2] = {double(box.minX) + margin, double(box.minY) + margin};
    const double hi[2] = {double(box.maxX) - margin, double(box.maxY) - margin};
    double t0 = 0.0;
    double t1 = double(ray.maxFraction);
    for (int i = 0; i < 2; ++i)
    {
        if (lo[i] > hi[i])
        {
            return false;
        }
        if (d[i] == 0.0)
        {
            if (p[i] < lo[i] || p[i] > hi[i])
            {
                return false;
            }
            continue;
        }
        double ta = (lo[i] - p[i]) / d[i];
        double tb = (hi[i] - p[i]) / d[i];
        if (ta > tb)
        {
            std::swap(ta, tb);
        }
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1)
        {
            return false;
        }
    }
    return true;
}

} // namespace fuzz
} // namespace quadphase
