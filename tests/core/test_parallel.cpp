// SPDX-License-Identifier: MIT
// Parallel pair generation gives the serial loop's output, pair for pair and in order, at any thread count, on any
// executor and under any schedule (and the brute-force reference's set, which the harness checks on every
// FindPairs).
#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "harness.h"
#include "quadphase_jobs/job_system.h"

using namespace quadphase;
using namespace qptest;

namespace
{

std::vector<std::vector<Pair>> PairHistory(HarnessSettings s, int threads, Schedule schedule, int chunk,
                                           int64_t& parallelCalls, bool queueMoves = false,
                                           const TaskSystem& tasks = TaskSystem{},
                                           Executor executor = Executor::Pool)
{
    s.queueMoves = queueMoves;
    s.config.taskSystem = tasks;
    s.config.executor = executor;
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

// The serial loop's pair history (one thread: no parallel call), the reference of every parallel run.
std::vector<std::vector<Pair>> SerialHistory(const HarnessSettings& s, bool queueMoves = false)
{
    int64_t parallelCalls = 0;
    std::vector<std::vector<Pair>> history =
        PairHistory(s, 1, Schedule::Static, 0, parallelCalls, queueMoves);
    REQUIRE(parallelCalls == 0);
    return history;
}

// Task systems that run every range on the calling thread, in an order of their own, or that break the contract.
struct InlineTasks
{
    enum class Mode
    {
        Reverse, // every item, one range per item, last item first
        SkipOdd, // only the even items: a broken job system
        Outside, // every item, plus one range past the end: a broken job system
        Twice,   // every item twice: a broken job system
    };
    Mode mode = Mode::Reverse;
    int ranges = 0;
    int enqueues = 0;
    // enqueueTask call number throwAt (counted from 1) throws std::runtime_error, running nothing
    int throwAt = 0;

    static void* Enqueue(TaskCallback* task, int itemCount, int minRange, void* context, void* user)
    {
        auto* self = static_cast<InlineTasks*>(user);
        REQUIRE(minRange >= 1);
        if (++self->enqueues == self->throwAt)
        {
            throw std::runtime_error("job system failure");
        }
        for (int i = itemCount - 1; i >= 0; --i)
        {
            if (self->mode != Mode::SkipOdd || i % 2 == 0)
            {
                task(i, i + 1, unsigned(i % 4), context);
                ++self->ranges;
            }
        }
        if (self->mode == Mode::Twice)
        {
            task(0, itemCount, 0u, context);
        }
        if (self->mode == Mode::Outside)
        {
            task(itemCount, itemCount + 2, 0u, context);
        }
        return self; // a handle: finishTask must be called with it
    }
    static void Finish(void* handle, void* user) { REQUIRE(handle == user); }

    TaskSystem Get()
    {
        TaskSystem tasks;
        tasks.enqueueTask = &Enqueue;
        tasks.finishTask = &Finish;
        tasks.workerCount = 4;
        tasks.userContext = this;
        return tasks;
    }
};

// 800 proxies: several blocks of 64 buffered proxies per FindPairs.
HarnessSettings TaskCase(uint32_t seed, int operations)
{
    HarnessSettings s = RunSettings(seed, Dist::Uniform, 800, operations);
    s.validateEvery = operations - 500;
    return s;
}

// Calls check(settings, serial history, threads) at 2-4 threads on two cases of 800 proxies (several blocks of 64
// buffered proxies per FindPairs), whose serial loop finds more than 1000 pairs.
template <typename Check>
void ForThreadCounts(Check check)
{
    for (Dist dist : {Dist::Uniform, Dist::LogMixed})
    {
        HarnessSettings s = RunSettings(91000u + uint32_t(int(dist)), dist, 800, 2500);
        s.validateEvery = 2000;
        INFO("case: " << Describe(s));

        const std::vector<std::vector<Pair>> serial = SerialHistory(s);
        size_t pairs = 0;
        for (const std::vector<Pair>& call : serial)
        {
            pairs += call.size();
        }
        REQUIRE(pairs > 1000);
        for (int threads = 2; threads <= 4; ++threads)
        {
            CAPTURE(threads);
            check(s, serial, threads);
        }
    }
}

} // namespace

TEST_CASE("A task system's ranges, run in any order, give the serial loop's output", "[parallel][tasks]")
{
    const HarnessSettings s = TaskCase(94000u, 2500);
    const std::vector<std::vector<Pair>> serial = SerialHistory(s);
    int64_t parallelCalls = 0;

    InlineTasks tasks;
    for (int threads : {0, 2, 4})
    {
        CAPTURE(threads);
        tasks.ranges = 0;
        const std::vector<std::vector<Pair>> onTasks =
            PairHistory(s, threads, Schedule::Static, 0, parallelCalls, false, tasks.Get());
        REQUIRE(onTasks == serial);
        if (threads > 1)
        {
            CHECK(parallelCalls > 0);
            CHECK(tasks.ranges > 0);
        }
    }
}

TEST_CASE("A task system that skips items or runs items out of range loses no pair and is reported",
          "[parallel][tasks][errors]")
{
    const HarnessSettings s = TaskCase(94100u, 1500);
    const std::vector<std::vector<Pair>> serial = SerialHistory(s);
    int64_t parallelCalls = 0;
    for (InlineTasks::Mode mode : {InlineTasks::Mode::SkipOdd, InlineTasks::Mode::Outside})
    {
        CAPTURE(int(mode));
        ErrorCounter errors;
        InlineTasks tasks;
        tasks.mode = mode;
        const std::vector<std::vector<Pair>> onTasks =
            PairHistory(s, 4, Schedule::Static, 0, parallelCalls, false, tasks.Get());
        REQUIRE(parallelCalls > 0);
        REQUIRE(onTasks == serial);
        // Out of range: every call. Skipped odd items: the calls of two blocks or more.
        if (mode == InlineTasks::Mode::Outside)
        {
            CHECK(errors.Count(ErrorCode::TaskSystemMisuse) == parallelCalls);
        }
        else
        {
            CHECK(errors.Count(ErrorCode::TaskSystemMisuse) > 0);
            CHECK(errors.Count(ErrorCode::TaskSystemMisuse) <= parallelCalls);
        }
    }
}

namespace
{

// 3,000 proxies in a 150 m square, in a quadtree of `config` and in the brute-force reference.
struct MovingWorld
{
    static constexpr int kProxies = 3000;
    const FatPolicy policy{};
    QuadtreeBroadPhase qt;
    BruteForceBroadPhase brute;
    std::mt19937 rng;
    std::vector<Box> tight;
    std::vector<ProxyId> ids;

