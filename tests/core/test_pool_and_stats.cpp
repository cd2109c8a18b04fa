// SPDX-License-Identifier: MIT
// ProxyPool (ids, move buffer, work flags), QuadtreeBroadPhase's Stats and automatic depth, TestOverlap.
#include <cmath>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "proxy_pool.h"

#include "harness.h"

using namespace quadphase;
using namespace qptest;

TEST_CASE("ProxyPool hands out ids last freed, first used, like b2DynamicTree's node pool", "[pool]")
{
    ProxyPool pool;
    int tag[8];
    for (int i = 0; i < 5; ++i)
    {
        REQUIRE(pool.Allocate(Box{float(i), 0.0f, float(i) + 1.0f, 1.0f}, &tag[i]) == i);
    }
    REQUIRE(pool.LiveCount() == 5);
    pool.Free(3);
    pool.Free(1);
    REQUIRE_FALSE(pool.IsLive(1));
    REQUIRE_FALSE(pool.IsLive(3));
    REQUIRE_FALSE(pool.IsLive(-1));
    REQUIRE_FALSE(pool.IsLive(5));
    REQUIRE(pool.UserData(1) == nullptr);
    REQUIRE(pool.LiveCount() == 3);
    REQUIRE(pool.Validate() == "");
    REQUIRE(pool.Allocate(Box{0, 0, 0, 0}, &tag[5]) == 1);
    REQUIRE(pool.Allocate(Box{0, 0, 0, 0}, &tag[6]) == 3);
    REQUIRE(pool.Allocate(Box{0, 0, 0, 0}, &tag[7]) == 5);
    REQUIRE(pool.UserData(3) == &tag[6]);
    REQUIRE(pool.IdBound() == 6);
    REQUIRE(pool.LiveCount() == 6);
    REQUIRE(pool.Validate() == "");
}

TEST_CASE("ProxyPool's move buffer: call order, each once, destroyed proxies dropped", "[pool]")
{
    ProxyPool pool;
    for (int i = 0; i < 6; ++i)
    {
        pool.Allocate(Box{0, 0, 1, 1}, nullptr);
    }
    pool.Buffer(4);
    pool.Buffer(1);
    pool.Buffer(4);
    pool.Buffer(2);
    pool.Buffer(5);
    REQUIRE(pool.BufferedCount() == 4);
    REQUIRE(pool.Validate() == "");

    pool.Free(2); // dropped lazily
    pool.Free(5);
    REQUIRE(pool.Validate() == "");
    REQUIRE(pool.Allocate(Box{0, 0, 1, 1}, nullptr) ==
            5); // reuses a buffered id: its old entry stands for it
    pool.Buffer(5);
    REQUIRE(pool.BufferedCount() == 4);
    REQUIRE(pool.Validate() == "");

    std::vector<ProxyId> work{99};
    pool.LendBuffer(work);
    REQUIRE(work == std::vector<ProxyId>{4, 1, 5});
    REQUIRE(pool.BufferedCount() == 0);
    for (ProxyId id = 0; id < pool.IdBound(); ++id)
    {
        CAPTURE(id);
        REQUIRE(pool.InWork(id) == (id == 4 || id == 1 || id == 5));
    }
    REQUIRE(pool.Validate() != ""); // "in work" outside FindPairs is a violation
    pool.ReturnBuffer(work);
    REQUIRE(pool.Validate() == "");

    // a freed id, reused after the buffer was taken, is buffered afresh
    REQUIRE(pool.Allocate(Box{0, 0, 1, 1}, nullptr) == 2);
    pool.Buffer(2);
    pool.Buffer(0);
    pool.LendBuffer(work);
    REQUIRE(work == std::vector<ProxyId>{2, 0});
    pool.ReturnBuffer(work);
    REQUIRE(pool.Validate() == "");
}

TEST_CASE("ProxyPool::ShiftOrigin subtracts the new origin from every live box", "[pool]")
{
    ProxyPool pool;
    pool.Allocate(Box{0.1f, 0.2f, 0.3f, 0.4f}, nullptr);
    pool.Allocate(Box{-5.0f, -6.0f, 7.0f, 8.0f}, nullptr);
    pool.Allocate(Box{1.0f, 1.0f, 2.0f, 2.0f}, nullptr);
    pool.Free(1);
    pool.ShiftOrigin(Vec2{0.7f, -1000.3f});
    REQUIRE(SameBox(pool.Fat(0), Box{0.1f - 0.7f, 0.2f + 1000.3f, 0.3f - 0.7f, 0.4f + 1000.3f}));
    REQUIRE(SameBox(pool.Fat(2), Box{1.0f - 0.7f, 1.0f + 1000.3f, 2.0f - 0.7f, 2.0f + 1000.3f}));
}

