// SPDX-License-Identifier: MIT
// The phase a falling-and-piling scene is in after a step, from the world's state (qp-step, qp-record): with D
// dynamic bodies, "falling" while fewer than 1% of them touch a static body (in rain: until the bottom row of the
// spawn grid lands), "resting" once fewer than 5% are awake and faster than 0.5 m/s, "piling" in between. A phase
// never goes back (falling, piling, resting in that order). Reads the world only; call it outside any timing.
#pragma once

#include <algorithm>

#include "box2d/box2d.h"

namespace qpbench
{

enum Phase
{
    Falling,
    Piling,
    Resting,
    PhaseCount
};
constexpr const char* kPhaseName[PhaseCount] = {"falling", "piling", "resting"};

/// The phase the world is in after a step; `previous` keeps it from going back. `awake`, when given, receives
/// the number of awake dynamic bodies.
inline Phase Classify(const b2World& world, Phase previous, int* awake = nullptr)
{
    int dynamic = 0, landed = 0, moving = 0, awakeCount = 0;
    for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        if (b->GetType() != b2_dynamicBody)
        {
            continue;
        }
        ++dynamic;
        awakeCount += b->IsAwake() ? 1 : 0;
        moving += b->IsAwake() && b->GetLinearVelocity().LengthSquared() > 0.25f ? 1 : 0;
        for (const b2ContactEdge* e = b->GetContactList(); e != nullptr; e = e->next)
        {
            if (e->contact->IsTouching() && e->other->GetType() == b2_staticBody)
            {
                ++landed;
                break;
            }
        }
    }
    if (awake != nullptr)
    {
        *awake = awakeCount;
    }
    const Phase p = 100 * landed < dynamic ? Falling : (20 * moving < dynamic ? Resting : Piling);
    return std::max(p, previous);
}

} // namespace qpbench
