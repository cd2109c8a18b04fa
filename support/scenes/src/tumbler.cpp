// SPDX-License-Identifier: MIT
// tumbler: the Box2D testbed's Tumbler benchmark.
//
// A dynamic hollow box (four 1 m thick walls, 20 x 20 m outside, 19 x 19 m inside, density 5, never sleeps)
// centred at (0, 10) turns around its centre at 0.05 pi rad/s, driven by a revolute joint motor
// (max torque 1e8) to a static ground body. Small boxes (0.25 x 0.25 m, density 1) are added over time, like
// the testbed, but ceil(size / 200) per step so that all `size` boxes exist after 200 steps whatever the size
// (800 -> 4 per step; the testbed adds one per step). They are spawned by perStep after each step, at the
// points of an 8 x 8 lattice with 0.4 m pitch around the centre (cycling through the lattice, so a point is
// reused only every 64 boxes, when the previous box has long fallen). Spawning is deterministic; the seed
// only rotates the starting lattice point.
#include "scene_common.h"

#include <algorithm>

namespace quadphase::scenes::detail
{

Scene BuildTumbler(int size, uint32_t seed)
{
    Scene scene = MakeScene(SceneId::Tumbler, size, seed, b2Vec2(0.0f, -10.0f));
    b2World& world = *scene.world;

    b2Body* ground = CreateStaticBody(world);

    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.allowSleep = false;
    bd.position.Set(0.0f, 10.0f);
    b2Body* drum = world.CreateBody(&bd);
    AddBoxFixture(drum, 0.5f, 10.0f, b2Vec2(10.0f, 0.0f), 5.0f);
    AddBoxFixture(drum, 0.5f, 10.0f, b2Vec2(-10.0f, 0.0f), 5.0f);
    AddBoxFixture(drum, 10.0f, 0.5f, b2Vec2(0.0f, 10.0f), 5.0f);
    AddBoxFixture(drum, 10.0f, 0.5f, b2Vec2(0.0f, -10.0f), 5.0f);

    b2RevoluteJointDef jd;
    jd.bodyA = ground;
    jd.bodyB = drum;
    jd.localAnchorA.Set(0.0f, 10.0f);
    jd.localAnchorB.Set(0.0f, 0.0f);
    jd.referenceAngle = 0.0f;
    jd.motorSpeed = 0.05f * b2_pi;
    jd.maxMotorTorque = 1e8f;
    jd.enableMotor = true;
    world.CreateJoint(&jd);

    const int perStepCount = (size + 199) / 200;
    constexpr int kLattice = 8;
    constexpr float kPitch = 0.4f;
    int spawned = 0;
    int next = static_cast<int>(seed % (kLattice * kLattice));
    scene.perStep = [size, perStepCount, spawned, next](b2World& w, int /*step*/) mutable {
        b2PolygonShape shape;
        shape.SetAsBox(0.125f, 0.125f);
        const int count = std::min(perStepCount, size - spawned);
        for (int i = 0; i < count; ++i)
        {
            const int ix = next % kLattice;
            const int iy = next / kLattice;
            next = (next + 1) % (kLattice * kLattice);

            b2BodyDef def;
            def.type = b2_dynamicBody;
            def.position.Set(kPitch * (static_cast<float>(ix) - 0.5f * (kLattice - 1)),
                             10.0f + kPitch * (static_cast<float>(iy) - 0.5f * (kLattice - 1)));
            b2Body* body = w.CreateBody(&def);
            body->CreateFixture(&shape, 1.0f);
            ++spawned;
        }
    };
    return scene;
}

} // namespace quadphase::scenes::detail
