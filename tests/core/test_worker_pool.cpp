// SPDX-License-Identifier: MIT
// The library's worker pool (plugin/core/src/worker_pool.h): every item once, on the caller and the pool's threads;
// a second caller runs its own task while the pool is busy. (That worlds share its threads and that the last one
// destroyed ends them: tests/parallel/threads_test.cpp, which counts the process's threads.)
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "worker_pool.h"

using namespace quadphase;
using quadphase::detail::WorkerPool;

namespace
{

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
    "[worker_pool][concurrent]")
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

TEST_CASE("A caller that finds the pool busy runs its whole task on its own thread",
          "[worker_pool][concurrent]")
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
