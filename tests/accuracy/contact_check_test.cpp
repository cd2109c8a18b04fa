// SPDX-License-Identifier: MIT
// bench/accuracy's checker must find contacts that are really missing and nothing else; the accuracy report's
// "missed contacts" of the exact builds (0) mean something only if it does.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>

#include "contact_check.h"
#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::accuracy::CheckMissedContacts;
using quadphase::accuracy::KineticEnergy;
using quadphase::accuracy::MeasurePenetration;
using quadphase::scenes::AddBody;

constexpr float kDt = 1.0f / 60.0f;

std::unique_ptr<b2World> MakeWorld()
{
    return std::make_unique<b2World>(b2Vec2(0.0f, 0.0f));
}

b2Body* AddBox(b2World& world, b2BodyType type, b2Vec2 position, float half, int16 group = 0)
{
    b2PolygonShape shape;
    shape.SetAsBox(half, half);
    b2FixtureDef material;
    material.density = 1.0f;
    material.filter.groupIndex = group;
    return AddBody(world, type, position, shape, material);
}

b2Body* AddCircle(b2World& world, b2BodyType type, b2Vec2 position, float radius)
{
    b2CircleShape shape;
    shape.m_radius = radius;
    b2FixtureDef material;
    material.density = 1.0f;
    return AddBody(world, type, position, shape, material);
}

class RejectAll : public b2ContactFilter
{
public:
    bool ShouldCollide(b2Fixture*, b2Fixture*) override { return false; }
};

} // namespace

TEST_CASE("a contact Box2D has not created yet is reported missing, and not once Step created it")
{
    auto world = MakeWorld();
    AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f);
    AddBox(*world, b2_dynamicBody, b2Vec2(0.8f, 0.0f), 0.5f);
    AddBox(*world, b2_dynamicBody, b2Vec2(10.0f, 0.0f), 0.5f); // overlaps nothing

    // Box2D creates contacts in the next Step's UpdatePairs: until then the overlapping pair has none.
    auto before = CheckMissedContacts(*world, true);
    CHECK(before.overlapping == 1);
    CHECK(before.missed == 1);
    REQUIRE(before.missedPairs.size() == 1);
    CHECK(before.missedPairs[0].first.fixture != before.missedPairs[0].second.fixture);

    world->Step(kDt, 8, 3);
    auto after = CheckMissedContacts(*world);
    CHECK(after.overlapping == 1);
    CHECK(after.missed == 0);
}

TEST_CASE("a body teleported onto another has a missing contact until the next Step")
{
    auto world = MakeWorld();
    AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f);
    b2Body* mover = AddBox(*world, b2_dynamicBody, b2Vec2(5.0f, 0.0f), 0.5f);
    world->Step(kDt, 8, 3);
    CHECK(CheckMissedContacts(*world).overlapping == 0);

    mover->SetTransform(b2Vec2(0.5f, 0.2f), 0.3f);
    auto m = CheckMissedContacts(*world);
    CHECK(m.overlapping == 1);
    CHECK(m.missed == 1);
    world->Step(kDt, 8, 3);
    CHECK(CheckMissedContacts(*world).missed == 0);
}

TEST_CASE("pairs Box2D would not collide are neither overlapping nor missed")
{
    SECTION("negative group index")
    {
        auto world = MakeWorld();
        AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f, -1);
        AddBox(*world, b2_dynamicBody, b2Vec2(0.5f, 0.0f), 0.5f, -1);
        CHECK(CheckMissedContacts(*world).overlapping == 0);
    }
    SECTION("same body")
    {
        auto world = MakeWorld();
        b2Body* body = AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f);
        b2CircleShape circle;
        circle.m_radius = 0.5f;
        body->CreateFixture(&circle, 1.0f);
        CHECK(CheckMissedContacts(*world).overlapping == 0);
    }
    SECTION("no dynamic body")
    {
        auto world = MakeWorld();
        AddBox(*world, b2_staticBody, b2Vec2(0.0f, 0.0f), 0.5f);
        AddBox(*world, b2_staticBody, b2Vec2(0.5f, 0.0f), 0.5f);
        AddBox(*world, b2_kinematicBody, b2Vec2(0.2f, 0.0f), 0.5f);
        CHECK(CheckMissedContacts(*world).overlapping == 0);
    }
    SECTION("the world's contact filter")
    {
        auto world = MakeWorld();
        RejectAll filter;
        world->SetContactFilter(&filter);
        AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f);
        AddBox(*world, b2_dynamicBody, b2Vec2(0.5f, 0.0f), 0.5f);
        CHECK(CheckMissedContacts(*world).overlapping == 0);
    }
    SECTION("a joint with collideConnected = false, and not with collideConnected = true")
    {
        for (bool collideConnected : {false, true})
        {
            auto world = MakeWorld();
            b2Body* a = AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.0f), 0.5f);
            b2Body* b = AddBox(*world, b2_dynamicBody, b2Vec2(0.5f, 0.0f), 0.5f);
            b2RevoluteJointDef jd;
            jd.Initialize(a, b, b2Vec2(0.25f, 0.0f));
            jd.collideConnected = collideConnected;
            world->CreateJoint(&jd);
            auto m = CheckMissedContacts(*world);
            CHECK(m.overlapping == (collideConnected ? 1 : 0));
            CHECK(m.missed == m.overlapping);
        }
    }
}

