// SPDX-License-Identifier: MIT
// Bad input at the Box2D level (quadphase build): a body whose AABB becomes NaN or infinite, and b2BroadPhase
// given unknown or destroyed ids, zero-size and inverted AABBs. The error hook gets a clear report, the call
// has defined behaviour (this is a release build, where the default handler does not abort), and every other
// proxy keeps exactly its pairs. The core-level cases (every call, every kind of bad box, against the brute
// force) are in tests/core/test_bad_input.cpp; the default handler's abort in debug builds in
// debug_error_hook_main.cpp.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "../core/test_support.h"
#include "box2d/box2d.h"
#include "box2d_internal.h"
#include "quadphase/box2d.h"
#include "quadphase/error.h"

namespace
{

using qptest::ErrorCounter;

/// A world with two piles of boxes, and one extra body ("victim") resting apart from them.
struct Piles
{
    std::unique_ptr<b2World> world = std::make_unique<b2World>(b2Vec2(0.0f, -10.0f));
    std::vector<b2Body*> others;
    b2Body* victim = nullptr;

    Piles()
    {
        b2BodyDef groundDef;
        b2Body* ground = world->CreateBody(&groundDef);
        b2PolygonShape groundShape;
        groundShape.SetAsBox(40.0f, 0.5f, b2Vec2(0.0f, -0.5f), 0.0f);
        ground->CreateFixture(&groundShape, 0.0f);
        for (int i = 0; i < 60; ++i)
        {
            others.push_back(
                Box(b2Vec2((i % 2 == 0 ? -8.0f : 8.0f) + 0.3f * float(i % 5), 0.5f + 1.1f * float(i / 2))));
        }
        victim = Box(b2Vec2(20.0f, 0.5f));
    }

    b2Body* Box(b2Vec2 p)
    {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position = p;
        b2Body* body = world->CreateBody(&def);
        b2PolygonShape shape;
        shape.SetAsBox(0.5f, 0.5f);
        body->CreateFixture(&shape, 1.0f);
        return body;
    }

    /// Index pairs (into `others`) of the touching contacts between two of `others`.
    std::set<std::pair<int, int>> OthersTouching() const
    {
        std::set<std::pair<int, int>> out;
        for (const b2Contact* c = world->GetContactList(); c != nullptr; c = c->GetNext())
        {
            const auto a = std::find(others.begin(), others.end(), c->GetFixtureA()->GetBody());
            const auto b = std::find(others.begin(), others.end(), c->GetFixtureB()->GetBody());
            if (c->IsTouching() && a != others.end() && b != others.end())
            {
                const int ia = int(a - others.begin());
                const int ib = int(b - others.begin());
                out.insert({std::min(ia, ib), std::max(ia, ib)});
            }
        }
        return out;
    }
};

bool SameBits(float a, float b)
{
    return std::memcmp(&a, &b, sizeof(float)) == 0;
}

/// Records UpdatePairs' pairs (b2BroadPhase::UpdatePairs' callback interface).
struct PairLog
{
    std::set<std::pair<int32, int32>> pairs;
    void AddPair(void* a, void* b)
    {
        const int32 ia = int32(reinterpret_cast<intptr_t>(a));
        const int32 ib = int32(reinterpret_cast<intptr_t>(b));
        pairs.insert({std::min(ia, ib), std::max(ia, ib)});
    }
};

b2AABB Aabb(float x0, float y0, float x1, float y1)
{
    b2AABB a;
    a.lowerBound.Set(x0, y0);
    a.upperBound.Set(x1, y1);
    return a;
}

} // namespace

