// SPDX-License-Identifier: MIT
// Extreme cases (docs/robustness.md), run identically in the stock and the quadphase build of Box2D: far
// coordinates and ShiftOrigin, sizes over seven decades, thousands of bodies in one spot, proxies that leave the
// bounds fast and come back, bodies created and destroyed every step. Both builds must pass the same checks; the
// quadphase build also gives exactly the stock tree's pairs (validation mode). One million proxies:
// core_extreme_test.cpp.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include <catch2/catch.hpp>

#include "quadphase_scenes/scenes.h"
#include "world_check.h"

using namespace qprobust;

namespace
{

} // namespace

TEST_CASE("extreme: a pyramid 1e5 and 1e6 m from the origin, then ShiftOrigin while running", "[extreme]")
{
    for (float offset : {1.0e5f, 1.0e6f})
    {
        INFO("offset " << offset);
        auto world = std::make_unique<b2World>(b2Vec2(0.0f, -10.0f));
        Exactness exact(*world);
        const b2Vec2 origin(offset, offset * 0.5f);
        AddBox(*world, b2_staticBody, origin + b2Vec2(0.0f, -0.5f), 30.0f, 0.5f, 0.0f);
        const int base = 6;
        for (int row = 0; row < base; ++row)
        {
            for (int i = 0; i < base - row; ++i)
            {
                const float x = (-0.5f * float(base - row - 1) + float(i)) * 1.1f;
                AddBox(*world, b2_dynamicBody, origin + b2Vec2(x, 0.5f + float(row)), 0.5f, 0.5f, 1.0f);
            }
        }
        for (int i = 0; i < 8; ++i)
        {
            AddCircle(*world, b2_dynamicBody, origin + b2Vec2(-10.0f + 2.5f * float(i), 10.0f), 0.4f, 1.0f);
        }
        // Far out, float positions are coarse (1/128 m at 1e5, 1/16 m at 1e6): the checks are what both
        // builds keep there, bodies near the pyramid, finite and not flung away.
        const b2AABB nearFar{origin + b2Vec2(-30.0f, -2.0f), origin + b2Vec2(30.0f, 20.0f)};
        const Observed far = StepWorld(*world, 120);
        CHECK(AllDynamicInside(*world, nearFar));

        world->ShiftOrigin(origin); // the pyramid is now at the origin, mid-run
        const b2AABB nearZero{b2Vec2(-30.0f, -2.0f), b2Vec2(30.0f, 20.0f)};
        CHECK(AllDynamicInside(*world, nearZero));
        const Observed near = StepWorld(*world, 180);

        char name[80];
        std::snprintf(name, sizeof(name), "pyramid at %.0e m, ShiftOrigin after 120 steps", double(offset));
        Print(name, far, "max speed after the shift %.3f, touching contacts %d", double(near.maxSpeed),
              TouchingContacts(*world));
        REQUIRE(far.finite);
        REQUIRE(near.finite);
        CHECK(far.maxSpeed < 30.0f);
        CHECK(near.maxSpeed < 30.0f);
        CHECK(AllDynamicInside(*world, nearZero));
        CHECK(TouchingContacts(*world) > 20); // still a pile resting on the ground
        exact.Require(300);
    }
}

