// SPDX-License-Identifier: MIT
// b2World::QueryAABB and b2World::RayCast callbacks that do what games do from them: spawn debris, destroy other
// bodies, teleport, enable, disable and wake bodies, over many rounds and steps (quadphase build, validation on).
// The contract (b2BroadPhase::Query in quadphase's b2_broad_phase.h):
// - a fixture that existed before the call and whose body was not changed during it is reported (once, for the
//   single-child shapes used here) when its fat AABB overlaps the box, or, for a ray cast, when its shape is hit;
// - a fixture destroyed during the call is never reported after its destruction (stock Box2D hands back the dangling
//   fixture here);
// - fixtures created or moved during the call may or may not be reported.
// Under AddressSanitizer (scripts/sanitize.sh) this also checks that no callback makes the broadphase read freed
// memory. The validation at queued moves is here too: switching validation on with moves queued finds no mismatch.
#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <vector>

#include <catch2/catch.hpp>

#include "box2d/box2d.h"
#include "box2d_internal.h"
#include "quadphase/box2d.h"

namespace
{

// A world whose fixtures carry serial numbers (user data), so a report can be checked against what is alive
// without dereferencing anything the callback may have destroyed.
class Arena
{
public:
    explicit Arena(uint32_t seed) : m_rng(seed), m_world(b2Vec2(0.0f, -2.0f))
    {
        quadphase::SetValidation(m_world, true);
        b2BodyDef groundDef;
        b2Body* ground = m_world.CreateBody(&groundDef);
        b2PolygonShape floor;
        floor.SetAsBox(60.0f, 0.5f, b2Vec2(50.0f, -0.5f), 0.0f);
        AddFixture(ground, floor);
        for (int i = 0; i < 400; ++i)
        {
            Spawn(Uniform(0.0f, 100.0f), Uniform(0.5f, 60.0f));
        }
    }

    b2World& World() { return m_world; }
    std::mt19937& Rng() { return m_rng; }
    float Uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(m_rng); }
    bool Chance(double p) { return std::bernoulli_distribution(p)(m_rng); }

    b2Body* Spawn(float x, float y)
    {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(x, y);
        b2Body* body = m_world.CreateBody(&def);
        if (Chance(0.5))
        {
            b2CircleShape circle;
            circle.m_radius = Uniform(0.2f, 0.8f);
            AddFixture(body, circle);
        }
        else
        {
            b2PolygonShape box;
            box.SetAsBox(Uniform(0.2f, 0.8f), Uniform(0.2f, 0.8f));
            AddFixture(body, box);
        }
        m_bodies.push_back(body);
        return body;
    }

    void Destroy(b2Body* body)
    {
        for (b2Fixture* f = body->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            m_live.erase(Serial(f));
        }
        m_bodies.erase(std::find(m_bodies.begin(), m_bodies.end(), body));
        m_world.DestroyBody(body);
    }

    b2Body* AnyBody() { return m_bodies[size_t(m_rng() % m_bodies.size())]; }
    size_t BodyCount() const { return m_bodies.size(); }
    bool IsLive(uint64_t serial) const { return m_live.count(serial) != 0; }

    static uint64_t Serial(const b2Fixture* f)
    {
        return uint64_t(const_cast<b2Fixture*>(f)->GetUserData().pointer);
    }

    // Serials of the enabled fixtures whose fat AABB overlaps `box`, from the broadphase's own records.
    std::set<uint64_t> OverlappingFatAABB(const b2AABB& box)
    {
        std::set<uint64_t> out;
        const b2BroadPhase& bp = m_world.GetContactManager().m_broadPhase;
        for (b2Body* body : m_bodies)
        {
            if (!body->IsEnabled())
            {
                continue;
            }
            for (b2Fixture* f = body->GetFixtureList(); f != nullptr; f = f->GetNext())
            {
                if (b2TestOverlap(bp.GetFatAABB(ProxyIdOf(f)), box))
                {
                    out.insert(Serial(f));
                }
            }
        }
        return out;
    }

    // Serials of the enabled fixtures the segment hits (b2Fixture::RayCast, what b2World::RayCast reports).
    std::set<uint64_t> HitBy(const b2Vec2& p1, const b2Vec2& p2)
    {
        std::set<uint64_t> out;
        b2RayCastInput input;
        input.p1 = p1;
        input.p2 = p2;
        input.maxFraction = 1.0f;
        for (b2Body* body : m_bodies)
        {
            if (!body->IsEnabled())
            {
                continue;
            }
            for (b2Fixture* f = body->GetFixtureList(); f != nullptr; f = f->GetNext())
            {
                b2RayCastOutput output;
                if (f->RayCast(&output, input, 0))
                {
                    out.insert(Serial(f));
                }
            }
        }
        return out;
    }

private:
    void AddFixture(b2Body* body, const b2Shape& shape)
    {
        b2FixtureDef fd;
        fd.shape = &shape;
        fd.density = 1.0f;
        fd.userData.pointer = uintptr_t(++m_nextSerial);
        body->CreateFixture(&fd);
        m_live.insert(m_nextSerial);
    }

