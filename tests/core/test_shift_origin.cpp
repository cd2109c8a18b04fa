// SPDX-License-Identifier: MIT
// ShiftOrigin: every fat box moves by -newOrigin with Box2D's float operations (bit-identical to the brute
// force), and pairs and queries still match afterwards. Harness::Shift checks the boxes; the rest of the
// harness checks everything else.
#include <cstdint>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

TEST_CASE("ShiftOrigin inside random call sequences", "[shift]")
{
    int64_t shifts = 0;
    for (Dist dist : kAllDists)
    {
        for (int depth : {-1, 0, 2, 5, 8})
        {
            for (int rep = 0; rep < 2; ++rep)
            {
                HarnessSettings s = RunSettings(70000u + uint32_t(int(dist)) * 100u +
                                                    uint32_t(depth + 1) * 10u + uint32_t(rep),
                                                dist, 120, 400);
                s.config.depth = depth;
                s.config.autoBounds = rep == 0;
                s.config.bounds = Box{-25.0f, -25.0f, 25.0f, 25.0f};
                s.shifts = true;
                s.validateEvery = depth >= 8 ? 0 : 8;
                INFO("case: " << Describe(s));
                Harness h(s);
                h.Run();
                // and a few shifts back to back, each followed by FindPairs
                for (int i = 0; i < 4; ++i)
                {
                    h.RandomShift();
                    h.RandomMove(h.Live()[size_t(UniformInt(h.Random(), 0, int(h.Live().size()) - 1))]);
                    h.FindPairs();
                    h.RandomQuery();
                    h.RandomRay();
                }
                shifts += h.Totals().shifts;
            }
        }
    }
    CHECK(shifts > 300);
}

TEST_CASE("ShiftOrigin keeps the pyramid's region on the world it covers", "[shift]")
{
    // With fixed bounds, the bounds move with the world: proxies inside before a shift are inside after it.
    Config c;
    c.depth = 5;
    c.autoBounds = false;
    c.bounds = Box{-16.0f, -16.0f, 16.0f, 16.0f};
    HarnessSettings s = RunSettings(71000u, Dist::Uniform, 100, 200);
    s.config = c;
    s.world = 12.0f;
    Harness h(s);
    h.Run();
    const int32_t outsideBefore = h.Quadtree().GetStats().outsideCount;
    h.Shift(Vec2{1000.0f, -500.0f});
    const Stats after = h.Quadtree().GetStats();
    CHECK(after.outsideCount == outsideBefore);
    CHECK(after.bounds.minX == -1016.0f);
    CHECK(after.bounds.minY == 484.0f);
    CHECK(after.depth == 5);
    // a shift reports no pairs by itself
    h.Run();
    h.Shift(Vec2{-1000.0f, 500.0f});
    REQUIRE(h.FindPairs().empty());
}
