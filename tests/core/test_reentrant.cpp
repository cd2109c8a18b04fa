// SPDX-License-Identifier: MIT
// Query and RayCast callbacks that call back into the broadphase (a game spawning, destroying and teleporting
// bodies from b2World::QueryAABB and RayCast callbacks), queries after a mass teleport, and GetStats beside
// concurrent const calls. The contract is on QuadtreeBroadPhase::Query:
// - a proxy that existed before the call and is neither destroyed nor moved during it is reported, once;
// - a proxy destroyed during the call is never reported after its destruction;
// - proxies created or moved during the call may or may not be reported;
// - no id is reported twice in one call.
// Under AddressSanitizer (scripts/sanitize.sh) these also check that no callback makes the walk read freed
// memory.
#include <algorithm>
#include <atomic>
#include <set>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "brute_force_broad_phase.h"
#include "quadtree_broad_phase.h"
#include "ray.h"
#include "test_support.h"

using namespace quadphase;
using namespace qptest;

namespace
{

Box SmallBoxAt(float x, float y, float half)
{
    return Box{x - half, y - half, x + half, y + half};
}

// A broadphase plus what the test knows of it: which ids are live and whose boxes changed during a call.
struct World
{
    explicit World(uint32_t seed, const Config& config = Config{}) : rng(seed), qt(FatPolicy{}, config) {}

    ProxyId Create(const Box& b)
    {
        const ProxyId id = qt.CreateProxy(b, nullptr);
        live.insert(id);
        liveList.push_back(id);
        return id;
    }

    void Destroy(ProxyId id)
    {
        qt.DestroyProxy(id);
        live.erase(id);
        liveList.erase(std::find(liveList.begin(), liveList.end(), id));
    }

    Box RandomBox(float world)
    {
        return SmallBoxAt(Uniform(rng, 0.0f, world), Uniform(rng, 0.0f, world), Uniform(rng, 0.05f, 1.0f));
    }

    // Creates `count` random boxes over [0, world]^2, then finds their pairs, so that nothing is buffered.
    void Populate(int count, float world)
    {
        for (int i = 0; i < count; ++i)
        {
            Create(RandomBox(world));
        }
        std::vector<Pair> pairs;
        qt.FindPairs(pairs);
    }

    ProxyId AnyLive() { return liveList[size_t(UniformInt(rng, 0, int(liveList.size()) - 1))]; }

    Rng rng;
    QuadtreeBroadPhase qt;
    std::set<ProxyId> live;
    std::vector<ProxyId> liveList; // the same ids, for picking one at random in O(1)
};

// What one re-entrant call saw, and what its callbacks did.
struct CallRecord
{
    World* world = nullptr;
    std::vector<ProxyId> reported;
    std::set<ProxyId> touched; // destroyed or moved during the call: no promise about them
    int deadReported = 0;      // reports of ids that were not live at the time
    int actions = 0;
    float worldSize = 100.0f;
    Box near{}; // where created proxies go, so that some of them overlap the query

    // One random call back into the broadphase.
    void Act()
    {
        World& w = *world;
        const int roll = UniformInt(w.rng, 0, 99);
        ++actions;
        if (roll < 30)
        {
            // spawn debris, half of it where the query looks; many at once sometimes (a re-tune on doubling)
            // (the doubling is capped: unchecked, a few doublings per call would grow the world without
            // bound)
            const bool doubling = w.live.size() < 1500 && Chance(w.rng, 0.05);
            const int n = doubling ? int(w.live.size()) + 10 : UniformInt(w.rng, 1, 2);
            for (int i = 0; i < n; ++i)
            {
                const Box b = Chance(w.rng, 0.5) ? SmallBoxAt(Uniform(w.rng, near.minX, near.maxX),
                                                              Uniform(w.rng, near.minY, near.maxY), 0.3f)
                                                 : w.RandomBox(worldSize);
                touched.insert(w.Create(b));
            }
        }
        else if (roll < 60 && w.live.size() > 20)
        {
            const ProxyId victim = w.AnyLive();
            w.Destroy(victim);
            touched.insert(victim);
        }
        else if (roll < 70)
        {
            const ProxyId id = w.AnyLive();
            w.qt.QueueMove(id, w.RandomBox(worldSize), Vec2{1.0f, -1.0f}); // what b2Body::SetTransform does
            touched.insert(id);
        }
        else if (roll < 80)
        {
            const ProxyId id = w.AnyLive();
            w.qt.MoveProxy(id, w.RandomBox(worldSize), Vec2{0.0f, 0.0f});
            touched.insert(id);
        }
        else if (roll < 90)
        {
            // a nested query: applies the queue and updates stale entries while the outer call is under way
            IdCollector inner;
            w.qt.Query(w.RandomBox(worldSize), &IdCollector::Callback, &inner);
        }
        // else: nothing
    }

