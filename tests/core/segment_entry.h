// The exact (double) entry of a segment into a box, for tests that need an oracle independent of the float
// segment test (SegmentTest). No Catch: the fuzz targets use it too (tests/fuzz/strict_segment.h).
#pragma once

#include <algorithm>
#include <utility>

#include "quadphase/box.h"
#include "quadphase/ray.h"

namespace qptest
{

/// Entry fraction of the segment p1 -> p1 + maxFraction (p2 - p1) into box b (slab test in double), or -1
/// when it misses.
inline double EntryFraction(const quadphase::RayInput& in, const quadphase::Box& b)
{
    double tmin = 0.0;
    double tmax = double(in.maxFraction);
    const double p[2] = {double(in.p1.x), double(in.p1.y)};
    const double d[2] = {double(in.p2.x) - double(in.p1.x), double(in.p2.y) - double(in.p1.y)};
    const double lo[2] = {double(b.minX), double(b.minY)};
    const double hi[2] = {double(b.maxX), double(b.maxY)};
    for (int axis = 0; axis < 2; ++axis)
    {
        if (d[axis] == 0.0)
        {
            if (p[axis] < lo[axis] || p[axis] > hi[axis])
            {
                return -1.0;
            }
            continue;
        }
        double t1 = (lo[axis] - p[axis]) / d[axis];
        double t2 = (hi[axis] - p[axis]) / d[axis];
        if (t1 > t2)
        {
            std::swap(t1, t2);
        }
        tmin = std::max(tmin, t1);
        tmax = std::min(tmax, t2);
        if (tmin > tmax)
        {
            return -1.0;
        }
    }
    return tmin;
}

} // namespace qptest
