// The library's worker pool (plugin/core/src/worker_pool.h): every item once, on the caller and the pool's threads;
// a second caller runs its own task while the pool is busy; threads shared by every broadphase and joined when the
// last one goes.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "quadphase/quadtree_broad_phase.h"
#include "test_support.h"
#include "worker_pool.h"

using namespace quadphase;
using quadphase::detail::WorkerPool;

namespace
{

// The pool's threads, by the name they give themselves (glibc), or -1 where the system cannot say.
int PoolThreadsRunning()
{
#if defined(__linux__) && defined(__GLIBC__)
    int count = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
    {
        std::ifstream comm(task.path() / "comm");
        std::string name;
        std::getline(comm, name);
        count += name == "quadphase" ? 1 : 0;
    }
    return count;
#else
    return -1;
#endif
}

// PoolThreadsRunning() once it equals `expected`, or after 5 s: a joined thread leaves /proc/self/task a moment
// after pthread_join returns.
int PoolThreadsOnceSettled(int expected)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    int running = PoolThreadsRunning();
    while (running != expected && std::chrono::steady_clock::now() < deadline)
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        running = PoolThreadsRunning();
    }
    return running;
}

// Runs one task through the TaskSystem callbacks, as FindPairs does.
void RunTask(const TaskSystem& tasks, TaskCallback* task, int items, void* context)
{
    void* handle = tasks.enqueueTask(task, items, 1, context, tasks.userContext);
    if (handle != nullptr)
    {
        tasks.finishTask(handle, tasks.userContext);
    }
}

using Clock = std::chrono::steady_clock;

// Items that count how often each ran and on which worker index. With `waitForWorker`, the caller's first item
// waits (10 s at most) until a pool thread has run an item, so that a pool whose threads never join is caught, on
// any machine load.
struct CountingTask
{
    CountingTask(int items, int workers, bool waitForWorker)
        : runs(size_t(items)), byWorker(size_t(workers)), waited(!waitForWorker)
    {
    }

    std::vector<std::atomic<int>> runs;
    std::vector<std::atomic<int>> byWorker;
    std::atomic<int> outOfRangeWorker{0};
    std::atomic<bool> waited;

    static void Run(int start, int end, unsigned worker, void* context)
    {
        auto* self = static_cast<CountingTask*>(context);
        if (worker >= self->byWorker.size())
        {
            self->outOfRangeWorker.fetch_add(1);
            return;
        }
        self->byWorker[worker].fetch_add(end - start);
        for (int i = start; i < end; ++i)
        {
            self->runs[size_t(i)].fetch_add(1);
        }
        if (worker == 0 && !self->waited.exchange(true))
        {
            const Clock::time_point deadline = Clock::now() + std::chrono::seconds(10);
            while (self->OnWorkers() == 0 && Clock::now() < deadline)
            {
                std::this_thread::sleep_for(std::chrono::microseconds(100));
            }
        }
    }

    int OnWorkers() const
    {
        int sum = 0;
        for (size_t w = 1; w < byWorker.size(); ++w)
        {
            sum += byWorker[w].load();
        }
        return sum;
    }
};

} // namespace

TEST_CASE(
    "The pool runs every item once, on the caller and its threads, with worker indices below workerCount",
    "[worker_pool]")
{
    std::shared_ptr<WorkerPool> pool = WorkerPool::Shared();
    REQUIRE(pool->Reserve(3) >= 3);
    for (int participants : {1, 2, 4})
    {
        CAPTURE(participants);
        WorkerPool::Tasks tasks(pool.get(), participants);
        const TaskSystem system = tasks.Get();
        REQUIRE(system.workerCount == participants);
        for (int round = 0; round < 20; ++round)
        {
            const int items = 1 + round * 37;
            const bool shared = participants > 1 && items > 1;
            CountingTask counting(items, participants, shared);
            RunTask(system, &CountingTask::Run, items, &counting);
            for (int i = 0; i < items; ++i)
            {
                REQUIRE(counting.runs[size_t(i)].load() == 1);
            }
            REQUIRE(counting.outOfRangeWorker.load() == 0);
            if (!shared)
            {
                REQUIRE(counting.OnWorkers() == 0); // nothing to share: all on the caller
            }
            else
            {
                REQUIRE(counting.OnWorkers() > 0); // the caller's first item waited for a pool thread
            }
        }
    }
    // Without a pool (a broadphase that never reached its threads): everything on the caller.
    WorkerPool::Tasks alone(nullptr, 4);
    CountingTask counting(100, 4, false);
    RunTask(alone.Get(), &CountingTask::Run, 100, &counting);
    CHECK(counting.byWorker[0].load() == 100);
}