TEST_CASE("a body teleported to NaN or infinity: reported, and the other bodies are unaffected",
          "[bad_input]")
{
    const float kNaN = std::numeric_limits<float>::quiet_NaN();
    const float kInf = std::numeric_limits<float>::infinity();
    for (float bad : {kNaN, kInf, -kInf})
    {
        INFO("bad coordinate " << bad);
        ErrorCounter errors;
        // Twin worlds: in `broken` the victim is teleported to a non-finite position, in `twin` to a sane
        // place far from everything. The other bodies must move bit for bit the same in both.
        Piles broken, twin;
        for (int step = 0; step < 150; ++step)
        {
            if (step == 30)
            {
                errors.Reset();
                broken.victim->SetTransform(b2Vec2(bad, 0.5f), 0.0f);
                REQUIRE(errors.Count(quadphase::ErrorCode::NonFiniteBox) == 1);
                REQUIRE(errors.LastMessage().find("MoveProxy") != std::string::npos);
                twin.victim->SetTransform(b2Vec2(30.0f, 0.5f), 0.0f);
                REQUIRE(errors.Total() == 1); // the sane teleport reports nothing
            }
            broken.world->Step(1.0f / 60.0f, 8, 3);
            twin.world->Step(1.0f / 60.0f, 8, 3);
        }
        // the non-finite box was reported once (the body moves with it for 120 steps: once per proxy, not once per
        // step), and only that kind of error
        CHECK(errors.Count(quadphase::ErrorCode::NonFiniteBox) == 1);
        CHECK(errors.Total() == errors.Count(quadphase::ErrorCode::NonFiniteBox));
        // the victim pairs with nothing, and the others have exactly the same contacts and positions
        for (const b2ContactEdge* e = broken.victim->GetContactList(); e != nullptr; e = e->next)
        {
            FAIL("the non-finite body has a contact");
        }
        CHECK(broken.OthersTouching() == twin.OthersTouching());
        CHECK(broken.OthersTouching().size() > 40);
        for (size_t i = 0; i < broken.others.size(); ++i)
        {
            const b2Vec2 p = broken.others[i]->GetPosition();
            const b2Vec2 q = twin.others[i]->GetPosition();
            INFO("body " << i);
            CHECK((SameBits(p.x, q.x) && SameBits(p.y, q.y)));
        }
        CHECK(broken.world->GetProxyCount() == twin.world->GetProxyCount());
        const std::string problem = quadphase::GetQuadtree(*broken.world).Validate();
        INFO(problem);
        CHECK(problem.empty());

        // The victim comes back to a sane place: it pairs again.
        errors.Reset();
        broken.victim->SetTransform(b2Vec2(-8.0f, 0.5f), 0.0f);
        broken.victim->SetLinearVelocity(b2Vec2(0.0f, 0.0f));
        broken.world->Step(1.0f / 60.0f, 8, 3);
        CHECK(errors.Total() == 0);
        CHECK(broken.victim->GetContactList() != nullptr);
    }
}

TEST_CASE("b2BroadPhase: unknown and destroyed ids are reported, validation stays exact", "[bad_input]")
{
    ErrorCounter errors;
    b2BroadPhase bp;
    quadphase::SetValidation(bp, true);
    std::vector<int32> ids;
    for (int i = 0; i < 50; ++i)
    {
        const float x = float(i % 10) * 0.8f;
        const float y = float(i / 10) * 0.8f;
        ids.push_back(bp.CreateProxy(Aabb(x, y, x + 1.0f, y + 1.0f), reinterpret_cast<void*>(intptr_t(i))));
    }
    PairLog first;
    bp.UpdatePairs(&first);
    REQUIRE(errors.Total() == 0);
    REQUIRE(first.pairs.size() > 50);

    bp.DestroyProxy(ids[7]);
    const int32 unknown[] = {ids[7], -1, -12345, 50, 1 << 30};
    int expected = 0;
    for (int32 id : unknown)
    {
        INFO("id " << id);
        bp.DestroyProxy(id); // a double destroy must not free the id twice
        REQUIRE(errors.Count(quadphase::ErrorCode::UnknownProxy) == ++expected);
        bp.MoveProxy(id, Aabb(0.0f, 0.0f, 1.0f, 1.0f), b2Vec2(0.5f, 0.0f));
        REQUIRE(errors.Count(quadphase::ErrorCode::UnknownProxy) == ++expected);
        bp.TouchProxy(id);
        REQUIRE(errors.Count(quadphase::ErrorCode::UnknownProxy) == ++expected);
        REQUIRE(bp.GetUserData(id) == nullptr);
        REQUIRE(errors.Total() == expected);
    }
    REQUIRE(bp.GetProxyCount() == 49);
    // the next two proxies get two distinct ids: 7 (freed once) and a fresh one
    const int32 a = bp.CreateProxy(Aabb(0.1f, 0.1f, 0.4f, 0.4f), reinterpret_cast<void*>(intptr_t(100)));
    const int32 b = bp.CreateProxy(Aabb(0.2f, 0.2f, 0.5f, 0.5f), reinterpret_cast<void*>(intptr_t(101)));
    CHECK(a == ids[7]);
    CHECK(b != a);
    CHECK(b == 50);
    PairLog second;
    bp.UpdatePairs(&second);
    CHECK(second.pairs.count({0, 100}) == 1);
    CHECK(second.pairs.count({100, 101}) == 1);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(bp);
    INFO(report.firstMismatch);
    CHECK(report.mismatches == 0);
    CHECK(report.checks == 2);
    CHECK(errors.Total() == expected); // nothing but the unknown ids
}

