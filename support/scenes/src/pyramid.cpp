// SPDX-License-Identifier: MIT
// pyramid: the Box2D testbed's Pyramid, with a configurable base.
//
// A two-sided edge ground and base*(base+1)/2 unit boxes (density 5, friction 0.2 Box2D default) stacked as
// in the testbed: boxes 1.125 m apart, each row shifted by 0.5625 m, bottom row 0.25 m above the ground, so
// the stack settles during the first steps and then mostly sleeps. The seed is unused (the scene has no
// randomness). Testbed size: 20; the benchmarks also use 100 (5050 boxes).
#include "scene_common.h"

#include <algorithm>

namespace quadphase::scenes::detail
{

Scene BuildPyramid(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Pyramid, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;

    const float spacing = 1.125f;
    const float width = spacing * static_cast<float>(size - 1);
    {
        const float halfGround = std::max(40.0f, 0.5f * width + 20.0f);
        b2Body* ground = CreateStaticBody(world);
        b2EdgeShape edge;
        edge.SetTwoSided(b2Vec2(-halfGround, 0.0f), b2Vec2(halfGround, 0.0f));
        ground->CreateFixture(&edge, 0.0f);
    }

    AddBoxPyramid(world, size, -0.5f * width, 0.75f);
    return scene;
}

} // namespace quadphase::scenes::detail
