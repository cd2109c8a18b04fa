// SPDX-License-Identifier: MIT
// quadphase's Box as Box2D's b2AABB.
#pragma once

#include "box2d/b2_collision.h"
#include "quadphase/box.h"

namespace qpbench
{

/// quadphase's Box as Box2D's b2AABB, for the tools that drive stock Box2D's b2BroadPhase (qp-replay,
/// qp-circles).
inline b2AABB ToAabb(const quadphase::Box& b)
{
    b2AABB a;
    a.lowerBound.Set(b.minX, b.minY);
    a.upperBound.Set(b.maxX, b.maxY);
    return a;
}

} // namespace qpbench
