// SPDX-License-Identifier: MIT
// Which threads the library starts, counted in the process (/proc/self/status; on Windows a snapshot of the
// system's threads). Each test case runs in a process of its own (see CMakeLists.txt), so that no earlier test has started OpenMP's team already.
#include <catch2/catch.hpp>

#include <cstdint>
#include <fstream>
#include <string>

#include "quadphase/box2d.h"
#include "quadphase_jobs/job_system.h"
#include "quadphase_scenes/scenes.h"

#if defined(_WIN32)
#define WIN32_LEAN_AND_MEAN
#include <windows.h>

#include <tlhelp32.h> // after windows.h, which it needs
#endif

namespace
{

using quadphase::scenes::SceneId;

int ThreadCount()
{
#if defined(_WIN32)
    const HANDLE snapshot = CreateToolhelp32Snapshot(TH32CS_SNAPTHREAD, 0);
    REQUIRE(snapshot != INVALID_HANDLE_VALUE);
    THREADENTRY32 entry;
    entry.dwSize = sizeof(entry);
    int count = 0;
    for (BOOL more = Thread32First(snapshot, &entry); more; more = Thread32Next(snapshot, &entry))
    {
        count += entry.th32OwnerProcessID == GetCurrentProcessId() ? 1 : 0;
    }
    CloseHandle(snapshot);
    return count;
#else
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
    {
        if (line.rfind("Threads:", 0) == 0)
        {
            return std::stoi(line.substr(8));
        }
    }
    FAIL("no Threads: line in /proc/self/status");
    return -1;
#endif
}

quadphase::Stats StepScene(quadphase::scenes::Scene& scene, int steps)
{
    for (int step = 0; step < steps; ++step)
    {
        quadphase::scenes::StepScene(scene);
    }
    return quadphase::GetStats(*scene.world);
}

} // namespace

TEST_CASE("with the defaults, a scene under the work threshold starts no thread", "[threads][defaults]")
{
    const int before = ThreadCount();
    // A pyramid of 55 boxes: every FindPairs has fewer buffered proxies than Config::parallelThreshold (128).
    quadphase::scenes::Scene pyramid = quadphase::scenes::BuildScene(SceneId::Pyramid, 10, 1);
    const quadphase::Stats small = StepScene(pyramid, 300);
    REQUIRE(small.pairsReported > 0);
    CHECK(small.parallelCalls == 0);
    CHECK(ThreadCount() == before);

    // 4,000 bodies: most calls buffer more than parallelThreshold proxies, but the scene is under
    // Config::parallelMinProxies, where a second thread did not pay.
    quadphase::scenes::Scene rain = quadphase::scenes::BuildScene(SceneId::Rain, 4000, 1);
    const quadphase::Stats mid = StepScene(rain, 120);
    REQUIRE(mid.proxiesQueried > 128 * 60);
    CHECK(mid.parallelCalls == 0);
    CHECK(ThreadCount() == before);
}

TEST_CASE("with the defaults, a large scene starts OpenMP's team when it is built, not in a step",
          "[threads][warm]")
{
    const int before = ThreadCount();
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, 20000, 1);
    REQUIRE(quadphase::GetConfig(*scene.world).parallelMinProxies <= 20000);
    const int built = ThreadCount();
    CHECK(built > before); // started in CreateProxy, between steps
    StepScene(scene, 30);
    CHECK(ThreadCount() == built); // no step started one
}

TEST_CASE("with a game's task system, pair generation starts no OpenMP thread", "[threads][tasks]")
{
    // its two pool threads exist before the count; the caller Waits, so the pool surely runs the ranges
    qpjobs::JobSystem jobs(3, qpjobs::JobSystem::Caller::Waits);
    const int before = ThreadCount();
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, 4000, 1);
    quadphase::SetTaskSystem(*scene.world, jobs.Tasks());
    quadphase::Config config = quadphase::GetConfig(*scene.world); // the task system included
    config.threads = 3; // every large call parallel, whatever the measured choice would say
    quadphase::Configure(*scene.world, config);
    const quadphase::Stats stats = StepScene(scene, 60);
    REQUIRE(stats.parallelCalls > 0);
    CHECK(jobs.RangesOnPool() > 0);
    CHECK(ThreadCount() == before);
}

TEST_CASE("without a task system the same scene does start OpenMP's team", "[threads][openmp]")
{
    // The control of the test above: the count does see OpenMP's threads when they are started.
    const int before = ThreadCount();
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, 4000, 1);
    quadphase::Config config = quadphase::GetConfig(*scene.world);
    config.threads = 3;
    quadphase::Configure(*scene.world, config);
    const quadphase::Stats stats = StepScene(scene, 60);
    REQUIRE(stats.parallelCalls > 0);
    CHECK(ThreadCount() > before);
}
