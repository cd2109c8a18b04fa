// SPDX-License-Identifier: MIT
// quadphase-jobs: pair generation on a game's own job system. Steps one scene twice, first on the library's own threads
// (Config::executor: its pool by default), then with a small job system of its own (support/job_system: a fixed pool of
// std::threads and a queue) handed over with quadphase::SetTaskSystem, and shows that the two simulations end
// bit-identical and that the pool's threads did the parallel work.
//
//   quadphase-jobs [WORKERS]     (default: the number of hardware threads, at least 2)
//
// Exit status: 0 when both runs end in the same state, 1 otherwise, 2 for a bad argument.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "quadphase/box2d.h"
#include "quadphase_jobs/job_system.h"
#include "quadphase_scenes/scenes.h"

namespace
{

using quadphase::scenes::SceneId;

constexpr int kSize = 20000; // particles: over Config::parallelMinProxies, where a second thread pays
constexpr int kSteps = 120;

struct Result
{
    uint64_t hash = 0;
    double seconds = 0.0;
    quadphase::Stats stats;
};

// Steps the scene with `workers` threads on every large call: the library's when `jobs` is null, else the job
// system's.
Result Run(int workers, qpjobs::JobSystem* jobs)
{
    quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(SceneId::Particles, kSize, 1);
    if (jobs != nullptr)
    {
        quadphase::SetTaskSystem(*scene.world, jobs->Tasks());
    }
    // Every worker on every large call, so that the pool's share shows; the default (0) chooses serial or parallel
    // by measurement. Both runs make the same calls (Configure rebuilds the quadtree), so they must end the same.
    quadphase::Config config = quadphase::GetConfig(*scene.world);
    config.threads = workers;
    quadphase::Configure(*scene.world, config);
    const auto start = std::chrono::steady_clock::now();
    for (int step = 0; step < kSteps; ++step)
    {
        quadphase::scenes::StepScene(scene);
    }
    Result r;
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    r.hash = quadphase::scenes::HashBodyPositions(*scene.world);
    r.stats = quadphase::GetStats(*scene.world);
    return r;
}

void Print(const char* name, const Result& r)
{
    std::printf("%-28s %8.1f ms  %7lld parallel of %7lld FindPairs calls  %9lld pairs  state %016llx\n", name,
                1e3 * r.seconds, (long long)r.stats.parallelCalls, (long long)r.stats.updatePairsCalls,
                (long long)r.stats.pairsReported, (unsigned long long)r.hash);
}

} // namespace

int main(int argc, char** argv)
{
    int workers = std::max(2, int(std::thread::hardware_concurrency()));
    if (argc > 2 || (argc == 2 && (workers = std::atoi(argv[1])) < 1))
    {
        std::fprintf(stderr, "usage: %s [WORKERS >= 1]\n", argv[0]);
        return 2;
    }
    std::printf("particles %d, %d steps\n", kSize, kSteps);
    const Result library = Run(workers, nullptr);
    Print(("library's pool, " + std::to_string(workers) + " threads").c_str(), library);

    qpjobs::JobSystem jobs(workers);
    const Result onJobs = Run(workers, &jobs);
    Print(("job system, " + std::to_string(workers) + " workers").c_str(), onJobs);
    std::printf("ranges run on the pool's threads: %lld\n", (long long)jobs.RangesOnPool());

    const bool same =
        onJobs.hash == library.hash && onJobs.stats.pairsReported == library.stats.pairsReported;
    std::printf("%s\n", same ? "bit-identical simulations" : "DIFFERENT simulations");
    return same ? 0 : 1;
}
