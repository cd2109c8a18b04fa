// SPDX-License-Identifier: MIT
// The fat-box policy (fat_policy.h) against Box2D 2.4.1's b2DynamicTree::CreateProxy / MoveProxy arithmetic,
// written here the way Box2D writes it, compared bit for bit.
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "box_simd.h"
#include "fat_policy.h"

#include "test_support.h"

using namespace quadphase;
using namespace qptest;

namespace
{

// --- Box2D 2.4.1, transcribed (b2Vec2 / b2AABB reduced to what these functions use)
// ---------------------------

struct b2Vec2
{
    float x, y;
};
b2Vec2 operator-(const b2Vec2& a, const b2Vec2& b)
{
    return b2Vec2{a.x - b.x, a.y - b.y};
}
b2Vec2 operator+(const b2Vec2& a, const b2Vec2& b)
{
    return b2Vec2{a.x + b.x, a.y + b.y};
}
b2Vec2 operator*(float s, const b2Vec2& a)
{
    return b2Vec2{s * a.x, s * a.y};
}

struct b2AABB
{
    b2Vec2 lowerBound;
    b2Vec2 upperBound;

    bool Contains(const b2AABB& aabb) const
    {
        bool result = true;
        result = result && lowerBound.x <= aabb.lowerBound.x;
        result = result && lowerBound.y <= aabb.lowerBound.y;
        result = result && aabb.upperBound.x <= upperBound.x;
        result = result && aabb.upperBound.y <= upperBound.y;
        return result;
    }
};

// b2DynamicTree::CreateProxy: the stored box.
b2AABB Box2DCreate(float extension, const b2AABB& aabb)
{
    b2Vec2 r = {extension, extension};
    b2AABB fat;
    fat.lowerBound = aabb.lowerBound - r;
    fat.upperBound = aabb.upperBound + r;
    return fat;
}

// b2DynamicTree::MoveProxy without the tree surgery: returns whether the stored box was replaced.
bool Box2DMove(float extension, float multiplier, b2AABB& treeAABB, const b2AABB& aabb,
               const b2Vec2& displacement)
{
    // Extend AABB
    b2AABB fatAABB;
    b2Vec2 r = {extension, extension};
    fatAABB.lowerBound = aabb.lowerBound - r;
    fatAABB.upperBound = aabb.upperBound + r;

    // Predict AABB movement
    b2Vec2 d = multiplier * displacement;

    // The directions pass through volatiles (not in Box2D) so that this reference keeps IEEE's results: from the
    // float compares themselves, clang 14 for WebAssembly (em++ -O1 and up) turns the if/else into
    // upperBound + (d <= 0 ? -0.0f : d), which gives -0 where -0 + +0 is +0 (upperBound -0, d +0: extension -0).
    volatile bool left = d.x < 0.0f;
    volatile bool down = d.y < 0.0f;
    if (left)
    {
        fatAABB.lowerBound.x += d.x;
    }
    else
    {
        fatAABB.upperBound.x += d.x;
    }

    if (down)
    {
        fatAABB.lowerBound.y += d.y;
    }
    else
    {
        fatAABB.upperBound.y += d.y;
    }

    if (treeAABB.Contains(aabb))
    {
        // The tree AABB still contains the object, but it might be too large.
        // Perhaps the object was moving fast but has since gone to sleep.
        // The huge AABB is larger than the new fat AABB.
        b2AABB hugeAABB;
        hugeAABB.lowerBound = fatAABB.lowerBound - 4.0f * r;
        hugeAABB.upperBound = fatAABB.upperBound + 4.0f * r;

        if (hugeAABB.Contains(treeAABB))
        {
            // The tree AABB contains the object AABB and the tree AABB is
            // not too large. No tree update needed.
            return false;
        }

        // Otherwise the tree AABB is huge and needs to be shrunk
    }

    treeAABB = fatAABB;
    return true;
}

// ---------------------------------------------------------------------------------------------------------------

b2AABB ToB2(const Box& b)
{
    return b2AABB{b2Vec2{b.minX, b.minY}, b2Vec2{b.maxX, b.maxY}};
}
Box FromB2(const b2AABB& b)
{
    return Box{b.lowerBound.x, b.lowerBound.y, b.upperBound.x, b.upperBound.y};
}

/// A float from a mix of awkward values: signed zeros, tiny, ordinary, huge, infinities and NaN (rarely).
float Awkward(Rng& rng, float scale)
{
    switch (UniformInt(rng, 0, 11))
    {
    case 0:
        return 0.0f;
    case 1:
        return -0.0f;
    case 2:
        return Uniform(rng, -1e-6f, 1e-6f);
    case 3:
        return LogUniform(rng, 3.0f, 30.0f) * (Chance(rng, 0.5) ? 1.0f : -1.0f);
    default:
        return Uniform(rng, -scale, scale);
    }
}

FatPolicy RandomPolicy(Rng& rng)
{
    switch (UniformInt(rng, 0, 5))
    {
    case 0:
        return FatPolicy{0.0f, 4.0f};
    case 1:
        return FatPolicy{0.1f, 0.0f};
    case 2:
        return FatPolicy{-0.0f, 4.0f};
    case 3:
        return FatPolicy{Uniform(rng, 0.0f, 2.0f), Uniform(rng, 0.0f, 8.0f)};
    default:
        return FatPolicy{0.1f, 4.0f}; // Box2D's b2_aabbExtension, b2_aabbMultiplier
    }
}

} // namespace