    void Record(ProxyId id)
    {
        reported.push_back(id);
        deadReported += world->live.count(id) == 0 ? 1 : 0;
    }
};

// What both callbacks do with a report: record it and, half the time, call back into the broadphase.
void OnReport(void* context, ProxyId id)
{
    CallRecord& call = *static_cast<CallRecord*>(context);
    call.Record(id);
    // Up to 40 actions a call: enough to change the world under the walk many times, without letting the
    // world grow with the number of reports.
    if (call.actions < 40 && Chance(call.world->rng, 0.5))
    {
        call.Act();
    }
}

bool QueryCallback(void* context, ProxyId id)
{
    OnReport(context, id);
    return true;
}

float RayCallback(void* context, const RayInput&, ProxyId id)
{
    OnReport(context, id);
    return -1.0f; // all hits, no clipping
}

// The proxies that existed before the call, were not touched during it, and must therefore have been
// reported.
void CheckUntouchedReported(const CallRecord& call, const std::vector<ProxyId>& expectedBefore)
{
    std::set<ProxyId> reported(call.reported.begin(), call.reported.end());
    for (ProxyId id : expectedBefore)
    {
        if (call.touched.count(id) == 0)
        {
            INFO("proxy " << id << " existed, overlapped, was not touched, and was not reported");
            REQUIRE(reported.count(id) == 1);
        }
    }
}

void CheckNoRepeats(const CallRecord& call)
{
    std::vector<ProxyId> sorted = call.reported;
    std::sort(sorted.begin(), sorted.end());
    REQUIRE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
}

// The live proxies whose fat boxes pass `test`, in id order.
template <typename Test>
std::vector<ProxyId> LiveWhere(const World& w, Test test)
{
    std::vector<ProxyId> ids;
    for (ProxyId id : w.live)
    {
        if (test(w.qt.GetFatBox(id)))
        {
            ids.push_back(id);
        }
    }
    return ids;
}

// One re-entrant call, made by run(call) with `call` as the callbacks' context, creating near `near`: checks
// what it reported against `before` (the live proxies it must report unless touched); returns its actions.
template <typename Run>
int CheckedCall(World& w, float size, const Box& near, const std::vector<ProxyId>& before, Run run)
{
    CallRecord call;
    call.world = &w;
    call.worldSize = size;
    call.near = near;
    run(call);
    REQUIRE(call.deadReported == 0);
    CheckNoRepeats(call);
    CheckUntouchedReported(call, before);
    return call.actions;
}

} // namespace

TEST_CASE("Query callbacks may create, destroy and move proxies", "[query][reentrant]")
{
    const float size = 100.0f;
    World w(4242u);
    w.Populate(300, size);
    std::vector<Pair> pairs;
    int actions = 0;
    for (int round = 0; round < 400; ++round)
    {
        const float cx = Uniform(w.rng, 0.0f, size), cy = Uniform(w.rng, 0.0f, size);
        const float half = Uniform(w.rng, 2.0f, 30.0f);
        const Box q{cx - half, cy - half, cx + half, cy + half};
        const std::vector<ProxyId> before = LiveWhere(w, [&](const Box& fat) { return Overlaps(fat, q); });
        INFO("round " << round);
        actions +=
            CheckedCall(w, size, q, before, [&](CallRecord& call) { w.qt.Query(q, &QueryCallback, &call); });
        if (round % 7 == 0)
        {
            w.qt.FindPairs(pairs);
            REQUIRE(w.qt.Validate() == "");
        }
    }
    REQUIRE(actions > 1000);
    REQUIRE(w.qt.Validate() == "");
}