TEST_CASE("Destroyed ids are reused last freed, first used, by both broadphases", "[pool]")
{
    HarnessSettings s;
    s.seed = 12345u;
    Harness h(s);
    std::vector<ProxyId> ids;
    for (int i = 0; i < 10; ++i)
    {
        ids.push_back(h.Create(h.Source().Next()));
    }
    REQUIRE(ids == std::vector<ProxyId>{0, 1, 2, 3, 4, 5, 6, 7, 8, 9});
    h.Destroy(7);
    h.Destroy(2);
    h.Destroy(4);
    REQUIRE(h.Create(h.Source().Next()) == 4); // Harness checks the brute force agrees
    REQUIRE(h.Create(h.Source().Next()) == 2);
    REQUIRE(h.Create(h.Source().Next()) == 7);
    REQUIRE(h.Create(h.Source().Next()) == 10);
    h.FindPairs();
}

TEST_CASE("Stats describe the pyramid and count the work", "[stats]")
{
    for (int depth : {-1, 3})
    {
        HarnessSettings s = RunSettings(13000u + uint32_t(depth + 1), Dist::Mixed, 300, 600);
        s.config.depth = depth;
        Harness h(s);
        h.Record(true);
        h.Run();
        QuadtreeBroadPhase& qt = h.Quadtree();
        Stats st = qt.GetStats();
        CAPTURE(depth, st.depth, st.proxyCount);
        REQUIRE(st.proxyCount == int32_t(h.Live().size()));
        REQUIRE(st.proxiesPerLevel.size() == size_t(st.depth + 1));
        int32_t sum = 0;
        for (int32_t c : st.proxiesPerLevel)
        {
            sum += c;
        }
        REQUIRE(sum == st.proxyCount);
        // maxX is minX + side, rounded: (maxX - minX) need not give the side back, leafSize x 2^depth does.
        REQUIRE(st.bounds.maxX == st.bounds.minX + st.leafSize * float(1 << st.depth));
        int32_t outside = 0;
        for (ProxyId id : h.Live())
        {
            outside += Contains(st.bounds, qt.GetFatBox(id)) ? 0 : 1;
        }
        REQUIRE(st.outsideCount == outside);
        REQUIRE(st.occupiedCells >= 1);
        REQUIRE(st.occupiedCells <= st.proxyCount);
        REQUIRE(st.largestCell >= 1);
        REQUIRE(st.memoryBytes > 0);
        REQUIRE(st.rebuilds >= 1);

        // work counters match what the harness saw
        int64_t pairs = 0;
        for (const std::vector<Pair>& p : h.History())
        {
            pairs += int64_t(p.size());
        }
        REQUIRE(st.updatePairsCalls == int64_t(h.History().size()));
        REQUIRE(st.pairsReported == pairs);
        REQUIRE(st.lastPairs == int64_t(h.History().back().size()));
        REQUIRE(st.reinserts <= h.Totals().refattens);
        REQUIRE(st.proxiesQueried <= h.Totals().creates + h.Totals().refattens + h.Totals().touches);

        const int64_t rebuilds = st.rebuilds;
        qt.ResetCounters();
        st = qt.GetStats();
        REQUIRE(st.updatePairsCalls == 0);
        REQUIRE(st.pairsReported == 0);
        REQUIRE(st.proxiesQueried == 0);
        REQUIRE(st.reinserts == 0);
        REQUIRE(st.rebuilds == rebuilds);
        REQUIRE(st.proxyCount == int32_t(h.Live().size()));
    }
}

