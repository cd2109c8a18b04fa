// SPDX-License-Identifier: MIT
// Query and RayCast: the quadtree reports the same ids as the brute force (and as an oracle), clipping finds
// the same closest fraction, and an early exit stops after exactly one callback. The checks live in
// Harness::CheckQuery and Harness::CheckRay.
#include <cstdint>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

namespace
{

void Populate(Harness& h, int n)
{
    for (int i = 0; i < n; ++i)
    {
        h.Create(h.Source().Next());
    }
    h.FindPairs();
    // move some, so fat boxes are stretched by displacement too
    for (int i = 0; i < n / 2; ++i)
    {
        h.RandomMove(h.Live()[size_t(UniformInt(h.Random(), 0, int(h.Live().size()) - 1))]);
    }
}

} // namespace

TEST_CASE("Query and RayCast agree with brute force on random sets", "[query][raycast]")
{
    int cases = 0;
    for (Dist dist : kAllDists)
    {
        for (int depth = -1; depth <= 10; depth += 1)
        {
            HarnessSettings s;
            s.seed = 31000u + uint32_t(int(dist)) * 100u + uint32_t(depth + 1);
            s.dist = dist;
            s.config.depth = depth;
            s.config.autoBounds = (depth % 2) != 0;
            s.config.bounds = Box{-30.0f, -30.0f, 30.0f, 30.0f};
            if (dist == Dist::ZeroArea && depth % 3 == 0)
            {
                s.policy.extension = 0.0f;
            }
            INFO("case: " << Describe(s));
            Harness h(s);
            Populate(h, UniformInt(h.Random(), 1, 250));
            for (int i = 0; i < 40; ++i)
            {
                h.RandomQuery();
                h.RandomRay();
            }
            ++cases;
        }
    }
    REQUIRE(cases == 7 * 12);
}

TEST_CASE("Query and RayCast on an empty broadphase call nothing", "[query][raycast]")
{
    HarnessSettings s;
    Harness h(s);
    h.CheckQuery(Box{-1e30f, -1e30f, 1e30f, 1e30f});
    h.CheckRay(RayInput{Vec2{-10.0f, -10.0f}, Vec2{10.0f, 10.0f}, 1.0f});
    // and after everything was destroyed
    const ProxyId a = h.Create(Box{0.0f, 0.0f, 1.0f, 1.0f});
    h.Destroy(a);
    h.CheckQuery(Box{-1e30f, -1e30f, 1e30f, 1e30f});
    h.CheckRay(RayInput{Vec2{-10.0f, -10.0f}, Vec2{10.0f, 10.0f}, 1.0f});
}

TEST_CASE("RayCast: rays along cell borders, from inside boxes, and with tiny maxFraction", "[raycast]")
{
    for (int depth : {0, 3, 6})
    {
        HarnessSettings s;
        s.seed = 32000u + uint32_t(depth);
        s.dist = Dist::ZeroArea;
        s.policy.extension = 0.0f;
        s.config.depth = depth;
        s.config.autoBounds = false;
        s.config.bounds = Box{-32.0f, -32.0f, 32.0f, 32.0f}; // cell borders on integers
        INFO("case: " << Describe(s));
        Harness h(s);
        // a lattice of unit squares, points and segments sharing borders
        for (int y = -8; y <= 8; y += 2)
        {
            for (int x = -8; x <= 8; x += 2)
            {
                h.Create(Box{float(x), float(y), float(x + 1), float(y + 1)});
                h.Create(Box{float(x), float(y), float(x), float(y)});
                h.Create(Box{float(x) + 0.5f, float(y), float(x) + 0.5f, float(y + 2)});
            }
        }
        h.FindPairs();
        for (int i = -9; i <= 9; ++i)
        {
            const float c = float(i);
            h.CheckRay(RayInput{Vec2{-20.0f, c}, Vec2{20.0f, c}, 1.0f});             // along a row border
            h.CheckRay(RayInput{Vec2{c, 20.0f}, Vec2{c, -20.0f}, 1.0f});             // along a column border
            h.CheckRay(RayInput{Vec2{c, c}, Vec2{c + 30.0f, c + 29.0f}, 1.0f});      // from a box corner
            h.CheckRay(RayInput{Vec2{c + 0.25f, 0.5f}, Vec2{c - 5.0f, 9.0f}, 1.0f}); // from inside
            h.CheckRay(RayInput{Vec2{-20.0f, c}, Vec2{20.0f, c + 0.5f}, 1e-3f});     // tiny maxFraction
            h.CheckRay(RayInput{Vec2{-9.0f, c}, Vec2{9.0f, -c}, 0.5f});
            h.CheckQuery(Box{c, c, c, c});          // a point query on a corner
            h.CheckQuery(Box{c, -20.0f, c, 20.0f}); // a segment on a border
        }
    }
}