TEST_CASE("extreme: objects from 1e-3 m to 1e4 m in one scene", "[extreme]")
{
    auto world = std::make_unique<b2World>(b2Vec2(0.0f, -10.0f));
    Exactness exact(*world);
    AddBox(*world, b2_staticBody, b2Vec2(0.0f, -0.5f), 5000.0f, 0.5f, 0.0f); // 1e4 m ground, top at y = 0
    // dynamic boxes and circles of 1 mm to 100 m, mixed along the ground, dropped from above their size
    const float sizes[] = {1e-3f, 3e-3f, 1e-2f, 3e-2f, 0.1f, 0.3f, 1.0f, 3.0f, 10.0f, 30.0f, 100.0f};
    float x = -400.0f;
    for (int rep = 0; rep < 3; ++rep)
    {
        for (float s : sizes)
        {
            x += 1.5f * s + 1.0f;
            if (rep == 1)
            {
                AddCircle(*world, b2_dynamicBody, b2Vec2(x, 2.0f * s + 0.5f), 0.5f * s, 1.0f);
            }
            else
            {
                AddBox(*world, b2_dynamicBody, b2Vec2(x, 2.0f * s + 0.5f), 0.5f * s, 0.5f * s, 1.0f);
            }
            // a swarm of 1 cm pebbles onto every large body
            if (s >= 10.0f)
            {
                for (int k = 0; k < 20; ++k)
                {
                    AddCircle(*world, b2_dynamicBody,
                              b2Vec2(x - 0.4f * s + 0.04f * s * float(k), 3.0f * s + 1.0f), 0.005f, 1.0f);
                }
            }
        }
    }
    const Observed seen = StepWorld(*world, 400);
    Print("sizes 1e-3 m .. 1e4 m", seen, "lowest body centre ever %.5f, touching contacts %d",
          double(seen.lowestY), TouchingContacts(*world));
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed < 120.0f);
    CHECK(seen.lowestY > -0.01f); // nothing through the ground
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-1000.0f, -0.01f), b2Vec2(1000.0f, 400.0f)}));
    exact.Require(400);
}

TEST_CASE("extreme: two thousand bodies piled into one spot", "[extreme]")
{
    // Every body overlaps every other; a negative group index keeps Box2D from making contacts, so this is
    // the broadphase's own worst case: n (n - 1) / 2 pairs whenever they all move (validation checks each of
    // them).
    auto world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
    Exactness exact(*world);
    const int n = 2000;
    for (int i = 0; i < n; ++i)
    {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(3.0f + 1e-4f * float(i % 7), -2.0f + 1e-4f * float(i % 11));
        def.linearVelocity.Set(1.5f, 1.0f);
        b2Body* b = world->CreateBody(&def);
        b2CircleShape shape;
        shape.m_radius = 0.05f;
        b2FixtureDef fixture;
        fixture.shape = &shape;
        fixture.density = 1.0f;
        fixture.filter.groupIndex = -1;
        b->CreateFixture(&fixture);
    }
    const Observed seen = StepWorld(*world, 8);
    Print("2000 bodies in one spot", seen, "contacts %d (filtered by group)", world->GetContactCount());
    REQUIRE(seen.finite);
    CHECK(seen.maxSpeed == Approx(std::sqrt(1.5f * 1.5f + 1.0f)).epsilon(1e-5));
    CHECK(world->GetContactCount() == 0);
    const long long pairs = exact.Require(8);
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    CHECK(pairs >= 2LL * n * (n - 1) / 2); // created, then moved out of their fat boxes at least once
#else
    (void)pairs;
#endif
}

