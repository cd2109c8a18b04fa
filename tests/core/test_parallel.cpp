// Parallel pair generation gives the serial loop's output, pair for pair and in order, at any thread count and
// under any schedule (and the brute-force reference's set, which the harness checks on every FindPairs).
#include <algorithm>
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

namespace
{

std::vector<std::vector<Pair>> PairHistory(HarnessSettings s, int threads, Schedule schedule, int chunk,
                                           int64_t& parallelCalls, bool queueMoves = false)
{
    s.queueMoves = queueMoves;
    s.config.threads = threads;
    s.config.schedule = schedule;
    s.config.chunk = chunk;
    s.config.parallelThreshold = 0;
    Harness h(s);
    h.Record(true);
    h.Run();
    parallelCalls = h.Quadtree().GetStats().parallelCalls;
    return h.History();
}

} // namespace

TEST_CASE("Parallel FindPairs equals the serial loop at 1-4 threads under every schedule", "[parallel]")
{
    for (Dist dist : {Dist::Uniform, Dist::LogMixed})
    {
        HarnessSettings s;
        s.seed = 91000u + uint32_t(int(dist));
        s.dist = dist;
        s.targetProxies = 800; // several blocks of 64 buffered proxies per FindPairs
        s.operations = 2500;
        s.validateEvery = 2000;
        INFO("case: " << Describe(s));

        int64_t parallelCalls = 0;
        const std::vector<std::vector<Pair>> serial = PairHistory(s, 1, Schedule::Static, 0, parallelCalls);
        REQUIRE(parallelCalls == 0);
        size_t pairs = 0;
        for (const std::vector<Pair>& call : serial)
        {
            pairs += call.size();
        }
        REQUIRE(pairs > 1000);

        const Schedule schedules[] = {Schedule::Static, Schedule::Dynamic, Schedule::Guided, Schedule::Auto};
        for (int threads = 2; threads <= 4; ++threads)
        {
            for (Schedule schedule : schedules)
            {
                const std::vector<int> chunks =
                    schedule == Schedule::Dynamic ? std::vector<int>{0, 1} : std::vector<int>{0};
                for (int chunk : chunks)
                {
                    CAPTURE(threads, int(schedule), chunk);
                    const std::vector<std::vector<Pair>> parallel =
                        PairHistory(s, threads, schedule, chunk, parallelCalls);
                    CHECK(parallelCalls > 0);
                    REQUIRE(parallel == serial);
                }
            }
        }
    }
}

TEST_CASE("Queued moves give MoveProxy's pairs, in one order at 1-4 threads", "[parallel]")
{
    // Queued moves update the entries that stay in their cell when they are applied, so a proxy moved twice
    // between two FindPairs can reach the stale list at another position than with MoveProxy, and a cell's
    // entries another order: the pair sets are MoveProxy's, the order is the queue's own, the same at any thread
    // count.
    for (Dist dist : {Dist::Uniform, Dist::Clustered})
    {
        HarnessSettings s;
        s.seed = 93000u + uint32_t(int(dist));
        s.dist = dist;
        s.targetProxies = 800; // batches of up to 266 moves, searched in parallel (threshold 0)
        s.operations = 2500;
        s.validateEvery = 500;
        s.shifts = true;
        INFO("case: " << Describe(s));

        int64_t parallelCalls = 0;
        const std::vector<std::vector<Pair>> immediate =
            PairHistory(s, 1, Schedule::Static, 0, parallelCalls);
        REQUIRE(immediate.size() > 50);
        std::vector<std::vector<Pair>> reference;
        for (int threads = 1; threads <= 4; ++threads)
        {
            CAPTURE(threads);
            const std::vector<std::vector<Pair>> queued =
                PairHistory(s, threads, Schedule::Dynamic, 1, parallelCalls, true);
            REQUIRE(queued.size() == immediate.size());
            for (size_t call = 0; call < queued.size(); ++call)
            {
                CAPTURE(call);
                std::vector<Pair> a = queued[call];
                std::vector<Pair> b = immediate[call];
                std::sort(a.begin(), a.end());
                std::sort(b.begin(), b.end());
                REQUIRE(a == b);
            }
            if (threads == 1)
            {
                reference = queued;
            }
            REQUIRE(queued == reference);
        }
    }
}