TEST_CASE("RayCast callbacks may create, destroy and move proxies", "[raycast][reentrant]")
{
    const float size = 200.0f;
    Config config;
    World w(777u, config);
    w.Populate(2000, size);
    std::vector<Pair> pairs;
    int actions = 0;
    for (int round = 0; round < 300; ++round)
    {
        RayInput in{};
        in.p1 = Vec2{Uniform(w.rng, -10.0f, size + 10.0f), Uniform(w.rng, -10.0f, size + 10.0f)};
        in.p2 = Vec2{Uniform(w.rng, -10.0f, size + 10.0f), Uniform(w.rng, -10.0f, size + 10.0f)};
        in.maxFraction = 1.0f;
        const SegmentTest segment(in);
        const std::vector<ProxyId> before =
            LiveWhere(w, [&](const Box& fat) { return segment.MayCross(fat); });
        INFO("round " << round);
        actions += CheckedCall(w, size, segment.Bounds(), before,
                               [&](CallRecord& call) { w.qt.RayCast(in, &RayCallback, &call); });
        if (round % 5 == 0)
        {
            w.qt.FindPairs(pairs);
            REQUIRE(w.qt.Validate() == "");
        }
    }
    REQUIRE(actions > 1000);
}

// Found by the Box2D-level fuzzer (tests/fuzz/box2d_fuzz.cpp, regression input
// tests/fuzz/regressions/box2d/reentrant-queued-move-reported-where-it-was): b2BroadPhase::MoveProxy queues
// the move (QueueMove), which changed no fat box before the queue was applied, so a proxy a callback moved
// away was still reported where it had been.
TEST_CASE("A proxy a callback moves through QueueMove is reported only where it now is",
          "[query][raycast][reentrant]")
{
    QuadtreeBroadPhase qt;
    const ProxyId first = qt.CreateProxy(Box{0.0f, 0.0f, 1.0f, 1.0f}, nullptr);
    const ProxyId second = qt.CreateProxy(Box{2.0f, 0.0f, 3.0f, 1.0f}, nullptr);
    std::vector<Pair> pairs;
    qt.FindPairs(pairs);
    const Box away{50.0f, 50.0f, 51.0f, 51.0f};
    struct Mover
    {
        QuadtreeBroadPhase* qt;
        ProxyId reported[2] = {-1, -1};
        int count = 0;
        Box to;
        void Report(ProxyId id)
        {
            reported[count++] = id;
            if (count == 1)
            {
                // move the other one away; its QueueMove is not applied yet
                const ProxyId other = id == 0 ? 1 : 0;
                qt->QueueMove(other, to, Vec2{0.0f, 0.0f});
            }
        }
        static bool Query(void* context, ProxyId id)
        {
            static_cast<Mover*>(context)->Report(id);
            return true;
        }
        static float Ray(void* context, const RayInput&, ProxyId id)
        {
            static_cast<Mover*>(context)->Report(id);
            return -1.0f;
        }
    };
    SECTION("Query")
    {
        Mover m{&qt, {-1, -1}, 0, away};
        qt.Query(Box{-1.0f, -1.0f, 4.0f, 2.0f}, &Mover::Query, &m);
        CHECK(m.count == 1); // was 2: the moved proxy reported at its old box
    }
    SECTION("RayCast")
    {
        Mover m{&qt, {-1, -1}, 0, away};
        qt.RayCast(RayInput{{-1.0f, 0.5f}, {4.0f, 0.5f}, 1.0f}, &Mover::Ray, &m);
        CHECK(m.count == 1);
    }
    CHECK(Overlaps(qt.GetFatBox(first), away) != Overlaps(qt.GetFatBox(second), away));
    REQUIRE(qt.Validate() == "");
}

