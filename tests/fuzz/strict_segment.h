// SPDX-License-Identifier: MIT
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

#include "../core/segment_entry.h"
#include "quadphase/box.h"
#include "ray.h"

namespace quadphase
{
namespace fuzz
{

/// Largest coordinate magnitude for which the targets compare RayCast with the float test exactly.
constexpr float kExactRayLimit = 65536.0f;

/// True when the segment p1 -> p1 + maxFraction (p2 - p1), computed in double (qptest::EntryFraction),
/// crosses `box` shrunk on every side by 1e-5 of the largest magnitude involved (about 80 float ulps): far
/// beyond any rounding of the float test.
inline bool StrictlyCrosses(const Box& box, const RayInput& ray)
{
    float magnitude = 0.0f;
    for (float v : {ray.p1.x, ray.p1.y, ray.p2.x, ray.p2.y, box.minX, box.minY, box.maxX, box.maxY})
    {
        magnitude = std::max(magnitude, std::fabs(v));
    }
    if (!std::isfinite(magnitude))
    {
        return false;
    }
    // The margin is far above a float ulp of the box, so computing the shrunk box in float changes nothing.
    const float margin = 1.0e-5f * magnitude + 1.0e-6f;
    const Box shrunk{box.minX + margin, box.minY + margin, box.maxX - margin, box.maxY - margin};
    return IsOrdered(shrunk) && qptest::EntryFraction(ray, shrunk) >= 0.0;
}

} // namespace fuzz
} // namespace quadphase