    // A fixture's proxy id, found in the broadphase's records (b2Fixture keeps it protected).
    int32 ProxyIdOf(b2Fixture* f)
    {
        const quadphase::QuadtreeBroadPhase& core = quadphase::GetQuadtree(m_world);
        core.ApplyQueuedMoves();
        const quadphase::ProxyPool& pool = core.GetPool();
        if (m_proxyOf.size() != size_t(pool.IdBound()) || m_proxyOfStale)
        {
            m_proxyOf.clear();
            for (quadphase::ProxyId id = 0; id < pool.IdBound(); ++id)
            {
                if (pool.IsLive(id))
                {
                    m_proxyOf[static_cast<b2FixtureProxy*>(pool.UserData(id))->fixture] = id;
                }
            }
            m_proxyOfStale = false;
        }
        return m_proxyOf.at(f);
    }

public:
    void ForgetProxyIds() { m_proxyOfStale = true; }

private:
    std::mt19937 m_rng;
    b2World m_world;
    std::vector<b2Body*> m_bodies;
    std::set<uint64_t> m_live;
    uint64_t m_nextSerial = 0;
    std::map<const b2Fixture*, int32> m_proxyOf;
    bool m_proxyOfStale = true;
};

// What one re-entrant call saw and did.
struct Call
{
    Arena* arena = nullptr;
    b2Vec2 near{0.0f, 0.0f};
    std::vector<uint64_t> reported;
    std::set<uint64_t> touched; // fixtures of bodies changed during the call: no promise about them
    int deadReports = 0;
    int actions = 0;

    void Touch(b2Body* body)
    {
        for (b2Fixture* f = body->GetFixtureList(); f != nullptr; f = f->GetNext())
        {
            touched.insert(Arena::Serial(f));
        }
    }

    void Report(b2Fixture* fixture)
    {
        const uint64_t serial = Arena::Serial(fixture);
        reported.push_back(serial);
        deadReports += arena->IsLive(serial) ? 0 : 1;
        if (actions < 12 && arena->Chance(0.4))
        {
            Act(fixture->GetBody());
        }
    }

    // One thing a game does from a callback; never destroys the body being reported.
    void Act(b2Body* reportedBody)
    {
        Arena& a = *arena;
        ++actions;
        const int roll = int(a.Rng()() % 100);
        if (roll < 25)
        {
            Touch(a.Spawn(near.x + a.Uniform(-3.0f, 3.0f), near.y + a.Uniform(-3.0f, 3.0f))); // debris
        }
        else if (roll < 45 && a.BodyCount() > 100)
        {
            b2Body* victim = a.AnyBody();
            if (victim != reportedBody)
            {
                Touch(victim);
                a.Destroy(victim);
            }
        }
        else if (roll < 65)
        {
            b2Body* body = a.AnyBody();
            Touch(body);
            body->SetTransform(b2Vec2(a.Uniform(0.0f, 100.0f), a.Uniform(0.5f, 60.0f)),
                               a.Uniform(0.0f, 3.0f));
        }
        else if (roll < 80)
        {
            b2Body* body = a.AnyBody();
            Touch(body);
            body->SetEnabled(!body->IsEnabled());
        }
        else
        {
            b2Body* body = a.AnyBody();
            Touch(body);
            body->SetAwake(!body->IsAwake());
        }
        a.ForgetProxyIds();
    }
};

struct QueryCallback : b2QueryCallback
{
    Call* call = nullptr;
    bool ReportFixture(b2Fixture* fixture) override
    {
        call->Report(fixture);
        return true;
    }
};

struct RayCallback : b2RayCastCallback
{
    Call* call = nullptr;
    float ReportFixture(b2Fixture* fixture, const b2Vec2&, const b2Vec2&, float) override
    {
        call->Report(fixture);
        return 1.0f; // all hits: the ray keeps its length
    }
};