    MovingWorld(const Config& config, uint32_t seed) : qt(policy, config), brute(policy), rng(seed)
    {
        std::uniform_real_distribution<float> pos(0.0f, 150.0f), size(0.1f, 1.5f);
        for (int i = 0; i < kProxies; ++i)
        {
            const float x = pos(rng), y = pos(rng);
            const float w = size(rng), h = size(rng);
            tight.push_back(Box{x, y, x + w, y + h});
            ids.push_back(qt.CreateProxy(tight.back(), nullptr));
            REQUIRE(brute.CreateProxy(tight.back(), nullptr) == ids.back());
        }
    }

    // Moves proxy i by up to `reach` on each axis, with QueueMove or the Box2D adapter's way (the fat-box test at
    // the call, QueueFatMove when the box changed).
    void Move(int i, float reach, bool fatMoves)
    {
        std::uniform_real_distribution<float> step(-reach, reach);
        const Vec2 d{step(rng), step(rng)};
        Box& t = tight[size_t(i)];
        t = Box{t.minX + d.x, t.minY + d.y, t.maxX + d.x, t.maxY + d.y};
        if (fatMoves)
        {
            Box fat;
            bool sane = false;
            if (!KeptAndSaneSimd(policy, qt.GetPool().Fat(ids[size_t(i)]), &t.minX, &t.maxX, d, fat, sane))
            {
                REQUIRE(sane);
                qt.QueueFatMove(ids[size_t(i)], t, fat);
            }
        }
        else
        {
            qt.QueueMove(ids[size_t(i)], t, d);
        }
        brute.MoveProxy(ids[size_t(i)], t, d);
    }

