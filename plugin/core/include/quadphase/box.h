// SPDX-License-Identifier: MIT
// Axis-aligned boxes and the exact comparisons the broadphase relies on.
#pragma once

#include <cmath>

namespace quadphase
{

/// A 2D vector in world units (metres for Box2D).
struct Vec2
{
    float x;
    float y;
};

/// An axis-aligned box in world units. Same memory layout as Box2D's b2AABB
/// (lowerBound.x, lowerBound.y, upperBound.x, upperBound.y).
/// A box is valid when minX <= maxX and minY <= maxY; touching boxes overlap.
struct Box
{
    float minX;
    float minY;
    float maxX;
    float maxY;
};

/// Overlap test with the same result as Box2D's b2TestOverlap for every finite or infinite box:
/// touching counts as overlapping. For boxes holding NaN it answers false (b2TestOverlap answers true),
/// so a corrupted box never pairs with anything.
inline bool Overlaps(const Box& a, const Box& b)
{
    return a.minX <= b.maxX && b.minX <= a.maxX && a.minY <= b.maxY && b.minY <= a.maxY;
}

/// True when `outer` contains `inner`, borders included (Box2D's b2AABB::Contains).
inline bool Contains(const Box& outer, const Box& inner)
{
    bool result = true;
    result = result && outer.minX <= inner.minX;
    result = result && outer.minY <= inner.minY;
    result = result && inner.maxX <= outer.maxX;
    result = result && inner.maxY <= outer.maxY;
    return result;
}

/// True when every coordinate is finite.
inline bool IsFinite(const Box& b)
{
    return std::isfinite(b.minX) && std::isfinite(b.minY) && std::isfinite(b.maxX) && std::isfinite(b.maxY);
}

/// True when min <= max on both axes (false for NaN).
inline bool IsOrdered(const Box& b)
{
    return b.minX <= b.maxX && b.minY <= b.maxY;
}

/// True when the box is finite and ordered: the common case, tested without short-circuit branches.
inline bool IsSane(const Box& b)
{
    // int operands: & on bools is what is meant, and clang warns about it otherwise.
    return (int(std::isfinite(b.minX)) & int(std::isfinite(b.minY)) & int(std::isfinite(b.maxX)) &
            int(std::isfinite(b.maxY)) & int(b.minX <= b.maxX) & int(b.minY <= b.maxY)) != 0;
}

/// Bitwise-equal comparison of the stored floats, used by validation.
inline bool SameBits(const Box& a, const Box& b)
{
    return a.minX == b.minX && a.minY == b.minY && a.maxX == b.maxX && a.maxY == b.maxY;
}

} // namespace quadphase