TEST_CASE("FattenNew reproduces b2DynamicTree::CreateProxy bit for bit", "[fat]")
{
    Rng rng(515u);
    for (int i = 0; i < 200000; ++i)
    {
        const FatPolicy policy = RandomPolicy(rng);
        const float s = LogUniform(rng, -2.0f, 4.0f);
        float a = Awkward(rng, s), b = Awkward(rng, s), c = Awkward(rng, s), d = Awkward(rng, s);
        const Box tight{std::min(a, b), std::min(c, d), std::max(a, b), std::max(c, d)};
        const Box mine = FattenNew(policy, tight);
        const Box theirs = FromB2(Box2DCreate(policy.extension, ToB2(tight)));
        if (!SameBox(mine, theirs))
        {
            FAIL("i=" << i << " extension " << policy.extension << " tight " << Str(tight) << ": "
                      << Str(mine) << " vs " << Str(theirs));
        }
    }
    SUCCEED();
}

TEST_CASE("Refatten reproduces b2DynamicTree::MoveProxy bit for bit, including the huge-box shrink", "[fat]")
{
    Rng rng(616u);
    int kept = 0, grown = 0, shrunk = 0, negativeZero = 0;
    for (int i = 0; i < 400000; ++i)
    {
        const FatPolicy policy = RandomPolicy(rng);

        const float s = LogUniform(rng, -2.0f, 3.0f);
        float a = Awkward(rng, s), b = Awkward(rng, s), c = Awkward(rng, s), d = Awkward(rng, s);
        Box tight{std::min(a, b), std::min(c, d), std::max(a, b), std::max(c, d)};
        if (Chance(rng, 0.05))
        {
            tight = Box{std::max(a, b), std::max(c, d), std::min(a, b), std::min(c, d)}; // inverted
        }
        const float m = s * 0.05f;
        Vec2 disp{Awkward(rng, m), Awkward(rng, m)};

        // The stored box: the box of a previous move (so it often still contains the new one), a box grown
        // far beyond it (to be shrunk), or an unrelated one.
        Box stored;
        switch (UniformInt(rng, 0, 4))
        {
        case 0:
        case 1:
        {
            const Vec2 prev{Uniform(rng, -m, m), Uniform(rng, -m, m)};
            stored = FattenNew(policy, Translate(tight, Vec2{-prev.x, -prev.y}));
            Refatten(policy, stored, Translate(tight, Vec2{-prev.x, -prev.y}), prev);
            break;
        }
        case 2:
        {
            const float g = policy.extension * Uniform(rng, 0.0f, 12.0f);
            stored =
                Box{tight.minX - g * Uniform(rng, 0.0f, 1.0f), tight.minY - g * Uniform(rng, 0.0f, 1.0f),
                    tight.maxX + g * Uniform(rng, 0.0f, 1.0f), tight.maxY + g * Uniform(rng, 0.0f, 1.0f)};
            break;
        }
        case 3:
            stored = tight; // exactly the shape (possible with extension 0)
            break;
        default:
        {
            float e = Awkward(rng, s), f = Awkward(rng, s), g = Awkward(rng, s), h = Awkward(rng, s);
            stored = Box{std::min(e, f), std::min(g, h), std::max(e, f), std::max(g, h)};
            break;
        }
        }
        if (Chance(rng, 0.002))
        {
            disp.x = std::numeric_limits<float>::quiet_NaN();
        }

        Box mine = stored;
        b2AABB theirs = ToB2(stored);
        const bool mineChanged = Refatten(policy, mine, tight, disp);
        const bool theirsChanged =
            Box2DMove(policy.extension, policy.multiplier, theirs, ToB2(tight), b2Vec2{disp.x, disp.y});
        if (mineChanged != theirsChanged || !SameBox(mine, FromB2(theirs)))
        {
            FAIL("i=" << i << " extension " << policy.extension << " multiplier " << policy.multiplier
                      << " tight " << Str(tight) << " displacement (" << disp.x << ", " << disp.y
                      << ") stored " << Str(stored) << ": Refatten " << mineChanged << " " << Str(mine)
                      << ", Box2D " << theirsChanged << " " << Str(FromB2(theirs)));
        }
        if (!theirsChanged)
        {
            ++kept;
        }
        else if (Contains(stored, tight))
        {
            ++shrunk; // contained, but too large: the huge-box rule replaced it
        }
        else
        {
            ++grown;
        }
        const float lowX = theirs.lowerBound.x;
        negativeZero += (theirsChanged && std::signbit(lowX) && lowX == 0.0f) ? 1 : 0;
    }
    INFO("kept " << kept << " grown " << grown << " shrunk " << shrunk << " -0 " << negativeZero);
    // every branch was exercised many times
    CHECK(kept > 10000);
    CHECK(grown > 10000);
    CHECK(shrunk > 10000);
    CHECK(negativeZero > 100);
}