void CheckCall(const Call& call, const std::set<uint64_t>& expected)
{
    REQUIRE(call.deadReports == 0);
    std::vector<uint64_t> sorted = call.reported;
    std::sort(sorted.begin(), sorted.end());
    REQUIRE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    for (uint64_t serial : expected)
    {
        if (call.touched.count(serial) == 0)
        {
            INFO("fixture " << serial << " existed, was not touched, and was not reported");
            REQUIRE(std::binary_search(sorted.begin(), sorted.end(), serial));
        }
    }
}

} // namespace

TEST_CASE("QueryAABB and RayCast callbacks spawn, destroy, teleport, enable and wake bodies",
          "[reentrant][validation]")
{
    Arena arena(20261125u);
    b2World& world = arena.World();
    int actions = 0;
    int reports = 0;
    for (int round = 0; round < 120; ++round)
    {
        INFO("round " << round);
        for (int q = 0; q < 4; ++q)
        {
            const b2Vec2 c(arena.Uniform(0.0f, 100.0f), arena.Uniform(0.0f, 60.0f));
            const float half = arena.Uniform(1.0f, 15.0f);
            b2AABB box;
            box.lowerBound = c - b2Vec2(half, half);
            box.upperBound = c + b2Vec2(half, half);
            const std::set<uint64_t> expected = arena.OverlappingFatAABB(box);
            Call call;
            call.arena = &arena;
            call.near = c;
            QueryCallback callback;
            callback.call = &call;
            world.QueryAABB(&callback, box);
            CheckCall(call, expected);
            actions += call.actions;
            reports += int(call.reported.size());
        }
        for (int r = 0; r < 4; ++r)
        {
            // Long and diagonal rays among short ones.
            const b2Vec2 p1(arena.Uniform(-5.0f, 105.0f), arena.Uniform(-5.0f, 65.0f));
            const b2Vec2 p2 = r % 2 == 0
                                  ? b2Vec2(arena.Uniform(-5.0f, 105.0f), arena.Uniform(-5.0f, 65.0f))
                                  : p1 + b2Vec2(arena.Uniform(-8.0f, 8.0f), arena.Uniform(-8.0f, 8.0f));
            if (b2DistanceSquared(p1, p2) < 1e-6f)
            {
                continue;
            }
            const std::set<uint64_t> expected = arena.HitBy(p1, p2);
            Call call;
            call.arena = &arena;
            call.near = 0.5f * (p1 + p2);
            RayCallback callback;
            callback.call = &call;
            world.RayCast(&callback, p1, p2);
            CheckCall(call, expected);
            actions += call.actions;
            reports += int(call.reported.size());
        }
        for (int s = 0; s < 3; ++s)
        {
            world.Step(1.0f / 60.0f, 8, 3);
        }
    }
    CHECK(actions > 1000);
    CHECK(reports > 3000);
    const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
    INFO(report.firstMismatch);
    CHECK(report.checks > 300);
    CHECK(report.mismatches == 0);
    CHECK(quadphase::GetQuadtree(world).Validate() == "");
}

TEST_CASE("Validation switched on while moves are queued finds no mismatch", "[validation]")
{
    // SetTransform queues the moves; the validator must start from the fat AABBs they define (it used to copy
    // the stored ones and report "1 extra pair" for correct pairs).
    for (int teleported = 1; teleported <= 50; teleported += 7)
    {
        b2World world(b2Vec2(0.0f, -10.0f));
        std::vector<b2Body*> bodies;
        for (int i = 0; i < 60; ++i)
        {
            b2BodyDef def;
            def.type = b2_dynamicBody;
            def.position.Set(float(i % 10) * 3.0f, float(i / 10) * 3.0f + 1.0f);
            b2Body* body = world.CreateBody(&def);
            b2PolygonShape box;
            box.SetAsBox(0.5f, 0.5f);
            body->CreateFixture(&box, 1.0f);
            bodies.push_back(body);
        }
        for (int s = 0; s < 5; ++s)
        {
            world.Step(1.0f / 60.0f, 8, 3);
        }
        // Onto one another: new pairs for the next step.
        for (int i = 0; i < teleported; ++i)
        {
            bodies[size_t(i)]->SetTransform(bodies[size_t(59 - i)]->GetPosition() + b2Vec2(0.3f, 0.2f), 0.0f);
        }
        REQUIRE(quadphase::GetQuadtree(world).QueuedMoveCount() > 0);
        quadphase::SetValidation(world, true);
        for (int s = 0; s < 10; ++s)
        {
            world.Step(1.0f / 60.0f, 8, 3);
        }
        const quadphase::ValidationReport report = quadphase::GetValidationReport(world);
        INFO("teleported " << teleported << ": " << report.firstMismatch);
        CHECK(report.checks >= 10);
        CHECK(report.mismatches == 0);
    }
}