TEST_CASE("b2BroadPhase: zero-size AABBs pair exactly and inverted ones are reported and pair with nothing",
          "[bad_input]")
{
    ErrorCounter errors;
    b2BroadPhase bp;
    quadphase::SetValidation(bp, true);
    // zero-size: points, and zero-width and zero-height segments, some exactly on others' borders
    const b2AABB zero[] = {Aabb(0.0f, 0.0f, 0.0f, 0.0f),  Aabb(0.0f, 0.0f, 0.0f, 0.0f),
                           Aabb(1.0f, 0.0f, 1.0f, 2.0f),  Aabb(0.0f, 1.0f, 3.0f, 1.0f),
                           Aabb(5.0f, 5.0f, 5.0f, 5.0f),  Aabb(5.2f, 5.0f, 5.2f, 5.0f),
                           Aabb(-3.0f, 0.0f, -3.0f, 0.0f)};
    int user = 0;
    for (const b2AABB& box : zero)
    {
        bp.CreateProxy(box, reinterpret_cast<void*>(intptr_t(user++)));
    }
    PairLog log;
    bp.UpdatePairs(&log);
    CHECK(errors.Total() == 0);
    CHECK(log.pairs.count({0, 1}) == 1); // two points at the same place
    CHECK(log.pairs.count({4, 5}) == 1); // 0.2 apart, within the 0.1 fat margins
    CHECK(log.pairs.count({0, 6}) == 0); // 3 apart
    // move the zero-size proxies around with zero-size boxes: still exact
    for (int32 id = 0; id < 7; ++id)
    {
        const float d = 0.37f * float(id + 1);
        const b2AABB& fat = bp.GetFatAABB(id);
        const float cx = 0.5f * (fat.lowerBound.x + fat.upperBound.x) + d;
        bp.MoveProxy(id, Aabb(cx, 0.0f, cx, 0.0f), b2Vec2(d, 0.0f));
    }
    PairLog moved;
    bp.UpdatePairs(&moved);
    CHECK(errors.Total() == 0);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(bp);
    INFO(report.firstMismatch);
    CHECK(report.mismatches == 0);
    CHECK(report.checks == 2);
    // the shadow b2DynamicTree has no defined behaviour for inverted boxes
    quadphase::SetValidation(bp, false);

    // inverted: reported; it pairs with nothing, and the others keep their pairs
    errors.Reset();
    const int32 inv = bp.CreateProxy(Aabb(2.0f, 2.0f, -2.0f, -2.0f), reinterpret_cast<void*>(intptr_t(99)));
    CHECK(errors.Count(quadphase::ErrorCode::InvertedBox) == 1);
    CHECK(errors.LastMessage().find("CreateProxy") != std::string::npos);
    for (int32 id = 0; id < 7; ++id)
    {
        bp.TouchProxy(id);
    }
    PairLog after;
    bp.UpdatePairs(&after);
    std::set<std::pair<int32, int32>> withoutInverted;
    for (const auto& p : after.pairs)
    {
        if (p.first != 99 && p.second != 99)
        {
            withoutInverted.insert(p);
        }
    }
    // the others' pairs are the pairs of all their current fat boxes, computed here directly
    std::set<std::pair<int32, int32>> expected;
    for (int32 i = 0; i < 7; ++i)
    {
        for (int32 j = i + 1; j < 7; ++j)
        {
            if (b2TestOverlap(bp.GetFatAABB(i), bp.GetFatAABB(j)))
            {
                expected.insert({i, j});
            }
        }
    }
    CHECK(withoutInverted == expected);
    CHECK(errors.Total() == 1);
    (void)inv;
}