TEST_CASE("extreme: proxies leave the bounds at high speed and come back", "[extreme]")
{
    // A resting cluster of 400 circles, and 200 kinematic sensor bodies that start among them, fly out
    // radially at 300 m/s (Box2D clamps it to 120 m/s) for 1.5 s (far beyond any bounds fitted to the
    // cluster) and fly back: the quadtree must follow them out and back (its bounds are refitted when a
    // quarter of the proxies is outside), with the stock pairs.
    auto world = std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
    Exactness exact(*world);
    for (int i = 0; i < 400; ++i)
    {
        AddCircle(*world, b2_dynamicBody, b2Vec2(float(i % 20) - 9.5f, float(i / 20) - 9.5f), 0.45f, 1.0f);
    }
    std::vector<b2Body*> flyers;
    std::vector<b2Vec2> start;
    for (int i = 0; i < 200; ++i)
    {
        const float a = 2.0f * b2_pi * float(i) / 200.0f;
        b2BodyDef def;
        def.type = b2_kinematicBody;
        def.position.Set(9.0f * std::cos(a) * float(i % 3 + 1) / 3.0f,
                         9.0f * std::sin(a) * float(i % 3 + 1) / 3.0f);
        def.linearVelocity.Set(300.0f * std::cos(a), 300.0f * std::sin(a));
        b2Body* b = world->CreateBody(&def);
        b2PolygonShape shape;
        shape.SetAsBox(0.2f, 0.2f);
        b2FixtureDef fixture;
        fixture.shape = &shape;
        fixture.isSensor = true;
        b->CreateFixture(&fixture);
        flyers.push_back(b);
        start.push_back(def.position);
    }
    float farthest = 0.0f;
    auto track = [&](int) {
        for (b2Body* b : flyers)
        {
            farthest = std::fmax(farthest, b->GetPosition().Length());
        }
    };
    const Observed out = StepWorld(*world, 90, track);
    for (b2Body* b : flyers)
    {
        b->SetLinearVelocity(-b->GetLinearVelocity());
    }
    const Observed back = StepWorld(*world, 90, track);

    float worst = 0.0f;
    for (size_t i = 0; i < flyers.size(); ++i)
    {
        worst = std::fmax(worst, (flyers[i]->GetPosition() - start[i]).Length());
    }
    Print("200 flyers out at 300 m/s and back", out,
          "farthest flyer %.1f m, worst return error %.4f m, cluster max speed %.4f", double(farthest),
          double(worst), double(back.maxSpeed));
    REQUIRE(out.finite);
    REQUIRE(back.finite);
    CHECK(farthest > 150.0f); // 2 m per step at most (b2_maxTranslation): 180 m out
    CHECK(worst < 0.05f);
    CHECK(back.maxSpeed < 1.0f); // sensors push nothing: the cluster stays at rest
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-10.0f, -10.0f), b2Vec2(10.0f, 10.0f)}));
    exact.Require(180);
}

TEST_CASE("extreme: bodies created and destroyed every step", "[extreme]")
{
    // An open box with a changing population: each step destroys 25 bodies at random and creates 25 new ones
    // at random places (portable random numbers, the same in both builds), 400 steps.
    auto world = std::make_unique<b2World>(b2Vec2(0.0f, -10.0f));
    Exactness exact(*world);
    AddBox(*world, b2_staticBody, b2Vec2(0.0f, -0.5f), 20.0f, 0.5f, 0.0f);
    AddBox(*world, b2_staticBody, b2Vec2(-20.5f, 15.0f), 0.5f, 15.0f, 0.0f);
    AddBox(*world, b2_staticBody, b2Vec2(20.5f, 15.0f), 0.5f, 15.0f, 0.0f);
    quadphase::scenes::Rng rng(6006u);
    std::vector<b2Body*> bodies;
    auto spawn = [&]() {
        const b2Vec2 p(rng.Uniform(-19.0f, 19.0f), rng.Uniform(1.0f, 25.0f));
        const float size = rng.Uniform(0.1f, 0.6f);
        bodies.push_back(rng.Index(2) == 0 ? AddCircle(*world, b2_dynamicBody, p, size, 1.0f)
                                           : AddBox(*world, b2_dynamicBody, p, size, size, 1.0f));
    };
    for (int i = 0; i < 500; ++i)
    {
        spawn();
    }
    long long created = 0;
    const Observed seen = StepWorld(*world, 400, [&](int) {
        for (int k = 0; k < 25; ++k)
        {
            const uint32_t victim = rng.Index(uint32_t(bodies.size()));
            world->DestroyBody(bodies[victim]);
            bodies[victim] = bodies.back();
            bodies.pop_back();
        }
        for (int k = 0; k < 25; ++k)
        {
            spawn();
            ++created;
        }
    });
    Print("churn 25 per step", seen, "bodies %d, created %lld, proxies %d", DynamicBodies(*world), created,
          world->GetProxyCount());
    REQUIRE(seen.finite);
    CHECK(DynamicBodies(*world) == 500);
    CHECK(world->GetProxyCount() == 503);
    CHECK(seen.maxSpeed < 40.0f);
    CHECK(AllDynamicInside(*world, b2AABB{b2Vec2(-20.0f, -0.1f), b2Vec2(20.0f, 30.0f)}));
    exact.Require(400);
}
