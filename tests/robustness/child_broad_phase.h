// SPDX-License-Identifier: MIT
// For the child programs of the cmake -P drivers (validation_log_child.cpp, secure_environment_child.cpp), which
// drive a b2BroadPhase directly: a callback for UpdatePairs and the boxes of their proxies.
#pragma once

#include <box2d/b2_broad_phase.h>

/// An UpdatePairs callback that ignores the pairs (the children look at what validation found, not at the pairs).
struct NoPairs
{
    void AddPair(void*, void*) {}
};

/// The 1 x 1 box whose lower corner is (x, y).
inline b2AABB Aabb(float x, float y)
{
    b2AABB box;
    box.lowerBound.Set(x, y);
    box.upperBound.Set(x + 1.0f, y + 1.0f);
    return box;
}