TEST_CASE("Refatten: the documented examples", "[fat]")
{
    const FatPolicy policy; // 0.1, 4
    const Box tight{0.0f, 0.0f, 1.0f, 1.0f};
    Box stored = FattenNew(policy, tight);
    REQUIRE(SameBox(stored, Box{-0.1f, -0.1f, 1.1f, 1.1f}));

    // a small move inside the fat box changes nothing
    Box kept = stored;
    REQUIRE_FALSE(Refatten(policy, kept, Translate(tight, Vec2{0.05f, 0.0f}), Vec2{0.05f, 0.0f}));
    REQUIRE(SameBox(kept, stored));

    // leaving it replaces the box, stretched 4x the displacement in the direction of motion
    Box moved = stored;
    REQUIRE(Refatten(policy, moved, Translate(tight, Vec2{0.5f, -0.25f}), Vec2{0.5f, -0.25f}));
    REQUIRE(moved.minX == 0.5f - 0.1f);
    REQUIRE(moved.maxX == (1.5f + 0.1f) + 4.0f * 0.5f);
    REQUIRE(moved.minY == (-0.25f - 0.1f) + 4.0f * -0.25f);
    REQUIRE(moved.maxY == 0.75f + 0.1f);

    // a box left huge by a fast move is shrunk when the shape stops, although it still contains the shape
    Box huge = Box{-10.0f, -10.0f, 10.0f, 10.0f};
    REQUIRE(Refatten(policy, huge, tight, Vec2{0.0f, 0.0f}));
    REQUIRE(SameBox(huge, stored));
}

