// SPDX-License-Identifier: MIT
// "Cheap when nothing moves", counted rather than timed: a FindPairs with nothing buffered queries nobody and
// reports nothing, and one after k moves queries at most k proxies.
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

TEST_CASE("FindPairs with nothing buffered queries no proxy", "[cheap]")
{
    for (Dist dist : kAllDists)
    {
        for (int depth : {-1, 0, 4, 8})
        {
            HarnessSettings s = SweepSettings(90000u, dist, depth, 300, 500);
            s.config.autoBounds = depth != 4;
            s.validateEvery = 0;
            INFO("case: " << Describe(s));
            Harness h(s);
            h.Run(); // ends with a FindPairs
            QuadtreeBroadPhase& qt = h.Quadtree();

            for (int round = 0; round < 10; ++round)
            {
                CAPTURE(round);
                // a second FindPairs right after the first: no pairs, nobody queried
                const Stats before = qt.GetStats();
                std::vector<Pair> pairs;
                qt.FindPairs(pairs);
                h.Brute().FindPairs(pairs);
                REQUIRE(pairs.empty());
                const Stats after = qt.GetStats();
                REQUIRE(after.proxiesQueried == before.proxiesQueried);
                REQUIRE(after.updatePairsCalls == before.updatePairsCalls + 1);
                REQUIRE(after.lastPairs == 0);
                REQUIRE(after.pairsReported == before.pairsReported);
                // and nothing was rebuilt either (a rebuild is O(proxies))
                REQUIRE(after.rebuilds == before.rebuilds);

                // move k proxies: at most k are queried (exactly those whose fat box was replaced)
                const int k = UniformInt(h.Random(), 0, 12);
                int refattened = 0;
                for (int i = 0; i < k; ++i)
                {
                    const ProxyId id = h.Live()[size_t(UniformInt(h.Random(), 0, int(h.Live().size()) - 1))];
                    const Box fat = qt.GetFatBox(id);
                    const float w = fat.maxX - fat.minX;
                    // alternate big moves (refatten) and no-op moves (the same tight box again: usually kept)
                    if (i % 2 == 0)
                    {
                        refattened += h.Move(id,
                                             Box{fat.minX + 2.0f * w + 1.0f, fat.minY,
                                                 fat.maxX + 2.0f * w + 1.0f, fat.maxY},
                                             Vec2{0.0f, 0.0f})
                                          ? 1
                                          : 0;
                    }
                    else
                    {
                        refattened += h.Move(id, h.Tight(id), Vec2{0.0f, 0.0f}) ? 1 : 0;
                    }
                }
                const Stats mid = qt.GetStats();
                h.FindPairs();
                const Stats end = qt.GetStats();
                const int64_t queried = end.proxiesQueried - mid.proxiesQueried;
                CAPTURE(k, refattened, queried);
                REQUIRE(queried <= int64_t(k));
                REQUIRE(queried <= int64_t(refattened)); // a proxy moved twice is queried once
                REQUIRE((queried == 0) == (refattened == 0));
            }
        }
    }
}

TEST_CASE("Touching k proxies queries exactly k, however often each is touched", "[cheap]")
{
    HarnessSettings s = RunSettings(91000u, Dist::Uniform, 200, 400);
    Harness h(s);
    h.Run();
    QuadtreeBroadPhase& qt = h.Quadtree();
    for (int k : {0, 1, 5, 40})
    {
        CAPTURE(k);
        const int64_t before = qt.GetStats().proxiesQueried;
        for (int i = 0; i < k; ++i)
        {
            h.Touch(h.Live()[size_t(i)]);
            h.Touch(h.Live()[size_t(i)]); // twice: buffered once
        }
        h.FindPairs();
        REQUIRE(qt.GetStats().proxiesQueried - before == int64_t(k));
    }
}
