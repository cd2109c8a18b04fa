// SPDX-License-Identifier: MIT
// The slab test in double precision, without the types of either side: the exact oracle under the core tests'
// segment entry (segment_entry.h) and the Box2D-level query dump (tests/box2d/query_raycast_dump.cpp).
#pragma once

#include <algorithm>
#include <utility>

namespace qptest
{

/// Narrows [t0, t1] to the parameters t at which p + t d lies in the box [lo, hi] (both axes, borders
/// included); false when nothing is left. On an axis with d = 0 the point must lie within the slab.
inline bool ClipToSlabs(const double p[2], const double d[2], const double lo[2], const double hi[2],
                        double& t0, double& t1)
{
    for (int axis = 0; axis < 2; ++axis)
    {
        if (d[axis] == 0.0)
        {
            if (p[axis] < lo[axis] || p[axis] > hi[axis])
            {
                return false;
            }
            continue;
        }
        double ta = (lo[axis] - p[axis]) / d[axis];
        double tb = (hi[axis] - p[axis]) / d[axis];
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

} // namespace qptest
