// SPDX-License-Identifier: MIT
// Stiff cases (docs/robustness.md), run identically in the stock and the quadphase build of Box2D: both must pass the
// same physical checks (no NaN, bounded speed, the tower still standing, no bullet through a wall), and the
// quadphase build must give exactly the stock tree's pairs (validation mode, 0 mismatches). Each prints a
// one-line summary, the figures of docs/robustness.md.
#include <cmath>
#include <memory>
#include <vector>

#include <catch2/catch.hpp>

#include "world_check.h"

using namespace qprobust;

namespace
{

std::unique_ptr<b2World> WorldWithGround(b2Vec2 gravity)
{
    auto world = std::make_unique<b2World>(gravity);
    AddBox(*world, b2_staticBody, b2Vec2(0.0f, -0.5f), 50.0f, 0.5f, 0.0f); // top face at y = 0
    return world;
}

} // namespace

TEST_CASE("stiff: a stack with 1:1000 mass ratios does not explode", "[stiff]")
{
    // Box2D's solver cannot hold such a stack upright: stock topples it within seconds (the heavy boxes slide
    // off the light ones). What both builds must keep: no NaN, no speed beyond a fall's, nothing through the
    // ground or flung out of the neighbourhood.
    auto world = WorldWithGround(b2Vec2(0.0f, -10.0f));
    Exactness exact(*world);
    std::vector<b2Body*> stack;
    for (int i = 0; i < 8; ++i)
    {
        // light, heavy, light, heavy ...: every contact in the stack has a 1:1000 mass ratio
        const float density = (i % 2 == 0) ? 1.0f : 1000.0f;
        stack.push_back(
            AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.5f + 1.0f * float(i)), 0.5f, 0.5f, density));
    }
    const Observed seen = StepWorld(*world, 600);

    const float spread = LargestAbsX(stack);
    Print("mass ratio 1:1000 stack of 8", seen, "lowest centre ever %.3f, largest final |x| %.3f, top y %.3f",
          double(seen.lowestY), double(spread), double(stack.back()->GetPosition().y));
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed < 15.0f); // a free fall from the top of the stack reaches 12.5 m/s
    CHECK(seen.lowestY > 0.4f);   // nothing sank into the ground (a box's centre rests at 0.5)
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-12.0f, 0.0f), b2Vec2(12.0f, 9.0f)}));
    exact.Require(600);
}

TEST_CASE("stiff: a tower of 40 bricks stands", "[stiff]")
{
    auto world = WorldWithGround(b2Vec2(0.0f, -10.0f));
    Exactness exact(*world);
    std::vector<b2Body*> tower;
    for (int i = 0; i < 40; ++i)
    {
        tower.push_back(
            AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.25f + 0.5f * float(i)), 1.0f, 0.25f, 1.0f));
    }
    const Observed seen = StepWorld(*world, 600);

    const float maxDrift = LargestAbsX(tower);
    Print("tower of 40 bricks (2 x 0.5 m)", seen, "top y %.3f (start 19.75), largest |x| %.3f",
          double(tower.back()->GetPosition().y), double(maxDrift));
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed < 5.0f);
    CHECK(tower.back()->GetPosition().y > 19.0f); // still standing (it settles by the boxes' skins)
    CHECK(maxDrift < 0.5f);                       // and upright
    exact.Require(600);
}

TEST_CASE("stiff: a heavy plank on light boxes", "[stiff]")
{
    auto world = WorldWithGround(b2Vec2(0.0f, -10.0f));
    Exactness exact(*world);
    std::vector<b2Body*> light;
    for (float x : {-2.5f, 2.5f})
    {
        for (int i = 0; i < 3; ++i)
        {
            light.push_back(
                AddBox(*world, b2_dynamicBody, b2Vec2(x, 0.25f + 0.5f * float(i)), 0.25f, 0.25f, 1.0f));
        }
    }
    // plank mass 6 * 0.2 * 1000 = 1200 kg on boxes of 0.25 kg each
    b2Body* plank = AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 1.6f), 3.0f, 0.1f, 1000.0f);
    const Observed seen = StepWorld(*world, 600);

    Print("heavy plank on light boxes", seen, "plank y %.3f (start 1.6), plank angle %.4f",
          double(plank->GetPosition().y), double(plank->GetAngle()));
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed < 10.0f);
    // stock squeezes the light boxes out from under the plank, which then rests on the ground (y = 0.1 +
    // skin)
    CHECK(plank->GetPosition().y > 0.09f);
    CHECK(std::fabs(plank->GetAngle()) < 0.3f);
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-6.0f, 0.0f), b2Vec2(6.0f, 3.0f)}));
    exact.Require(600);
}

