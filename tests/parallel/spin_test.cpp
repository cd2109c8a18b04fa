// SPDX-License-Identifier: MIT
// No spinning: after a parallel step, the library's threads take no CPU while the game sleeps until its next frame.
// The process's CPU time (every thread's) is read across a 50 ms sleep of the caller, after steps whose pair search
// ran in parallel. Each test case runs in a process of its own (see CMakeLists.txt): a process in which OpenMP's
// team once ran keeps it, spinning or not.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "quadphase/box2d.h"
#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::Executor;

// CPU a sleep of 50 ms may see in the whole process, in ms: far above what the process used with the pool (medians
// 0.02-0.04 ms on 2 cores: the clock reads, and the workers going back to sleep), far below libgomp's spin at its
// default wait policy (medians 1.3-8 ms, no sample under 0.7 ms; docs/design.md, "Parallel pair generation").
constexpr double kIdleCpuLimitMs = 0.25;

double ProcessCpuMs()
{
    timespec now{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
    return 1e3 * double(now.tv_sec) + 1e-6 * double(now.tv_nsec);
}

// The process's CPU (ms) during 7 sleeps of 50 ms, sorted, each right after a step whose FindPairs ran in parallel
// on `executor` (2 threads, every large call parallel): a game's frame, then its wait for the next one.
std::vector<double> CpuDuringSleepsMs(Executor executor)
{
    quadphase::scenes::Scene scene =
        quadphase::scenes::BuildScene(quadphase::scenes::SceneId::Particles, 4000, 1);
    quadphase::Config config = quadphase::GetConfig(*scene.world);
    config.threads = 2;
    config.executor = executor;
    quadphase::Configure(*scene.world, config);
    std::vector<double> samples;
    for (int step = 0; step < 300 && samples.size() < 7; ++step)
    {
        const int64_t before = quadphase::GetStats(*scene.world).parallelCalls;
        quadphase::scenes::StepScene(scene);
        if (quadphase::GetStats(*scene.world).parallelCalls > before)
        {
            const double start = ProcessCpuMs();
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
            samples.push_back(ProcessCpuMs() - start);
        }
    }
    std::sort(samples.begin(), samples.end());
    return samples;
}

std::string Describe(const std::vector<double>& samples)
{
    std::ostringstream text;
    text << "CPU during each 50 ms sleep (ms, sorted):";
    for (double ms : samples)
    {
        text << " " << ms;
    }
    return text.str();
}

} // namespace

TEST_CASE("after a parallel step on the default executor, the process takes no CPU while the caller sleeps",
          "[spin][pool]")
{
    REQUIRE(quadphase::Config{}.executor == Executor::Pool);
    const std::vector<double> samples = CpuDuringSleepsMs(Executor::Pool);
    INFO(Describe(samples));
    REQUIRE(samples.size() == 7);
    CHECK(samples[3] < kIdleCpuLimitMs); // the median
}

TEST_CASE("the same measurement sees OpenMP's threads spin at its default wait policy", "[spin][openmp]")
{
    // The control of the test above: the measurement does see threads that spin after a step, so the test above
    // can fail. libgomp reads its wait policy from the environment when it is loaded, and spins less when it has
    // fewer cores than threads.
    for (const char* name : {"OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "KMP_BLOCKTIME"})
    {
        if (std::getenv(name) != nullptr)
        {
            WARN(name << " is set: OpenMP's threads may not spin; the control is skipped");
            return;
        }
    }
    if (std::thread::hardware_concurrency() < 2)
    {
        WARN("fewer than 2 cores: libgomp spins only briefly with more threads than cores; the control is "
             "skipped");
        return;
    }
    const std::vector<double> samples = CpuDuringSleepsMs(Executor::OpenMP);
    INFO(Describe(samples));
    REQUIRE(samples.size() == 7);
    CHECK(samples[3] > kIdleCpuLimitMs);
}
