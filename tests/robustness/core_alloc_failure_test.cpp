// SPDX-License-Identifier: MIT
// std::bad_alloc inside FindPairs, at every allocation it makes, on 2 threads (the library's pool's, and OpenMP's
// where the build has it): the exception must reach the caller (an exception that leaves a worker thread or an
// OpenMP region ends the program),
// the broadphase must stay valid, and the next FindPairs must report every pair a twin that never failed reports:
// nothing queued or buffered is lost.
// This executable replaces the global operator new, so it is kept apart from the other tests.
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "quadtree_broad_phase.h"

namespace
{

// Allocation number k (counted from 1 after Arm(k)) throws std::bad_alloc, once. 0: never.
std::atomic<long> g_countdown{0};
std::atomic<long> g_failures{0};

void Arm(long k)
{
    g_countdown.store(k);
}

} // namespace

void* operator new(std::size_t size)
{
    if (g_countdown.load(std::memory_order_relaxed) > 0 && g_countdown.fetch_sub(1) == 1)
    {
        g_failures.fetch_add(1);
        throw std::bad_alloc();
    }
    void* p = std::malloc(size == 0 ? 1 : size);
    if (p == nullptr)
    {
        throw std::bad_alloc();
    }
    return p;
}

// Every unaligned form goes to the same malloc and free, so that a sanitizer runtime (which supplies the forms not
// replaced here) never frees with free what its own operator new allocated.
void* operator new[](std::size_t size)
{
    return operator new(size);
}

void* operator new(std::size_t size, const std::nothrow_t&) noexcept
{
    try
    {
        return operator new(size);
    }
    catch (const std::bad_alloc&)
    {
        return nullptr;
    }
}

void* operator new[](std::size_t size, const std::nothrow_t&) noexcept
{
    return operator new(size, std::nothrow);
}

void operator delete(void* p) noexcept
{
    std::free(p);
}

void operator delete(void* p, std::size_t) noexcept
{
    std::free(p);
}

void operator delete[](void* p) noexcept
{
    std::free(p);
}

void operator delete[](void* p, std::size_t) noexcept
{
    std::free(p);
}

void operator delete(void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}

void operator delete[](void* p, const std::nothrow_t&) noexcept
{
    std::free(p);
}

using namespace quadphase;

namespace
{

Box RandomBox(std::mt19937& rng, float world)
{
    std::uniform_real_distribution<float> at(0.0f, world);
    std::uniform_real_distribution<float> half(0.05f, 1.5f);
    const float x = at(rng), y = at(rng), h = half(rng);
    return Box{x - h, y - h, x + h, y + h};
}

std::vector<Pair> Sorted(std::vector<Pair> pairs)
{
    for (Pair& p : pairs)
    {
        if (p.a > p.b)
        {
            std::swap(p.a, p.b);
        }
    }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    return pairs;
}

// Fails allocation 1, 2, ... of FindPairs on 2 threads of `executor` until a call gets through, over 6 steps' moves.
// The moves are QueueMove's, or with `fatMoves` QueueFatMove's (the Box2D adapter's: the caller's fat-box test, and
// only the moves whose fat box changed), whose apply lists the queue itself and borrows the stale list's tail.
void CheckFindPairsAllocFailures(Executor executor, bool fatMoves)
{
    CAPTURE(executor == Executor::Pool ? "pool" : "openmp");
    CAPTURE(fatMoves);
    g_failures.store(0);
    Config config;
    config.executor = executor;
    config.threads = 2;           // parallel calls whatever the machine measures
    config.parallelThreshold = 8; // and for small batches too
    QuadtreeBroadPhase failing(FatPolicy{}, config);
    QuadtreeBroadPhase twin(FatPolicy{}, config);
    std::mt19937 rng(2026u);
    const float world = 120.0f;
    std::vector<ProxyId> ids;
    for (int i = 0; i < 6000; ++i)
    {
        const Box b = RandomBox(rng, world);
        ids.push_back(failing.CreateProxy(b, nullptr));
        REQUIRE(twin.CreateProxy(b, nullptr) == ids.back());
    }
    std::vector<Pair> a, b;
    failing.FindPairs(a);
    twin.FindPairs(b);
    REQUIRE(Sorted(a) == Sorted(b));

    long thrown = 0;
    long parallelCalls = 0;
    for (int round = 0; round < 6; ++round)
    {
        // A step's moves: most bodies drift, some jump across the world (cell changes, stale entries).
        std::uniform_real_distribution<float> drift(-0.3f, 0.3f);
        for (ProxyId id : ids)
        {
            const Box old = twin.GetFatBox(id);
            Box to;
            if (rng() % 10 == 0)
            {
                to = RandomBox(rng, world);
            }
            else
            {
                const float dx = drift(rng), dy = drift(rng);
                to = Box{old.minX + 0.1f + dx, old.minY + 0.1f + dy, old.maxX - 0.1f + dx,
                         old.maxY - 0.1f + dy};
            }
            if (fatMoves)
            {
                const Box fat = MovedFatBox(failing.GetPolicy(), to, Vec2{0.0f, 0.0f});
                if (!KeepsFatBox(failing.GetPolicy(), old, to, fat))
                {
                    failing.QueueFatMove(id, to, fat);
                    twin.QueueFatMove(id, to, fat);
                }
            }
            else
            {
                failing.QueueMove(id, to, Vec2{0.0f, 0.0f});
                twin.QueueMove(id, to, Vec2{0.0f, 0.0f});
            }
        }
        b.clear();
        twin.FindPairs(b);
        // Fail at allocation 1, then 2, ... until a FindPairs gets through.
        for (long k = 1;; ++k)
        {
            a.clear();
            Arm(k);
            bool threw = false;
            try
            {
                failing.FindPairs(a);
            }
            catch (const std::bad_alloc&)
            {
                threw = true;
            }
            Arm(0);
            INFO("round " << round << ", failure at allocation " << k);
            REQUIRE(failing.Validate() == "");
            if (!threw)
            {
                REQUIRE(Sorted(a) == Sorted(b));
                break;
            }
            ++thrown;
            REQUIRE(a.empty()); // nothing half-reported
            REQUIRE(k < 100000);
        }
        parallelCalls = failing.GetStats().parallelCalls;
    }
    // The failures did happen, and the searches did run in parallel regions.
    CHECK(thrown > 6);
    CHECK(g_failures.load() == thrown);
    CHECK(parallelCalls > 0);
}

} // namespace