TEST_CASE("Automatic depth: capped by maxDepth and by 2 leaf cells per proxy, for any cellToProxyRatio",
          "[stats]")
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    struct Case
    {
        float ratio;
        int maxDepth;
    };
    for (const Case& k : {Case{2.0f, 12}, Case{2.0f, 3}, Case{0.0f, 12}, Case{0.0f, 4}, Case{-1.0f, 12},
                          Case{nan, 12}, Case{1e30f, 12}, Case{0.25f, 0}})
    {
        HarnessSettings s = RunSettings(14000u, Dist::Uniform, 400, 700);
        s.config.cellToProxyRatio = k.ratio;
        s.config.maxDepth = k.maxDepth;
        s.validateEvery = 50;
        INFO("ratio " << k.ratio << " maxDepth " << k.maxDepth);
        Harness h(s);
        h.Run();
        // Tune for exactly the current proxies: Configure re-tunes when a layout setting changes, so go through
        // a fixed depth and back to the case's settings.
        Config fixed = s.config;
        fixed.depth = 0;
        h.Quadtree().Configure(fixed);
        h.Quadtree().Configure(s.config);
        REQUIRE(h.Quadtree().Validate() == "");
        const Stats st = h.Quadtree().GetStats();
        const int n = st.proxyCount;
        CAPTURE(n, st.depth);
        REQUIRE(st.depth >= 0);
        REQUIRE(st.depth <= k.maxDepth);
        REQUIRE((int64_t(1) << (2 * st.depth)) <= 2 * int64_t(std::max(n, 1)));
        if (k.ratio == 0.0f)
        {
            // a zero target cell: as fine as the caps allow
            const int cap = std::min(k.maxDepth, int(std::floor(std::log2(2.0 * double(n)) / 2.0)));
            REQUIRE(st.depth == cap);
        }
        if (std::isnan(k.ratio) || k.ratio < 0.0f || k.ratio == 1e30f)
        {
            REQUIRE(st.depth == 0);
        }
    }
}

TEST_CASE("TestOverlap compares the stored fat boxes", "[stats]")
{
    HarnessSettings s = RunSettings(15000u, Dist::Clustered, 100, 300);
    Harness h(s);
    h.Run();
    int overlapping = 0;
    for (ProxyId a : h.Live())
    {
        for (ProxyId b : h.Live())
        {
            const bool want = Overlaps(h.Brute().GetFatBox(a), h.Brute().GetFatBox(b));
            if (h.Quadtree().TestOverlap(a, b) != want)
            {
                FAIL("TestOverlap(" << a << ", " << b << ") != " << want);
            }
            overlapping += want ? 1 : 0;
        }
    }
    CHECK(overlapping > int(h.Live().size()));
}

TEST_CASE("SetTiming books queued moves as maintenance time only while it is on", "[stats]")
{
    QuadtreeBroadPhase qt;
    std::vector<ProxyId> ids;
    for (int i = 0; i < 64; ++i)
    {
        const float x = float(i);
        ids.push_back(qt.CreateProxy(Box{x, 0.0f, x + 0.5f, 0.5f}, nullptr));
    }
    std::vector<Pair> pairs;
    qt.FindPairs(pairs);
    // Moves far enough to get new fat boxes; each proxy once per round, so every call can take the inline path.
    auto queueAll = [&](float dy) {
        for (size_t i = 0; i < ids.size(); ++i)
        {
            const float x = float(i);
            qt.QueueMove(ids[i], Box{x, dy, x + 0.5f, dy + 0.5f}, Vec2{0.0f, dy});
        }
    };
    qt.ResetCounters();
    queueAll(5.0f);
    REQUIRE(qt.QueuedMoveCount() == int32_t(ids.size()));
    // Untimed, queuing books nothing: the time is booked when the queue is applied.
    REQUIRE(qt.GetStats().updateSeconds == 0.0);
    qt.FindPairs(pairs);

    qt.SetTiming(true);
    qt.ResetCounters();
    queueAll(10.0f);
    REQUIRE(qt.QueuedMoveCount() == int32_t(ids.size()));
    REQUIRE(qt.GetStats().updateSeconds > 0.0); // every timed call is timed, so the out-of-line path ran
    qt.FindPairs(pairs);
    REQUIRE(qt.Validate().empty());
    for (size_t i = 0; i < ids.size(); ++i)
    {
        REQUIRE(Contains(qt.GetFatBox(ids[i]), Box{float(i), 10.0f, float(i) + 0.5f, 10.5f}));
    }

    qt.SetTiming(false);
    qt.ResetCounters();
    queueAll(15.0f);
    REQUIRE(qt.GetStats().updateSeconds == 0.0);
}
