// SPDX-License-Identifier: MIT
// Automatic view: what is in the world at the start.
#include "view_bounds.h"

#include <algorithm>

namespace quadphase::scene_cli
{

namespace
{
struct Bounds
{
    bool empty = true;
    b2AABB box{};

    void Add(const b2AABB& aabb)
    {
        if (empty)
        {
            box = aabb;
            empty = false;
        }
        else
        {
            box.Combine(aabb);
        }
    }
};
} // namespace

ViewRect AutoView(const b2World& world)
{
    Bounds small;
    Bounds all;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        for (const b2Fixture* fixture = body->GetFixtureList(); fixture != nullptr;
             fixture = fixture->GetNext())
        {
            // Fixture AABBs of a body's proxies: one per child (a chain has one per segment).
            for (int32 child = 0; child < fixture->GetShape()->GetChildCount(); ++child)
            {
                b2AABB aabb;
                fixture->GetShape()->ComputeAABB(&aabb, body->GetTransform(), child);
                all.Add(aabb);
                const b2Vec2 extent = aabb.upperBound - aabb.lowerBound;
                if (extent.x <= kAutoViewMaxFixture && extent.y <= kAutoViewMaxFixture)
                {
                    small.Add(aabb);
                }
            }
        }
    }
    const Bounds& use = small.empty ? all : small;
    if (use.empty)
    {
        return ViewRect{-10.0f, -10.0f, 10.0f, 10.0f};
    }
    const b2Vec2 lo = use.box.lowerBound;
    const b2Vec2 hi = use.box.upperBound;
    const float margin = 0.04f * std::max({hi.x - lo.x, hi.y - lo.y, 1.0f});
    return ViewRect{lo.x - margin, lo.y - margin, hi.x + margin, hi.y + margin};
}

} // namespace quadphase::scene_cli