TEST_CASE("SIMD fat-box, overlap and sanity tests equal the scalar ones bit for bit, special values included",
          "[fat]")
{
    // Values that probe every compare and addition: signed zeros, infinities, NaN, denormals, huge and tiny.
    const float special[] = {0.0f,
                             -0.0f,
                             1.0f,
                             -1.0f,
                             0.1f,
                             -0.1f,
                             1e-40f,
                             -1e-40f,
                             3e38f,
                             -3e38f,
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN(),
                             1e7f,
                             -1e7f,
                             0.30000001f};
    std::mt19937 rng(12345u);
    auto pick = [&](bool anything) {
        if (anything && rng() % 4 == 0)
        {
            return special[rng() % (sizeof(special) / sizeof(special[0]))];
        }
        return std::uniform_real_distribution<float>(-50.0f, 50.0f)(rng);
    };
    int64_t kept = 0, changed = 0, overlapping = 0;
    for (int i = 0; i < 400000; ++i)
    {
        const bool anything = i % 2 == 0;
        FatPolicy policy;
        if (i % 7 == 0)
        {
            policy.extension = pick(anything);
            policy.multiplier = pick(anything);
        }
        Box tight{pick(anything), pick(anything), pick(anything), pick(anything)};
        if (!anything && tight.minX > tight.maxX)
        {
            std::swap(tight.minX, tight.maxX);
        }
        if (!anything && tight.minY > tight.maxY)
        {
            std::swap(tight.minY, tight.maxY);
        }
        // A stored box near the tight one most of the time, so both outcomes are common.
        Box stored = i % 3 == 0 ? Box{pick(anything), pick(anything), pick(anything), pick(anything)}
                                : FattenNew(policy, tight);
        if (i % 3 == 1)
        {
            stored.minX -= 0.2f * float(rng() % 3);
            stored.maxY += 0.2f * float(rng() % 3);
        }
        const Vec2 d{i % 5 == 0 ? pick(anything) : std::uniform_real_distribution<float>(-0.3f, 0.3f)(rng),
                     i % 5 == 1 ? pick(anything) : std::uniform_real_distribution<float>(-0.3f, 0.3f)(rng)};
        Box a = stored, b = stored;
        const bool ra = RefattenNoBranch(policy, a, tight, d);
        const bool rb = RefattenSimd(policy, b, tight, d);
        INFO("case " << i);
        REQUIRE(ra == rb);
        // Bit for bit, except that any NaN equals any NaN: which of two NaN operands an addition passes on is up
        // to the compiler (it may swap the operands of a commutative operation), in the scalar code as in stock
        // Box2D, so NaN bits are not reproducible across builds (an ASan build differed in a sign).
        REQUIRE(SameBox(a, b));
        (ra ? changed : kept) += 1;
        // MoveProxy's one-mask test: kept and sane together, and otherwise the moved fat box and the sanity.
        Box moved{};
        bool sane = false;
        const bool keptAndSane = KeptAndSaneSimd(policy, stored, &tight.minX, &tight.maxX, d, moved, sane);
        REQUIRE(keptAndSane == (!ra && IsSane(tight)));
        if (!keptAndSane)
        {
            REQUIRE(sane == IsSane(tight));
            REQUIRE(SameBox(moved, MovedFatBox(policy, tight, d)));
        }

        const Box q{pick(anything), pick(anything), pick(anything), pick(anything)};
        REQUIRE(IsSane(q) == IsSaneSimd(q));
        REQUIRE(IsSane(tight) == IsSaneSimd(tight));
        const bool oa = Overlaps(stored, q);
        REQUIRE(oa == OverlapsPrepared(stored, Prepare(q)));
        overlapping += oa ? 1 : 0;
    }
    // Both outcomes of both tests were exercised many times.
    CHECK(kept > 10000);
    CHECK(changed > 10000);
    CHECK(overlapping > 10000);
    CHECK(overlapping < 390000);
}