// Found by the Box2D-level fuzzer (regression input tests/fuzz/regressions/box2d/
// reentrant-ray-moved-proxy-in-a-later-batch): RayCast collects a batch of entries per level (or row) after
// the previous batch's callbacks, and an entry a callback's move left stale still held the old box, which the
// walk trusted when nothing changed between that collection and the report.
TEST_CASE("RayCast: a proxy a callback moves, met in a later batch, is reported only where it now is",
          "[raycast][reentrant]")
{
    for (const bool queued : {false, true})
    {
        INFO((queued ? "QueueMove" : "MoveProxy"));
        Config config;
        config.depth = 4;
        config.autoBounds = false;
        config.bounds = Box{-64.0f, -64.0f, 64.0f, 64.0f};
        QuadtreeBroadPhase qt(FatPolicy{}, config);
        const ProxyId big = qt.CreateProxy(Box{-40.0f, -10.0f, -20.0f, 10.0f}, nullptr); // a coarse level
        const ProxyId small = qt.CreateProxy(Box{20.0f, -0.5f, 21.0f, 0.5f}, nullptr);   // the finest level
        std::vector<Pair> pairs;
        qt.FindPairs(pairs);
        REQUIRE(qt.GetPyramid().Depth() == 4);
        struct Mover
        {
            QuadtreeBroadPhase* qt;
            ProxyId small;
            bool queued;
            std::vector<ProxyId> reported;
            static float Ray(void* context, const RayInput&, ProxyId id)
            {
                auto* self = static_cast<Mover*>(context);
                self->reported.push_back(id);
                if (self->reported.size() == 1 && id != self->small)
                {
                    const Box away{20.0f, 40.0f, 21.0f, 41.0f}; // off the ray
                    if (self->queued)
                    {
                        self->qt->QueueMove(self->small, away, Vec2{0.0f, 0.0f});
                    }
                    else
                    {
                        self->qt->MoveProxy(self->small, away, Vec2{0.0f, 0.0f});
                    }
                }
                return -1.0f;
            }
        };
        Mover m{&qt, small, queued, {}};
        qt.RayCast(RayInput{{-60.0f, 0.0f}, {60.0f, 0.0f}, 1.0f}, &Mover::Ray, &m);
        REQUIRE(!m.reported.empty());
        CHECK(m.reported.front() == big); // the coarse level's batch comes first
        CHECK(m.reported.size() == 1);    // was 2: the small proxy reported at its old box
        REQUIRE(qt.Validate() == "");
    }
}

TEST_CASE("A callback that rebuilds the pyramid mid-ray: the walk starts again and reports no id twice",
          "[raycast][reentrant]")
{
    World w(99u);
    w.Populate(500, 100.0f);
    const int64_t rebuildsBefore = w.qt.GetStats().rebuilds;
    RayInput in{{0.0f, 0.0f}, {100.0f, 100.0f}, 1.0f};
    const SegmentTest segment(in);
    const std::vector<ProxyId> before = LiveWhere(w, [&](const Box& fat) { return segment.MayCross(fat); });
    REQUIRE(before.size() > 10);
    struct Rebuilder
    {
        World* w;
        std::vector<ProxyId> reported;
        std::set<ProxyId> created;
        int calls = 0;
        static float Callback(void* context, const RayInput&, ProxyId id)
        {
            Rebuilder& self = *static_cast<Rebuilder*>(context);
            self.reported.push_back(id);
            if (++self.calls == 3)
            {
                // doubling the proxy count re-tunes, i.e. rebuilds, the pyramid
                const int n = int(self.w->live.size()) + 50;
                for (int i = 0; i < n; ++i)
                {
                    self.created.insert(self.w->Create(self.w->RandomBox(300.0f)));
                }
            }
            return -1.0f;
        }
    } rebuilder{&w, {}, {}, 0};
    w.qt.RayCast(in, &Rebuilder::Callback, &rebuilder);
    REQUIRE(w.qt.GetStats().rebuilds > rebuildsBefore);
    std::vector<ProxyId> sorted = rebuilder.reported;
    std::sort(sorted.begin(), sorted.end());
    REQUIRE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
    for (ProxyId id : before)
    {
        REQUIRE(std::binary_search(sorted.begin(), sorted.end(), id));
    }
}

