// SPDX-License-Identifier: MIT
// Determinism of parallel pair generation: the same scene stepped with any thread count, on the library's pool or
// under any OpenMP schedule, or on a game's job system with any worker count, gives bit-identical bodies, because
// FindPairs hands Box2D the same pairs in the same order.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstdlib>
#include <thread>
#include <vector>

#include "quadphase/box2d.h"
#include "quadphase_jobs/job_system.h"
#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::Executor;
using quadphase::Schedule;
using quadphase::scenes::SceneId;

struct RunResult
{
    std::vector<uint32_t> bodies; ///< quadphase::scenes::BodyStateBits at the end
    int64_t parallelCalls = 0;
    int64_t pairs = 0;
};

// 600 steps in the Release suite; the emulated (ARM64, Windows) and instrumented (ThreadSanitizer, AddressSanitizer)
// suites run 120 through QUADPHASE_DETERMINISM_STEPS.
int StepCount()
{
    const char* value = std::getenv("QUADPHASE_DETERMINISM_STEPS");
    return value != nullptr && std::atoi(value) > 0 ? std::atoi(value) : 600;
}

RunResult Run(SceneId id, int size, int threads, Schedule schedule, int chunk,
              const quadphase::TaskSystem& tasks = quadphase::TaskSystem{},
              Executor executor = Executor::OpenMP, uint32_t seed = 7)
{
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(id, size, seed);
    quadphase::Config config = quadphase::GetConfig(*scene.world);
    config.taskSystem = tasks;
    config.executor = executor;
    config.threads = threads;
    config.schedule = schedule;
    config.chunk = chunk;
    // every FindPairs with work takes the parallel path, even in these small scenes
    config.parallelThreshold = 0;
    quadphase::Configure(*scene.world, config);
    for (int step = 0, steps = StepCount(); step < steps; ++step)
    {
        quadphase::scenes::StepScene(scene);
    }
    const quadphase::Stats stats = quadphase::GetStats(*scene.world);
    return RunResult{quadphase::scenes::BodyStateBits(*scene.world), stats.parallelCalls,
                     stats.pairsReported};
}

// A parallel run against the serial one: it did run in parallel, and gave the same pairs and the same bodies.
void CheckParallelRun(const RunResult& run, const RunResult& serial)
{
    CHECK(run.parallelCalls > 0);
    CHECK(run.pairs == serial.pairs);
    CHECK((run.bodies == serial.bodies)); // not decomposed: no dump of two long vectors
}

// Steps each of three scenes (a GENERATE of the calling test case) at 1 thread and at 2-4 on `executor`, under each
// of `variants` (OpenMP's schedules; the pool has none), and checks the bodies against the serial run's.
struct Variant
{
    Schedule schedule;
    int chunk;
    const char* name;
};

void CheckThreadCounts(Executor executor, const std::vector<Variant>& variants)
{
    struct Case
    {
        SceneId id;
        int size;
    };
    const Case sceneCase =
        GENERATE(Case{SceneId::Rain, 1000}, Case{SceneId::Tumbler, 200}, Case{SceneId::Particles, 1000});
    CAPTURE(quadphase::scenes::SceneName(sceneCase.id), sceneCase.size);

    const RunResult serial = Run(sceneCase.id, sceneCase.size, 1, Schedule::Static, 0, {}, executor);
    REQUIRE(serial.parallelCalls == 0);
    REQUIRE(serial.pairs > 0);
    for (int threads = 2; threads <= 4; ++threads)
    {
        for (const Variant& v : variants)
        {
            CAPTURE(threads, v.name);
            CheckParallelRun(Run(sceneCase.id, sceneCase.size, threads, v.schedule, v.chunk, {}, executor),
                             serial);
        }
    }

    // A second run of the same configuration gives the same state again.
    const Variant& last = variants.back();
    const RunResult again = Run(sceneCase.id, sceneCase.size, 2, last.schedule, last.chunk, {}, executor);
    CHECK((again.bodies == serial.bodies));
}

} // namespace

TEST_CASE("bodies are bit-identical at 1-4 threads on the pool", "[parallel][determinism]")
{
    CheckThreadCounts(Executor::Pool, {{Schedule::Static, 0, "pool"}});
}

TEST_CASE("bodies are bit-identical at 1-4 threads under every OpenMP schedule",
          "[parallel][determinism][openmp]")
{
    CheckThreadCounts(Executor::OpenMP, {{Schedule::Static, 0, "static"},
                                         {Schedule::Dynamic, 1, "dynamic,1"},
                                         {Schedule::Guided, 0, "guided"},
                                         {Schedule::Auto, 0, "auto"}});
}

