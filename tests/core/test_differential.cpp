// SPDX-License-Identifier: MIT
// Randomized differential tests: QuadtreeBroadPhase against BruteForceBroadPhase (and an oracle computed from
// the fat boxes) over random call sequences, box distributions and configurations. See harness.h for the
// checks made after every call.
#include <cstdint>
#include <string>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

namespace
{

uint32_t CaseSeed(Dist dist, int depth, int rep, uint32_t salt)
{
    // a fixed, readable seed per case, printed on failure
    return salt * 1000000u + uint32_t(int(dist)) * 10000u + uint32_t(depth + 1) * 100u + uint32_t(rep);
}

HarnessSettings CaseSettings(Dist dist, int depth, int rep, uint32_t salt)
{
    HarnessSettings s;
    s.seed = CaseSeed(dist, depth, rep, salt);
    Rng rng(s.seed ^ 0x9e3779b9u);
    s.dist = dist;
    s.world = Chance(rng, 0.5) ? 50.0f : LogUniform(rng, 0.0f, 3.0f);
    s.config.depth = depth;
    s.config.autoBounds = (rep % 2) == 0;
    const float f = std::ldexp(1.0f, UniformInt(rng, -2, 1)); // fixed bounds: 1/4 .. 2 x the world
    s.config.bounds = Box{-s.world * f + Uniform(rng, -1.0f, 1.0f), -s.world * f, s.world * f, s.world * f};
    if (dist == Dist::Outside)
    {
        s.config.autoBounds = rep % 4 == 3; // mostly fixed bounds, so most proxies are outside
        s.config.bounds = Box{-s.world, -s.world, s.world, s.world};
    }
    if (Chance(rng, 0.3))
    {
        s.config.cellToProxyRatio = Uniform(rng, 0.5f, 8.0f);
        s.config.maxDepth = UniformInt(rng, 0, 10);
    }
    if (dist == Dist::ZeroArea && Chance(rng, 0.6))
    {
        s.policy.extension = 0.0f; // fat boxes of zero area, on cell borders
    }
    if (Chance(rng, 0.15))
    {
        s.policy.multiplier = Chance(rng, 0.5) ? 0.0f : 1.0f;
    }
    s.targetProxies = UniformInt(rng, 20, 220);
    s.operations = 500;
    s.timing = Chance(rng, 0.2);
    return s;
}

HarnessTotals RunDistribution(Dist dist, int reps, uint32_t salt, bool shifts)
{
    HarnessTotals totals;
    for (int depth = -1; depth <= 10; ++depth)
    {
        for (int rep = 0; rep < reps; ++rep)
        {
            HarnessSettings s = CaseSettings(dist, depth, rep, salt);
            s.shifts = shifts;
            s.queueMoves = rep % 2 == 1; // half the cases queue their moves,
            s.fatMoves = depth % 2 == 0; // half of those as the Box2D adapter does
            // the deep fixed pyramids cost O(cells) per Validate: validate them at FindPairs only
            if (depth >= 8)
            {
                s.validateEvery = 0;
            }
            INFO("case: " << Describe(s));
            Harness h(s);
            h.Run();
            totals += h.Totals();
        }
    }
    return totals;
}

void CheckCoverage(const HarnessTotals& t)
{
    INFO("findPairs " << t.findPairs << " pairs " << t.pairs << " creates " << t.creates << " moves "
                      << t.moves << " refattens " << t.refattens << " destroys " << t.destroys << " touches "
                      << t.touches << " queries " << t.queries << " rays " << t.rays);
    // the sequences did exercise every call
    CHECK(t.findPairs > 500);
    CHECK(t.pairs > 1000);
    CHECK(t.refattens > 1000);
    CHECK(t.moves > t.refattens); // some moves stayed inside the fat box
    CHECK(t.destroys > 100);
    CHECK(t.touches > 50);
    CHECK(t.queries > 100);
    CHECK(t.rays > 100);
}

} // namespace

TEST_CASE("Differential: each box distribution (see Dist), over depths -1 to 10", "[differential]")
{
    struct Case
    {
        Dist dist;
        int reps;
        uint32_t salt; // each case's own seeds
    };
    const Case c = GENERATE(Case{Dist::Uniform, 3, 1}, Case{Dist::LogMixed, 3, 2},
                            Case{Dist::Clustered, 3, 3}, Case{Dist::Outside, 4, 4},
                            Case{Dist::ZeroArea, 3, 5}, Case{Dist::Huge, 3, 6}, Case{Dist::Mixed, 3, 7});
    INFO("distribution " << DistName(c.dist));
    CheckCoverage(RunDistribution(c.dist, c.reps, c.salt, false));
}

TEST_CASE("QueueFatMove gives QueueMove's pairs in QueueMove's order", "[differential]")
{
    // The Box2D adapter runs the fat-box test itself and queues only the outcome: the core must then do exactly
    // what it does with the move, bit for bit (the pair order, hence Box2D's contacts, depend on it).
    for (int rep = 0; rep < 6; ++rep)
    {
        const Dist dist = rep % 3 == 0 ? Dist::Mixed : rep % 3 == 1 ? Dist::Clustered : Dist::Outside;
        HarnessSettings s = RunSettings(9100u + uint32_t(rep), dist, 300, 1500);
        s.queueMoves = true;
        s.shifts = rep % 2 == 0;
        INFO("case: " << Describe(s));
        Harness queued(s);
        queued.Record(true);
        queued.Run();
        s.fatMoves = true;
        Harness fat(s);
        fat.Record(true);
        fat.Run();
        REQUIRE(queued.History().size() > 20);
        CHECK(fat.History() == queued.History());
    }
}