TEST_CASE("Queries after a mass teleport bring the entries up to date once instead of scanning the queue",
          "[query][cheap]")
{
    const float size = 500.0f;
    World w(2024u);
    BruteForceBroadPhase bf;
    std::vector<ProxyId> ids;
    for (int i = 0; i < 5000; ++i)
    {
        const Box b = w.RandomBox(size);
        ids.push_back(w.Create(b));
        REQUIRE(bf.CreateProxy(b, nullptr) == ids.back());
    }
    std::vector<Pair> a, b;
    w.qt.FindPairs(a);
    bf.FindPairs(b);
    // Respawn the level: every body teleported (Box2D's SetTransform queues a move per fixture).
    for (ProxyId id : ids)
    {
        const Box to = w.RandomBox(size);
        w.qt.QueueMove(id, to, Vec2{0.0f, 0.0f});
        bf.MoveProxy(id, to, Vec2{0.0f, 0.0f});
    }
    const int64_t reinsertsBefore = w.qt.GetStats().reinserts;
    // The first query after the teleport re-places the entries that changed cell (the work the next FindPairs
    // would do), so that this query and the ones after it read only the cells near them.
    for (int i = 0; i < 100; ++i)
    {
        const Box q = SmallBoxAt(Uniform(w.rng, 0.0f, size), Uniform(w.rng, 0.0f, size), 5.0f);
        IdCollector x, y;
        w.qt.Query(q, &IdCollector::Callback, &x);
        bf.Query(q, &IdCollector::Callback, &y);
        REQUIRE(x.SortedIds() == y.SortedIds());
        if (i == 0)
        {
            REQUIRE(w.qt.GetStats().reinserts > reinsertsBefore + 1000);
        }
    }
    REQUIRE(w.qt.Validate() == "");
    // and the pairs of the next step are the stock ones
    a.clear();
    b.clear();
    w.qt.FindPairs(a);
    bf.FindPairs(b);
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    REQUIRE(a == b);
}

TEST_CASE("GetStats beside concurrent const calls that apply queued moves", "[parallel][stats][concurrent]")
{
    // Run under ThreadSanitizer by scripts/race-check.sh ("[parallel]"): GetStats takes the lock under which
    // a concurrent Query applies the queue, so neither reads what the other writes.
    World w(5u);
    std::vector<ProxyId> ids;
    for (int i = 0; i < 4000; ++i)
    {
        ids.push_back(w.Create(w.RandomBox(300.0f)));
    }
    std::vector<Pair> pairs;
    w.qt.FindPairs(pairs);
    for (int round = 0; round < 20; ++round)
    {
        for (ProxyId id : ids)
        {
            if (Chance(w.rng, 0.5))
            {
                w.qt.QueueMove(id, w.RandomBox(300.0f), Vec2{0.5f, 0.0f});
            }
        }
        const QuadtreeBroadPhase& reader = w.qt;
        std::atomic<int64_t> found{0};
        std::thread querying([&] {
            for (int i = 0; i < 50; ++i)
            {
                IdCollector c;
                reader.Query(Box{float(i), float(i), float(i) + 20.0f, float(i) + 20.0f},
                             &IdCollector::Callback, &c);
                found += int64_t(c.ids.size());
            }
        });
        int64_t proxies = 0;
        for (int i = 0; i < 50; ++i)
        {
            proxies += reader.GetStats().proxyCount;
        }
        querying.join();
        REQUIRE(proxies == 50 * 4000);
        REQUIRE(found.load() >= 0);
        w.qt.FindPairs(pairs);
    }
    REQUIRE(w.qt.Validate() == "");
}