TEST_CASE("std::bad_alloc at any allocation of FindPairs on 2 threads: thrown to the caller, nothing lost",
          "[alloc]")
{
    // The pool runs in every build; OpenMP only where the build has it (Executor::OpenMP is serial without it).
    for (const bool fatMoves : {false, true})
    {
        CheckFindPairsAllocFailures(Executor::Pool, fatMoves);
        if (OpenMPAvailable())
        {
            CheckFindPairsAllocFailures(Executor::OpenMP, fatMoves);
        }
    }
}

TEST_CASE("std::bad_alloc in CreateProxy, DestroyProxy, ShiftOrigin and Configure: all or nothing", "[alloc]")
{
    QuadtreeBroadPhase failing(FatPolicy{}, Config{});
    QuadtreeBroadPhase twin(FatPolicy{}, Config{});
    std::mt19937 rng(7u);
    std::vector<ProxyId> live;
    long thrown = 0;
    // Each call is tried with a failure at its 1st, 2nd, ... allocation until it gets through; a call that threw
    // must have changed nothing (same proxy count, valid), and the twin, which never fails, must end identical.
    auto attempt = [&](const char* what, auto&& call) {
        for (long k = 1;; ++k)
        {
            const int32_t before = failing.GetProxyCount();
            Arm(k);
            try
            {
                call();
                Arm(0);
                return;
            }
            catch (const std::bad_alloc&)
            {
                Arm(0);
                ++thrown;
                INFO(what << ": failure at allocation " << k << ", proxies " << before);
                REQUIRE(failing.GetProxyCount() == before);
                REQUIRE(failing.Validate() == "");
            }
            REQUIRE(k < 100000);
        }
    };
    for (int i = 0; i < 3000; ++i)
    {
        const Box b = RandomBox(rng, 150.0f);
        ProxyId id = -1;
        attempt("CreateProxy", [&] { id = failing.CreateProxy(b, nullptr); });
        REQUIRE(twin.CreateProxy(b, nullptr) == id);
        live.push_back(id);
        if (rng() % 4 == 0)
        {
            const size_t k = rng() % live.size();
            const ProxyId victim = live[k];
            attempt("DestroyProxy", [&] { failing.DestroyProxy(victim); });
            twin.DestroyProxy(victim);
            live.erase(live.begin() + std::ptrdiff_t(k));
        }
    }
    attempt("ShiftOrigin", [&] { failing.ShiftOrigin(Vec2{3.0f, -2.0f}); });
    twin.ShiftOrigin(Vec2{3.0f, -2.0f});
    Config coarse;
    coarse.depth = 3;
    attempt("Configure", [&] { failing.Configure(coarse); });
    twin.Configure(coarse);
    std::vector<Pair> a, b;
    failing.FindPairs(a);
    twin.FindPairs(b);
    CHECK(thrown > 100);
    REQUIRE(failing.GetProxyCount() == twin.GetProxyCount());
    REQUIRE(Sorted(a) == Sorted(b));
    REQUIRE(failing.Validate() == "");
}
