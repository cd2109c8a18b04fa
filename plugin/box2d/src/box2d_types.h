// SPDX-License-Identifier: MIT
// Box2D's types and settings as the core's: b2AABB as Box, b2_aabbExtension and b2_aabbMultiplier as FatPolicy.
#pragma once

#include <cstddef>
#include <type_traits>

#include "box2d/b2_collision.h"
#include "box2d/b2_settings.h"
#include "broad_phase_interface.h"
#include "fat_policy.h"
#include "quadphase/box.h"

namespace quadphase
{
namespace detail
{

// The core's query callback type is the adapter's, and its boxes are b2AABB's floats in b2AABB's order: callbacks
// and boxes pass straight through.
static_assert(std::is_same<int32, ProxyId>::value, "Box2D's int32 must be quadphase's ProxyId");
static_assert(sizeof(b2AABB) == sizeof(Box) && offsetof(b2AABB, upperBound) == offsetof(Box, maxX),
              "b2AABB and quadphase::Box must both be minX, minY, maxX, maxY");

inline Box ToBox(const b2AABB& a)
{
    return Box{a.lowerBound.x, a.lowerBound.y, a.upperBound.x, a.upperBound.y};
}

/// b2DynamicTree's fat-box policy, Box2D's settings.
inline FatPolicy Box2DFatPolicy()
{
    FatPolicy policy;
    policy.extension = b2_aabbExtension;
    policy.multiplier = b2_aabbMultiplier;
    return policy;
}

} // namespace detail
} // namespace quadphase