TEST_CASE("A caller that finds the pool busy runs its whole task on its own thread", "[worker_pool]")
{
    std::shared_ptr<WorkerPool> pool = WorkerPool::Shared();
    REQUIRE(pool->Reserve(2) >= 2);

    // Task A's items block until released, so the pool stays busy with it.
    struct Blocking
    {
        std::atomic<int> started{0};
        std::atomic<bool> release{false};
        static void Run(int, int, unsigned, void* context)
        {
            auto* self = static_cast<Blocking*>(context);
            self->started.fetch_add(1);
            const Clock::time_point deadline = Clock::now() + std::chrono::seconds(10);
            while (!self->release.load() && Clock::now() < deadline)
            {
                std::this_thread::sleep_for(std::chrono::microseconds(100));
            }
        }
    } blocking;
    std::thread first([&] {
        WorkerPool::Tasks tasks(pool.get(), 3);
        RunTask(tasks.Get(), &Blocking::Run, 8, &blocking);
    });
    const Clock::time_point deadline = Clock::now() + std::chrono::seconds(10);
    while (blocking.started.load() == 0 && Clock::now() < deadline)
    {
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    REQUIRE(blocking.started.load() > 0);

    WorkerPool::Tasks tasks(pool.get(), 3);
    const TaskSystem system = tasks.Get();
    CountingTask counting(50, 3, false); // no pool thread can come: do not wait for one
    void* handle = system.enqueueTask(&CountingTask::Run, 50, 1, &counting, system.userContext);
    CHECK(handle == nullptr); // ran to completion in enqueueTask
    CHECK(counting.byWorker[0].load() == 50);
    blocking.release = true;
    first.join();
    CHECK(blocking.started.load() == 8);

    // And once free, the pool takes tasks again.
    CountingTask after(50, 3, true);
    RunTask(system, &CountingTask::Run, 50, &after);
    CHECK(after.OnWorkers() > 0);
}

TEST_CASE("Broadphases share one pool, and its threads end with the last broadphase that holds it",
          "[worker_pool]")
{
    if (PoolThreadsRunning() < 0)
    {
        WARN("the pool's threads cannot be counted on this system: skipped");
        return;
    }
    REQUIRE(PoolThreadsOnceSettled(0) == 0); // the earlier test cases' pools are gone with their holders

    Config config;
    config.threads = 4;
    config.parallelThreshold = 0;
    qptest::Rng rng(96000u);
    std::vector<Box> boxes;
    for (int i = 0; i < 600; ++i)
    {
        const float x = qptest::Uniform(rng, 0.0f, 40.0f);
        const float y = qptest::Uniform(rng, 0.0f, 40.0f);
        boxes.push_back(Box{x, y, x + 1.5f, y + 1.5f});
    }
    auto pairsOf = [&boxes](const Config& c) {
        QuadtreeBroadPhase qt(FatPolicy{}, c);
        for (const Box& b : boxes)
        {
            qt.CreateProxy(b, nullptr);
        }
        std::vector<Pair> pairs;
        qt.FindPairs(pairs);
        return pairs;
    };
    Config serial = config;
    serial.threads = 1;
    const std::vector<Pair> expected = pairsOf(serial);
    REQUIRE(expected.size() > 100);
    CHECK(PoolThreadsRunning() == 0); // one thread starts none

    for (int round = 0; round < 40; ++round)
    {
        CAPTURE(round);
        {
            // Two at once: the threads are the pool's, not each broadphase's.
            QuadtreeBroadPhase a(FatPolicy{}, config);
            QuadtreeBroadPhase b(FatPolicy{}, config);
            REQUIRE(PoolThreadsRunning() == 3);
            for (const Box& box : boxes)
            {
                a.CreateProxy(box, nullptr);
                b.CreateProxy(box, nullptr);
            }
            std::vector<Pair> pairsA;
            std::vector<Pair> pairsB;
            a.FindPairs(pairsA);
            b.FindPairs(pairsB);
            REQUIRE(pairsA == expected);
            REQUIRE(pairsB == expected);
            REQUIRE(a.GetStats().parallelCalls == 1);
            // A broadphase that goes over to OpenMP lets go of the pool; the other still holds it.
            Config openmp = config;
            openmp.executor = Executor::OpenMP;
            a.Configure(openmp);
            REQUIRE(PoolThreadsRunning() == 3);
        }
        REQUIRE(PoolThreadsOnceSettled(0) == 0);
    }
}
