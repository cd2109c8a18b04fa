// SPDX-License-Identifier: MIT
// Validation mode switched on mid-run (quadphase build, b2BroadPhase): the shadow b2DynamicTree is seeded
// from the quadtree's fat AABBs, and some of them have no tight AABB that b2DynamicTree::CreateProxy fattens
// to them (below a power of two, fl(t + 0.1) skips every other float). Found by the Box2D-level fuzzer
// (tests/fuzz/box2d_fuzz.cpp, regression input tests/fuzz/regressions/box2d/validation-midrun-inexact-seed):
// the validator reported "cannot seed the shadow tree ... exactly" as a mismatch although the quadtree was
// right. Such proxies are now seeded one float off and left out of the comparisons until a move gives both
// trees the same bits.
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "box2d/box2d.h"
#include "quadphase/box2d.h"
#include "quadphase/error.h"

namespace
{

int g_reports = 0;
void CountReport(quadphase::ErrorCode, const char*, void*)
{
    ++g_reports;
}

/// Counts error reports while it lives.
struct ReportCounter
{
    quadphase::ErrorHandler previous;
    ReportCounter() : previous(quadphase::SetErrorHandler(&CountReport)) { g_reports = 0; }
    ~ReportCounter() { quadphase::SetErrorHandler(previous); }
};

b2AABB Aabb(float x0, float y0, float x1, float y1)
{
    b2AABB a;
    a.lowerBound.Set(x0, y0);
    a.upperBound.Set(x1, y1);
    return a;
}

struct PairLog
{
    std::set<std::pair<intptr_t, intptr_t>> pairs;
    void AddPair(void* a, void* b)
    {
        const intptr_t x = reinterpret_cast<intptr_t>(a);
        const intptr_t y = reinterpret_cast<intptr_t>(b);
        pairs.insert({std::min(x, y), std::max(x, y)});
    }
};

/// True when some float t gives fl(t + 0.1f) == target (how b2DynamicTree::CreateProxy fattens an upper
/// bound).
bool Reachable(float target)
{
    float t = target - b2_aabbExtension;
    for (int i = 0; i < 64; ++i)
    {
        const float v = t + b2_aabbExtension;
        if (v == target)
        {
            return true;
        }
        t = std::nextafter(t, v < target ? INFINITY : -INFINITY);
    }
    return false;
}

/// Validation ran `checks` UpdatePairs comparisons, compared pairs, and found (and reported) nothing.
void CheckValidatedCleanly(const b2BroadPhase& bp, int64_t checks)
{
    const quadphase::ValidationReport report = quadphase::GetValidationReport(bp);
    INFO(report.firstMismatch);
    CHECK(report.mismatches == 0);
    CHECK(report.checks == checks);
    CHECK(report.pairsCompared > 0);
    CHECK(g_reports == 0);
}

} // namespace