TEST_CASE("chain children are checked one by one")
{
    auto world = MakeWorld();
    b2BodyDef bd;
    b2Body* ground = world->CreateBody(&bd);
    b2Vec2 vertices[5];
    for (int i = 0; i < 5; ++i)
    {
        vertices[i].Set(-10.0f + 5.0f * static_cast<float>(i), 0.0f);
    }
    b2ChainShape chain;
    chain.CreateChain(vertices, 5, b2Vec2(-15.0f, 0.0f), b2Vec2(15.0f, 0.0f));
    ground->CreateFixture(&chain, 0.0f);
    // Straddles the vertex at x = 0 (children 1 and 2) and touches nothing else.
    AddBox(*world, b2_dynamicBody, b2Vec2(0.0f, 0.2f), 0.5f);

    auto before = CheckMissedContacts(*world, true);
    CHECK(before.overlapping == 2);
    CHECK(before.missed == 2);
    REQUIRE(before.missedPairs.size() == 2);
    world->Step(kDt, 8, 3);
    CHECK(CheckMissedContacts(*world).missed == 0);
}

TEST_CASE("the checker's grid finds the same overlapping pairs as testing every pair")
{
    auto world = MakeWorld();
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> pos(-20.0f, 20.0f);
    std::uniform_real_distribution<float> half(0.1f, 1.2f);
    std::vector<b2Body*> bodies;
    bodies.push_back(AddBox(*world, b2_staticBody, b2Vec2(0.0f, -21.0f), 30.0f)); // spans many grid cells
    for (int i = 0; i < 400; ++i)
    {
        const float x = pos(rng), y = pos(rng), h = half(rng);
        bodies.push_back(i % 3 == 0 ? AddCircle(*world, b2_dynamicBody, b2Vec2(x, y), h)
                                    : AddBox(*world, b2_dynamicBody, b2Vec2(x, y), h));
    }
    int64_t expected = 0;
    for (size_t i = 0; i < bodies.size(); ++i)
    {
        for (size_t j = i + 1; j < bodies.size(); ++j)
        {
            const b2Fixture* a = bodies[i]->GetFixtureList();
            const b2Fixture* b = bodies[j]->GetFixtureList();
            expected += b2TestOverlap(a->GetShape(), 0, b->GetShape(), 0, bodies[i]->GetTransform(),
                                      bodies[j]->GetTransform())
                            ? 1
                            : 0;
        }
    }
    REQUIRE(expected > 100);
    auto m = CheckMissedContacts(*world);
    CHECK(m.overlapping == expected);
    CHECK(m.missed == expected); // no Step yet: no contact at all
    world->Step(kDt, 1, 0);
    // After the step every overlapping pair has its contact (the broadphases of both builds are exact).
    CHECK(CheckMissedContacts(*world).missed == 0);
}

TEST_CASE("penetration is the overlap depth of the touching contacts")
{
    auto world = MakeWorld();
    AddCircle(*world, b2_staticBody, b2Vec2(0.0f, 0.0f), 0.5f);
    AddCircle(*world, b2_dynamicBody, b2Vec2(0.9f, 0.0f), 0.5f);
    CHECK(MeasurePenetration(*world).points == 0); // no contact yet
    // One velocity iteration, no position iteration, no time-of-impact pass (which would push the ball out):
    // the contact is created and evaluated; the ball moves by at most its solver velocity times the tiny
    // step.
    world->SetContinuousPhysics(false);
    world->Step(1e-6f, 1, 0);
    const auto p = MeasurePenetration(*world);
    CHECK(p.points == 1);
    CHECK(p.maxDepth == Approx(0.1).margin(1e-3));
    CHECK(p.sumDepth == Approx(p.maxDepth));
}

TEST_CASE("kinetic energy is m v^2 / 2 + I w^2 / 2 about the centre of mass")
{
    auto world = MakeWorld();
    AddCircle(*world, b2_staticBody, b2Vec2(0.0f, 0.0f), 0.5f); // static: no energy
    b2Body* ball = AddCircle(*world, b2_dynamicBody, b2Vec2(3.0f, 0.0f), 0.5f);
    ball->SetLinearVelocity(b2Vec2(3.0f, 4.0f));
    ball->SetAngularVelocity(2.0f);
    const double mass = ball->GetMass();
    const double inertia = ball->GetInertia(); // centred shape: about the centre of mass
    const double expectedBall = 0.5 * mass * 25.0 + 0.5 * inertia * 4.0;
    CHECK(KineticEnergy(*world) == Approx(expectedBall));

    // An off-centre shape: Box2D's GetInertia() is about the body origin, the energy needs it about the
    // centre.
    b2BodyDef bd;
    bd.type = b2_dynamicBody;
    bd.position.Set(10.0f, 0.0f);
    b2Body* offset = world->CreateBody(&bd);
    b2CircleShape circle;
    circle.m_radius = 0.5f;
    circle.m_p.Set(2.0f, 0.0f);
    offset->CreateFixture(&circle, 1.0f);
    offset->SetAngularVelocity(1.0f);
    const double centred = double(offset->GetInertia()) - double(offset->GetMass()) * 4.0;
    const double v2 =
        offset->GetLinearVelocity().LengthSquared(); // the centre moves when spinning about the origin
    CHECK(KineticEnergy(*world) == Approx(expectedBall + 0.5 * offset->GetMass() * v2 + 0.5 * centred * 1.0));
}