TEST_CASE("Differential: a larger world of 2000 proxies", "[differential]")
{
    for (int rep = 0; rep < 2; ++rep)
    {
        HarnessSettings s =
            RunSettings(8000u + uint32_t(rep), rep == 0 ? Dist::Mixed : Dist::Clustered, 2000, 3000);
        s.world = 200.0f;
        s.validateEvery = 100;
        INFO("case: " << Describe(s));
        Harness h(s);
        h.Run();
        CHECK(h.Totals().findPairs > 50);
    }
}

TEST_CASE("Differential: Configure mid-sequence rebuilds without changing results", "[differential]")
{
    for (int rep = 0; rep < 6; ++rep)
    {
        HarnessSettings s;
        s.seed = 9100u + uint32_t(rep);
        s.dist = kAllDists[rep % 7];
        s.operations = 150;
        Harness h(s);
        Rng rng(s.seed);
        for (int round = 0; round < 6; ++round)
        {
            INFO("case: " << Describe(s) << " round " << round);
            h.Run();
            Config c;
            c.depth = UniformInt(rng, -1, 9);
            c.autoBounds = Chance(rng, 0.5);
            c.bounds = Box{Uniform(rng, -60.0f, 0.0f), Uniform(rng, -60.0f, 0.0f), Uniform(rng, 1.0f, 60.0f),
                           Uniform(rng, 1.0f, 60.0f)};
            const int64_t rebuilds = h.Quadtree().GetStats().rebuilds;
            h.Quadtree().Configure(c);
            REQUIRE(h.Quadtree().GetStats().rebuilds == rebuilds + 1);
            REQUIRE(h.Quadtree().Validate() == "");
            // Configure reports nothing by itself: a FindPairs right after finds only what was buffered
            // before
            h.FindPairs();
        }
    }
}

TEST_CASE("Configure that changes only the executor rebuilds nothing: the pairs and their order stay",
          "[differential][parallel]")
{
    // A rebuild re-tunes for the proxies of its moment, so it would change the layout, hence the pair order, from
    // then on: a game that turns threads on or off must get the simulation it had.
    for (int rep = 0; rep < 4; ++rep)
    {
        HarnessSettings s;
        s.seed = 9300u + uint32_t(rep);
        s.dist = kAllDists[(2 * rep + 1) % 7];
        s.operations = 200;
        Harness configured(s);
        Harness untouched(s);
        configured.Record(true);
        untouched.Record(true);
        INFO("case: " << Describe(s));
        for (int round = 0; round < 4; ++round)
        {
            configured.Run();
            untouched.Run();
            Config c = configured.Quadtree().GetConfig();
            c.threads = 1 + (round % 3);
            c.executor = round % 2 == 0 ? Executor::Pool : Executor::OpenMP;
            c.schedule = round % 2 == 0 ? Schedule::Static : Schedule::Dynamic;
            c.chunk = round;
            c.parallelThreshold = round % 2 == 0 ? 0 : 128;
            c.parallelMinProxies = round;
            const int64_t rebuilds = configured.Quadtree().GetStats().rebuilds;
            configured.Quadtree().Configure(c);
            REQUIRE(configured.Quadtree().GetStats().rebuilds == rebuilds);
            REQUIRE(configured.Quadtree().GetConfig().threads == c.threads);
            REQUIRE(configured.Quadtree().GetConfig().executor == c.executor);
            REQUIRE(configured.Quadtree().Validate() == "");
        }
        REQUIRE(configured.History().size() == untouched.History().size());
        REQUIRE(configured.History() == untouched.History());
        // and a layout setting still rebuilds
        Config c = configured.Quadtree().GetConfig();
        c.cellToProxyRatio *= 2.0f;
        const int64_t rebuilds = configured.Quadtree().GetStats().rebuilds;
        configured.Quadtree().Configure(c);
        REQUIRE(configured.Quadtree().GetStats().rebuilds == rebuilds + 1);
    }
}

TEST_CASE("Differential: extreme coordinate scales (1e37 and 1e-30 worlds)", "[differential]")
{
    // At 1e37 the region the automatic bounds want overflows to infinity (the fallback side is used and
    // almost everything is outside); at 1e-30 every box is far larger than the world.
    for (float world : {1e37f, 1e30f, 1e-30f})
    {
        for (int depth : {-1, 0, 5})
        {
            for (Dist dist : {Dist::Uniform, Dist::Mixed})
            {
                HarnessSettings s =
                    RunSettings(9500u + uint32_t(depth + 1) * 10u + uint32_t(int(dist)), dist, 100, 400);
                s.world = world;
                s.config.depth = depth;
                s.config.autoBounds = depth != 5;
                INFO("case: " << Describe(s));
                Harness h(s);
                h.Run();
                CHECK(h.Totals().findPairs > 10);
            }
        }
    }
}