TEST_CASE("b2BroadPhase: validation switched on mid-run over fat AABBs b2DynamicTree cannot reproduce",
          "[validation]")
{
    ReportCounter reports;
    b2BroadPhase bp;
    // A proxy whose upper x ends just below -0.0625 after a move: fl(t + 0.1) for t in [-0.25, -0.125) steps
    // by 2^-26 while the floats there step by 2^-27, so half the fat bounds a displacement can produce are
    // unreachable. Search the displacement that gives one (the test fails if none is found).
    const int32 mover = bp.CreateProxy(Aabb(-0.5f, 0.0f, -0.18f, 0.3f), reinterpret_cast<void*>(intptr_t(1)));
    const int32 partner = bp.CreateProxy(Aabb(-0.3f, 0.1f, 0.2f, 0.5f), reinterpret_cast<void*>(intptr_t(2)));
    const int32 far = bp.CreateProxy(Aabb(5.0f, 5.0f, 6.0f, 6.0f), reinterpret_cast<void*>(intptr_t(3)));
    const int32 farPartner =
        bp.CreateProxy(Aabb(5.5f, 5.5f, 6.5f, 6.5f), reinterpret_cast<void*>(intptr_t(4)));
    PairLog first;
    bp.UpdatePairs(&first);
    REQUIRE(first.pairs.count({1, 2}) == 1);
    bool unreachable = false;
    for (int k = 1; k < 200 && !unreachable; ++k)
    {
        // moves far enough to refatten, then back: the fat AABB is rebuilt from the tight one and d each time
        bp.MoveProxy(mover, Aabb(-0.5f, 0.0f, -0.18f, 0.3f), b2Vec2(float(k) * 1.0e-9f, 0.0f));
        PairLog log;
        bp.UpdatePairs(&log);
        unreachable = !Reachable(bp.GetFatAABB(mover).upperBound.x);
        if (!unreachable)
        {
            bp.MoveProxy(mover, Aabb(0.0f, 2.0f, 0.3f, 2.3f), b2Vec2(0.0f, 0.0f));
            bp.UpdatePairs(&log);
        }
    }
    REQUIRE(unreachable);
    REQUIRE(g_reports == 0);

    quadphase::SetValidation(bp, true);
    CHECK(g_reports == 0); // was: "cannot seed the shadow tree with proxy 0 ... exactly"

    // Steps after validation started: still no report, pairs of the other proxies compared, and the mover is
    // compared again once a move gives both trees the same fat AABB.
    for (int step = 0; step < 4; ++step)
    {
        bp.MoveProxy(partner, Aabb(-0.3f, 0.1f + 0.01f * float(step), 0.2f, 0.5f), b2Vec2(0.0f, 0.01f));
        const float x = 5.0f + 2.0f * float(step + 1);
        bp.MoveProxy(far, Aabb(x, 5.0f, x + 1.0f, 6.0f), b2Vec2(2.0f, 0.0f));
        bp.MoveProxy(farPartner, Aabb(x + 0.5f, 5.5f, x + 1.5f, 6.5f), b2Vec2(2.0f, 0.0f));
        PairLog log;
        bp.UpdatePairs(&log);
    }
    bp.MoveProxy(mover, Aabb(0.1f, 0.0f, 0.4f, 0.3f),
                 b2Vec2(0.5f, 0.0f)); // leaves its fat AABB: refattens in both
    PairLog last;
    bp.UpdatePairs(&last);
    CHECK(last.pairs.count({1, 2}) == 1);
    CheckValidatedCleanly(bp, 5);
}

TEST_CASE("b2BroadPhase: validation switched on after ShiftOrigin", "[validation]")
{
    ReportCounter reports;
    // An origin shift moves fat bounds to where no fl(t -+ 0.1) lands (negative upper bounds just above minus
    // a power of two). Search a shift that does it for some proxy (the test fails if none is found).
    for (int attempt = 0; attempt < 64; ++attempt)
    {
        b2BroadPhase bp;
        std::vector<int32> ids;
        for (int i = 0; i < 40; ++i)
        {
            const float x = float(i % 8) * 0.7f;
            const float y = float(i / 8) * 0.7f;
            ids.push_back(
                bp.CreateProxy(Aabb(x, y, x + 1.0f, y + 1.0f), reinterpret_cast<void*>(intptr_t(i + 1))));
        }
        PairLog first;
        bp.UpdatePairs(&first);
        bp.ShiftOrigin(b2Vec2(5.0f + 0.0371f * float(attempt), -1.0f));
        int unreachable = 0;
        for (int32 id : ids)
        {
            unreachable += Reachable(bp.GetFatAABB(id).upperBound.x) ? 0 : 1;
        }
        if (unreachable == 0)
        {
            continue;
        }
        quadphase::SetValidation(bp, true);
        CHECK(g_reports == 0); // was: "cannot seed the shadow tree with proxy ... exactly"
        for (int step = 0; step < 3; ++step)
        {
            for (size_t i = 0; i < ids.size(); i += 3)
            {
                const float x = float(i % 8) * 0.7f + 0.3f * float(step + 1);
                const float y = float(i / 8) * 0.7f;
                bp.MoveProxy(ids[i], Aabb(x, y, x + 1.0f, y + 1.0f), b2Vec2(0.3f, 0.0f));
            }
            PairLog log;
            bp.UpdatePairs(&log);
        }
        CheckValidatedCleanly(bp, 3);
        return;
    }
    FAIL("no origin shift gave a fat bound b2DynamicTree cannot reproduce");
}