TEST_CASE("stiff: a pyramid under 10x gravity", "[stiff]")
{
    auto world = WorldWithGround(b2Vec2(0.0f, -100.0f));
    Exactness exact(*world);
    const int base = 12;
    for (int row = 0; row < base; ++row)
    {
        for (int i = 0; i < base - row; ++i)
        {
            const float x = -0.5f * float(base - row - 1) + float(i) * 1.0f;
            AddBox(*world, b2_dynamicBody, b2Vec2(x * 1.05f, 0.5f + float(row)), 0.5f, 0.5f, 1.0f);
        }
    }
    const Observed seen = StepWorld(*world, 600);

    Print("pyramid of 78 under 10x gravity", seen, "lowest box centre ever %.3f, touching contacts %d",
          double(seen.lowestY), TouchingContacts(*world));
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed < 20.0f);
    CHECK(seen.lowestY > 0.3f); // no box through the ground
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-10.0f, 0.0f), b2Vec2(10.0f, 13.0f)}));
    exact.Require(600);
}

TEST_CASE("stiff: bullets at 300 m/s do not pass thin walls (continuous collision on)", "[stiff]")
{
    auto world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
    world->SetContinuousPhysics(true);
    Exactness exact(*world);
    const float wallX = 10.0f;
    AddBox(*world, b2_staticBody, b2Vec2(wallX, 0.0f), 0.025f, 6.0f, 0.0f); // 5 cm thick static wall
    // 5 cm thick dynamic walls, heavy, one per lane above the static wall: bullets vs dynamic bodies
    std::vector<b2Body*> dynamicWalls;
    for (int i = 0; i < 3; ++i)
    {
        b2Body* wall =
            AddBox(*world, b2_dynamicBody, b2Vec2(wallX, 10.0f + 3.0f * float(i)), 0.025f, 1.2f, 50.0f);
        wall->SetFixedRotation(true);
        dynamicWalls.push_back(wall);
    }
    std::vector<b2Body*> bullets;
    std::vector<b2Body*> lanes; // the dynamic wall in the bullet's lane, or nullptr for the static wall
    for (int i = 0; i < 24; ++i)
    {
        const bool upper = i >= 12;
        const float y = upper ? 10.0f + 3.0f * float((i - 12) % 3) + 0.25f * float((i - 12) / 3 - 2)
                              : -5.0f + 10.0f * float(i) / 11.0f;
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.bullet = true;
        def.position.Set(-0.5f * float(i % 4), y);
        // 300 m/s, slightly off the axis; Box2D clamps a step's travel to b2_maxTranslation (2 m, 120 m/s),
        // still 40 wall thicknesses per step
        const float angle = 0.02f * float(i % 5 - 2);
        def.linearVelocity.Set(300.0f * std::cos(angle), 300.0f * std::sin(angle));
        b2Body* b = world->CreateBody(&def);
        b2CircleShape shape;
        shape.m_radius = 0.05f;
        b->CreateFixture(&shape, 5.0f);
        bullets.push_back(b);
        lanes.push_back(upper ? dynamicWalls[size_t((i - 12) % 3)] : nullptr);
    }
    // A bullet tunnelled when it is beyond its wall while level with the wall's face (a bullet deflected
    // around the end of a pushed wall is not a tunnel).
    int passed = 0;
    const Observed seen = StepWorld(*world, 120, [&](int) {
        for (size_t i = 0; i < bullets.size(); ++i)
        {
            const b2Vec2 p = bullets[i]->GetPosition();
            const b2Vec2 wall = lanes[i] != nullptr ? lanes[i]->GetPosition() : b2Vec2(wallX, 0.0f);
            const float halfHeight = lanes[i] != nullptr ? 1.2f : 6.0f;
            passed += (p.x > wall.x && std::fabs(p.y - wall.y) < halfHeight) ? 1 : 0;
        }
    });

    Print("24 bullets at 300 m/s vs 5 cm walls", seen, "bullet-steps beyond their wall %d", passed);
    REQUIRE(seen.finite);
    CHECK(passed == 0);
    exact.Require(120);
}
