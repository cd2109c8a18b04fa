// SPDX-License-Identifier: MIT
// The exact (double) entry of a segment into a box, for tests that need an oracle independent of the float
// segment test (SegmentTest). No Catch: the fuzz targets use it too (tests/fuzz/strict_segment.h).
#pragma once

#include "quadphase/box.h"
#include "ray.h"
#include "slab_clip.h"

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
    return ClipToSlabs(p, d, lo, hi, tmin, tmax) ? tmin : -1.0;
}

} // namespace qptest