TEST_CASE("bodies are bit-identical on a game's job system at 1-4 workers", "[parallel][determinism][tasks]")
{
    const SceneId id = GENERATE(SceneId::Rain, SceneId::Particles);
    CAPTURE(quadphase::scenes::SceneName(id));
    const RunResult serial = Run(id, 1000, 1, Schedule::Static, 0);
    REQUIRE(serial.pairs > 0);
    using Caller = qpjobs::JobSystem::Caller;
    for (int workers = 1; workers <= 4; ++workers)
    {
        // Helps: the caller races the pool for ranges, as a game's main thread does. Waits: the pool runs every
        // split task, so the pool check below cannot lose that race.
        for (Caller caller : {Caller::Helps, Caller::Waits})
        {
            CAPTURE(workers, caller == Caller::Helps ? "helps" : "waits");
            qpjobs::JobSystem jobs(workers, caller);
            // threads = 0: the defaults (serial in a scene this small); 4 asks for every worker.
            for (int threads : {0, 4})
            {
                CAPTURE(threads);
                const int64_t before = jobs.RangesOnPool();
                const RunResult onJobs = Run(id, 1000, threads, Schedule::Static, 0, jobs.Tasks());
                CHECK(onJobs.pairs == serial.pairs);
                CHECK((onJobs.bodies == serial.bodies));
                if (workers > 1 && threads == 4)
                {
                    CHECK(onJobs.parallelCalls > 0);
                }
                if (workers > 1 && threads == 4 && caller == Caller::Waits)
                {
                    CHECK(jobs.RangesOnPool() > before); // the pool's threads really searched
                }
            }
        }
    }
}

// On a machine with fewer cores, 16 threads are oversubscribed: the blocks then run in whatever order the system
// schedules the threads, which the bodies must not depend on.
TEST_CASE("bodies are bit-identical at 16 threads on the pool, and on a job system of 15 workers",
          "[parallel][determinism][executors]")
{
    const SceneId id = GENERATE(SceneId::Rain, SceneId::Particles);
    CAPTURE(quadphase::scenes::SceneName(id));
    const RunResult serial = Run(id, 1000, 1, Schedule::Static, 0);
    REQUIRE(serial.pairs > 0);
    CheckParallelRun(Run(id, 1000, 16, Schedule::Static, 0, {}, Executor::Pool), serial);
    // Waits: the job system's 14 threads run every range of a split task.
    qpjobs::JobSystem jobs(15, qpjobs::JobSystem::Caller::Waits);
    CheckParallelRun(Run(id, 1000, 15, Schedule::Static, 0, jobs.Tasks()), serial);
    CHECK(jobs.RangesOnPool() > 0);
}

TEST_CASE("bodies are bit-identical at 16 threads on OpenMP", "[parallel][determinism][executors][openmp]")
{
    const SceneId id = GENERATE(SceneId::Rain, SceneId::Particles);
    CAPTURE(quadphase::scenes::SceneName(id));
    const RunResult serial = Run(id, 1000, 1, Schedule::Static, 0);
    REQUIRE(serial.pairs > 0);
    CheckParallelRun(Run(id, 1000, 16, Schedule::Dynamic, 1, {}, Executor::OpenMP), serial);
}

TEST_CASE(
    "two worlds stepped at once from two threads each get their serial bodies, sharing the library's pool",
    "[parallel][determinism][executors]")
{
    // The pool runs one task at a time: whichever world finds it busy searches its blocks on its own thread. Only
    // the time may depend on which; the bodies may not.
    const RunResult serialRain = Run(SceneId::Rain, 1000, 1, Schedule::Static, 0, {}, Executor::Pool, 11);
    const RunResult serialParticles =
        Run(SceneId::Particles, 1000, 1, Schedule::Static, 0, {}, Executor::Pool, 12);
    for (int round = 0; round < 2; ++round)
    {
        CAPTURE(round);
        RunResult rain;
        RunResult particles;
        std::thread other(
            [&rain] { rain = Run(SceneId::Rain, 1000, 2, Schedule::Static, 0, {}, Executor::Pool, 11); });
        particles = Run(SceneId::Particles, 1000, 3, Schedule::Static, 0, {}, Executor::Pool, 12);
        other.join();
        CHECK(rain.parallelCalls > 0);
        CHECK(particles.parallelCalls > 0);
        CHECK((rain.bodies == serialRain.bodies));
        CHECK((particles.bodies == serialParticles.bodies));
    }
}
