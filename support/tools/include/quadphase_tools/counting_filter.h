// SPDX-License-Identifier: MIT
// A contact filter that counts the new pairs reaching Box2D's filtering: the same count whatever the
// broadphase reports internally, so the builds can be compared on it. Compiled against the including
// program's Box2D build.
#pragma once

#include <cstdint>

#include "box2d/box2d.h"

namespace quadphase::tools
{

/// Counts the pairs Box2D asks the user filter about, and keeps Box2D's default decision.
class CountingFilter : public b2ContactFilter
{
public:
    bool ShouldCollide(b2Fixture* fixtureA, b2Fixture* fixtureB) override
    {
        ++calls;
        return b2ContactFilter::ShouldCollide(fixtureA, fixtureB);
    }

    int64_t calls = 0;
};

} // namespace quadphase::tools
