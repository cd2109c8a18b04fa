// SPDX-License-Identifier: MIT
// Which threads the library starts, counted in the process (/proc/self/status, on Windows a snapshot of the system's
// threads; the pool's own threads by the name they carry, /proc/self/task/*/comm, on Windows GetThreadDescription).
// Each test case runs in a process of its own (see CMakeLists.txt), so that no earlier test has started a team
// already.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdint>
#include <cwchar>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

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

#if defined(_WIN32)
// How many of this process's threads `counts` (a function of the thread's id returning 0 or 1) counts, from a
// snapshot of the system's threads.
template <typename Counts>
int CountOwnThreads(Counts counts)
{
    const HANDLE snapshot = CreateToolhelp32Snapshot(TH32CS_SNAPTHREAD, 0);
    REQUIRE(snapshot != INVALID_HANDLE_VALUE);
    THREADENTRY32 entry;
    entry.dwSize = sizeof(entry);
    int count = 0;
    for (BOOL more = Thread32First(snapshot, &entry); more; more = Thread32Next(snapshot, &entry))
    {
        count += entry.th32OwnerProcessID == GetCurrentProcessId() ? counts(entry.th32ThreadID) : 0;
    }
    CloseHandle(snapshot);
    return count;
}
#endif

int ThreadCount()
{
#if defined(_WIN32)
    return CountOwnThreads([](DWORD) { return 1; });
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

// Threads named "quadphase": the library's pool (plugin/core/src/worker_pool.cpp names them: with glibc as it starts
// them, on Windows each worker itself as it starts, so count there with PoolThreadCountOnceSettled).
int PoolThreadCount()
{
#if defined(_WIN32)
    using GetThreadDescriptionFn = HRESULT(WINAPI*)(HANDLE, PWSTR*);
    const FARPROC proc = GetProcAddress(GetModuleHandleW(L"kernel32.dll"), "GetThreadDescription");
    REQUIRE(proc != nullptr); // Windows 10 1607 and later, and Wine, have it
    const auto getDescription = reinterpret_cast<GetThreadDescriptionFn>(reinterpret_cast<void (*)()>(proc));
    return CountOwnThreads([getDescription](DWORD id) {
        int named = 0;
        const HANDLE thread = OpenThread(THREAD_QUERY_LIMITED_INFORMATION, FALSE, id);
        PWSTR name = nullptr;
        if (thread != nullptr && SUCCEEDED(getDescription(thread, &name)) && name != nullptr)
        {
            named = std::wcscmp(name, L"quadphase") == 0 ? 1 : 0;
            LocalFree(name);
        }
        if (thread != nullptr)
        {
            CloseHandle(thread);
        }
        return named;
    });
#else
    int count = 0;
    for (const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
    {
        std::ifstream comm(task.path() / "comm");
        std::string name;
        std::getline(comm, name);
        count += name == "quadphase" ? 1 : 0;
    }
    return count;
#endif
}

// PoolThreadCount() once it equals `expected`, or after 5 s: a joined thread leaves /proc/self/task a moment after
// pthread_join returns.
int PoolThreadCountOnceSettled(int expected)
{
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    int count = PoolThreadCount();
    while (count != expected && std::chrono::steady_clock::now() < deadline)
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        count = PoolThreadCount();
    }
    return count;
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

TEST_CASE("with the defaults, a large scene starts the library's pool when it is built, not in a step",
          "[threads][warm]")
{
    const int before = ThreadCount();
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, 20000, 1);
    REQUIRE(quadphase::GetConfig(*scene.world).parallelMinProxies <= 20000);
    REQUIRE(quadphase::GetConfig(*scene.world).executor == quadphase::Executor::Pool);
    const int built = ThreadCount();
    CHECK(built == before + 2); // OMP_NUM_THREADS=3: the caller and two workers, started in CreateProxy
    CHECK(PoolThreadCountOnceSettled(2) == 2); // the pool's, none of OpenMP's
    const quadphase::Stats stats = StepScene(scene, 30);
    CHECK(stats.parallelCalls > 0); // the measured choice tried them at least
    CHECK(ThreadCount() == built);  // no step started one
}

TEST_CASE("with a game's task system, pair generation starts no thread of its own", "[threads][tasks]")
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

TEST_CASE("on the OpenMP executor the same scene starts OpenMP's team, and no pool", "[threads][openmp]")
{
    // The control of the tests above: the count does see OpenMP's threads when they are started.
    const int before = ThreadCount();
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, 4000, 1);
    quadphase::Config config = quadphase::GetConfig(*scene.world);
    config.threads = 3;
    config.executor = quadphase::Executor::OpenMP;
    quadphase::Configure(*scene.world, config);
    const quadphase::Stats stats = StepScene(scene, 60);
    REQUIRE(stats.parallelCalls > 0);
    CHECK(ThreadCount() > before);
    CHECK(PoolThreadCount() == 0);
}

TEST_CASE("worlds share the pool's threads, and the last world destroyed ends them", "[threads][teardown]")
{
    REQUIRE(PoolThreadCount() == 0);
    for (int round = 0; round < 20; ++round)
    {
        CAPTURE(round);
        {
            // Two worlds, each asking for 4 threads: the process gets 3 workers (the callers are the fourth), not 6.
            quadphase::scenes::Scene a =
                quadphase::scenes::BuildScene(SceneId::Particles, 2000, uint32_t(round));
            quadphase::scenes::Scene b = quadphase::scenes::BuildScene(SceneId::Rain, 2000, uint32_t(round));
            for (quadphase::scenes::Scene* scene : {&a, &b})
            {
                quadphase::Config config = quadphase::GetConfig(*scene->world);
                config.threads = 4;
                quadphase::Configure(*scene->world, config);
            }
            REQUIRE(PoolThreadCountOnceSettled(3) == 3);
            CHECK(StepScene(a, 5).parallelCalls > 0);
            CHECK(StepScene(b, 5).parallelCalls > 0);
            // A world that goes over to OpenMP lets go of the pool; the other one still holds it.
            quadphase::Config openmp = quadphase::GetConfig(*a.world);
            openmp.executor = quadphase::Executor::OpenMP;
            quadphase::Configure(*a.world, openmp);
            CHECK(PoolThreadCountOnceSettled(3) == 3);
        }
        REQUIRE(PoolThreadCountOnceSettled(0) == 0);
    }
}