    // The quadtree's FindPairs, in its order, once its set was checked against the reference's.
    std::vector<Pair> FindPairsChecked()
    {
        std::vector<Pair> pairs, reference;
        qt.FindPairs(pairs);
        brute.FindPairs(reference);
        std::vector<Pair> sorted = pairs;
        std::sort(sorted.begin(), sorted.end());
        std::sort(reference.begin(), reference.end());
        reference.erase(std::unique(reference.begin(), reference.end()), reference.end());
        REQUIRE(sorted == reference);
        return pairs;
    }
};

// Every one of 3,000 proxies, or a third of them, moved between two FindPairs calls (MovingWorld::Move): queues of
// 1,000 to 3,000 moves, applied in blocks on the executor when FindPairs runs in parallel. Each call's pairs are
// checked against the brute-force reference's set; returns the pair history, and Validate()'s answer at the end in
// `invalid`.
std::vector<std::vector<Pair>> MassMoves(bool fatMoves, int threads, const TaskSystem& tasks,
                                         Executor executor, std::string& invalid)
{
    Config config;
    config.threads = threads;
    config.taskSystem = tasks;
    config.executor = executor;
    config.parallelThreshold = 0;
    MovingWorld world(config, 96000u);
    std::vector<std::vector<Pair>> history;
    for (int round = 0; round < 12; ++round)
    {
        for (int i = round % 3 == 2 ? round % 3 : 0; i < MovingWorld::kProxies; i += round % 3 == 2 ? 3 : 1)
        {
            world.Move(i, 0.7f, fatMoves);
        }
        CAPTURE(round);
        history.push_back(world.FindPairsChecked());
    }
    invalid = world.qt.Validate();
    return history;
}

} // namespace

TEST_CASE("Thousands of queued moves are applied in blocks on every executor, with the serial loop's pairs "
          "and order",
          "[parallel][tasks][executors][concurrent]")
{
    for (bool fatMoves : {false, true})
    {
        CAPTURE(fatMoves);
        std::string invalid;
        const std::vector<std::vector<Pair>> serial =
            MassMoves(fatMoves, 1, TaskSystem{}, Executor::Pool, invalid);
        REQUIRE(invalid.empty());
        size_t pairs = 0;
        for (const std::vector<Pair>& call : serial)
        {
            pairs += call.size();
        }
        REQUIRE(pairs > 1000);
        std::vector<Executor> executors{Executor::Pool};
        if (OpenMPAvailable())
        {
            executors.push_back(Executor::OpenMP);
        }
        for (Executor executor : executors)
        {
            for (int threads : {2, 4, 16})
            {
                CAPTURE(int(executor), threads);
                REQUIRE(MassMoves(fatMoves, threads, TaskSystem{}, executor, invalid) == serial);
                REQUIRE(invalid.empty());
            }
        }
        {
            qpjobs::JobSystem jobs(15, qpjobs::JobSystem::Caller::Helps);
            REQUIRE(MassMoves(fatMoves, 15, jobs.Tasks(), Executor::Pool, invalid) == serial);
            REQUIRE(invalid.empty());
            CHECK(jobs.RangesOnPool() > 0);
        }
        // Two task-system calls per FindPairs (the apply's blocks, then the search's), and a broken job system
        // loses nothing: each block runs once, the misuse is reported.
        for (InlineTasks::Mode mode : {InlineTasks::Mode::Reverse, InlineTasks::Mode::SkipOdd,
                                       InlineTasks::Mode::Outside, InlineTasks::Mode::Twice})
        {
            CAPTURE(int(mode));
            ErrorCounter errors;
            InlineTasks tasks;
            tasks.mode = mode;
            REQUIRE(MassMoves(fatMoves, 4, tasks.Get(), Executor::Pool, invalid) == serial);
            REQUIRE(invalid.empty());
            CHECK(tasks.enqueues == 2 * int(serial.size()));
            CHECK((errors.Count(ErrorCode::TaskSystemMisuse) > 0) == (mode != InlineTasks::Mode::Reverse));
        }
    }
}

// A job system whose enqueueTask throws while FindPairs applies a queue of thousands of moves in blocks (before any
// block ran): the exception reaches the caller, the broadphase stays valid, and the next FindPairs reports the pairs
// of every queued move, as the brute-force reference does.
TEST_CASE("A task system that throws during the queued moves' apply loses no move",
          "[parallel][tasks][errors]")
{
    for (bool fatMoves : {false, true})
    {
        CAPTURE(fatMoves);
        InlineTasks tasks;
        Config config;
        config.threads = 4;
        config.taskSystem = tasks.Get();
        config.parallelThreshold = 0;
        MovingWorld world(config, 97000u);
        REQUIRE(world.FindPairsChecked().size() > 500);
        for (int i = 0; i < MovingWorld::kProxies; ++i)
        {
            world.Move(i, 2.0f, fatMoves);
        }
        tasks.throwAt = tasks.enqueues + 1; // the apply's blocks: the first task of the next FindPairs
        std::vector<Pair> pairs;
        REQUIRE_THROWS_AS(world.qt.FindPairs(pairs), std::runtime_error);
        REQUIRE(tasks.ranges > 0); // the earlier call ran on the task system
        REQUIRE(pairs.empty());
        REQUIRE(world.qt.Validate() == "");
        REQUIRE(world.FindPairsChecked().size() > 1000);
        REQUIRE(world.qt.Validate() == "");
    }
}

// The documented fallback of Config::threads: the build's CMake says whether it was built with OpenMP
// (QUADPHASE_TEST_OPENMP), so that a build which lost OpenMP unnoticed fails here instead of running serially.
TEST_CASE("threads > 1 without a task system runs on the pool in every build, and on OpenMP or, in a build "
          "without it, serially and unreported",
          "[parallel][fallback]")
{
    REQUIRE(OpenMPAvailable() == bool(QUADPHASE_TEST_OPENMP));
    const HarnessSettings s = TaskCase(94200u, 1500);
    const std::vector<std::vector<Pair>> serial = SerialHistory(s);
    for (Executor executor : {Executor::Pool, Executor::OpenMP})
    {
        CAPTURE(int(executor));
        ErrorCounter errors;
        HarnessSettings four = s;
        four.config.executor = executor;
        four.config.threads = 4;
        four.config.parallelThreshold = 0;
        Harness h(four);
        h.Record(true);
        h.Run();
        REQUIRE(h.History() == serial);
        CHECK(h.Quadtree().GetConfig().threads == 4); // kept as given, in either build
        CHECK(errors.Total() == 0);
        const bool parallel = executor == Executor::Pool || OpenMPAvailable();
        CHECK((h.Quadtree().GetStats().parallelCalls > 0) == parallel);
    }
}

TEST_CASE("A half-set task system is rejected with a clear error and changes nothing",
          "[parallel][tasks][errors]")
{
    QuadtreeBroadPhase qt;
    const ProxyId a = qt.CreateProxy(Box{0.0f, 0.0f, 1.0f, 1.0f}, nullptr);
    Config config = qt.GetConfig();
    InlineTasks inlineTasks;
    const TaskSystem good = inlineTasks.Get();
    TaskSystem noFinish = good;
    noFinish.finishTask = nullptr;
    TaskSystem noWorkers = good;
    noWorkers.workerCount = 0;
    for (const TaskSystem& bad : {noFinish, noWorkers})
    {
        config.taskSystem = bad;
        REQUIRE_THROWS_AS(qt.Configure(config), std::invalid_argument);
        REQUIRE_THROWS_WITH(QuadtreeBroadPhase(FatPolicy{}, config),
                            Catch::Contains("enqueueTask, finishTask"));
        CHECK(qt.GetConfig().taskSystem.enqueueTask == nullptr);
    }
    REQUIRE(qt.GetFatBox(a).maxX >= 1.0f);
    REQUIRE(qt.Validate() == "");
}

TEST_CASE("Parallel FindPairs equals the serial loop at 1-4 threads on the pool", "[parallel]")
{
    ForThreadCounts([](const HarnessSettings& s, const std::vector<std::vector<Pair>>& serial, int threads) {
        int64_t parallelCalls = 0;
        const std::vector<std::vector<Pair>> pool =
            PairHistory(s, threads, Schedule::Static, 0, parallelCalls, false, TaskSystem{}, Executor::Pool);
        CHECK(parallelCalls > 0);
        REQUIRE(pool == serial);
    });
}

TEST_CASE("Parallel FindPairs equals the serial loop at 1-4 threads under every OpenMP schedule",
          "[parallel][openmp]")
{
    ForThreadCounts([](const HarnessSettings& s, const std::vector<std::vector<Pair>>& serial, int threads) {
        const Schedule schedules[] = {Schedule::Static, Schedule::Dynamic, Schedule::Guided, Schedule::Auto};
        for (Schedule schedule : schedules)
        {
            const std::vector<int> chunks =
                schedule == Schedule::Dynamic ? std::vector<int>{0, 1} : std::vector<int>{0};
            for (int chunk : chunks)
            {
                CAPTURE(int(schedule), chunk);
                int64_t parallelCalls = 0;
                const std::vector<std::vector<Pair>> parallel = PairHistory(
                    s, threads, schedule, chunk, parallelCalls, false, TaskSystem{}, Executor::OpenMP);
                CHECK(parallelCalls > 0);
                REQUIRE(parallel == serial);
            }
        }
    });
}

TEST_CASE("Queued moves give MoveProxy's pairs, in one order at 1-4 threads", "[parallel]")
{
    // Queued moves update the entries that stay in their cell when they are applied, so a proxy moved twice
    // between two FindPairs can reach the stale list at another position than with MoveProxy, and a cell's
    // entries another order: the pair sets are MoveProxy's, the order is the queue's own, the same at any thread
    // count.
    for (Dist dist : {Dist::Uniform, Dist::Clustered})
    {
        // 800 proxies: batches of up to 266 moves, searched in parallel (threshold 0)
        HarnessSettings s = RunSettings(93000u + uint32_t(int(dist)), dist, 800, 2500);
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

TEST_CASE(
    "At 16 threads every executor gives the serial loop's output, and so does a job system of 15 workers",
    "[parallel][executors][concurrent]")
{
    // 16 threads on a machine with fewer cores is oversubscribed: the ranges then run in whatever order the
    // system schedules the threads, which is what the output must not depend on.
    for (Dist dist : {Dist::Uniform, Dist::Clustered})
    {
        HarnessSettings s = RunSettings(95000u + uint32_t(int(dist)), dist, 2000, 1500);
        s.validateEvery = 1000;
        INFO("case: " << Describe(s));
        for (bool queueMoves : {false, true})
        {
            CAPTURE(queueMoves);
            const std::vector<std::vector<Pair>> reference = SerialHistory(s, queueMoves);
            int64_t parallelCalls = 0;
            // OpenMP where the build has it ([fallback] checks that it has what its CMake says).
            std::vector<Executor> executors{Executor::Pool};
            if (OpenMPAvailable())
            {
                executors.push_back(Executor::OpenMP);
            }
            for (Executor executor : executors)
            {
                CAPTURE(int(executor));
                const std::vector<std::vector<Pair>> parallel = PairHistory(
                    s, 16, Schedule::Dynamic, 1, parallelCalls, queueMoves, TaskSystem{}, executor);
                CHECK(parallelCalls > 0);
                REQUIRE(parallel == reference);
            }
            // Waits: the caller leaves every range of a split task to the job system's 14 threads.
            for (qpjobs::JobSystem::Caller caller :
                 {qpjobs::JobSystem::Caller::Helps, qpjobs::JobSystem::Caller::Waits})
            {
                qpjobs::JobSystem jobs(15, caller);
                const std::vector<std::vector<Pair>> onJobs =
                    PairHistory(s, 15, Schedule::Static, 0, parallelCalls, queueMoves, jobs.Tasks());
                CHECK(parallelCalls > 0);
                CHECK(jobs.RangesOnPool() > 0);
                REQUIRE(onJobs == reference);
            }
        }
    }
}

TEST_CASE("Each executor is chosen through Configure, and switching executors mid-run keeps the pairs",
          "[parallel][executors]")
{
    HarnessSettings s = TaskCase(95100u, 2000);
    const std::vector<std::vector<Pair>> serial = SerialHistory(s);
    REQUIRE(Config{}.executor == Executor::Pool); // the default: threads that sleep between steps

    s.config.threads = 3;
    s.config.parallelThreshold = 0;
    Harness h(s);
    h.Record(true);
    // Run()'s operations, with the executor switched every 250 of them
    for (int op = 0; op < s.operations; ++op)
    {
        if (op % 250 == 0)
        {
            Config c = h.Quadtree().GetConfig();
            c.executor = (op / 250) % 2 == 0 ? Executor::OpenMP : Executor::Pool;
            h.Quadtree().Configure(c);
            REQUIRE(h.Quadtree().GetConfig().executor == c.executor);
        }
        h.RandomOperation();
    }
    h.FindPairs();
    CHECK(h.Quadtree().GetStats().parallelCalls > 0);
    REQUIRE(h.History() == serial);
}
