// SPDX-License-Identifier: MIT
// qp-step-stock / qp-step-quadtree: the in-engine step benchmark. One source, compiled against stock
// Box2D 2.4.1 (QUADPHASE_VARIANT_STOCK) and against Box2D with the quadtree broadphase
// (QUADPHASE_VARIANT_QUADPHASE); bench/bench.py runs the two alternately, in random order, within one
// invocation, and takes medians over repeats.
//
//   qp-step-<variant> --scene NAME --size N [--seed S] [--warmup W] [--steps S] [--threads T|default]
//                     [--ccd scene|on|off] [--json FILE] [--label TEXT] [--validate] [--timing]
//                     [--busy] [--jobs N] [--interval I [--max-growth PCT]]
//                     (--list prints the scenes: name, size range and default, then tab-separated what the size
//                     counts and a description)
//
// Builds the scene, steps it W times untimed (warm-up), then S timed steps, and appends one JSON line with,
// per timed step, the median and the mean of Box2D's own b2Profile fields (step, collide, solve, broadphase,
// solveTOI; milliseconds), for step and broadphase also p50 (the median again), p99 (nearest rank), the
// maximum and the total over the timed steps (a player sees the worst frames, not the median), the mean
// contact count, the new pairs per step that reached Box2D's contact filter (the same count in both builds),
// the process's peak resident memory (VmHWM) and, for the quadtree build, the quadtree's pairs reported,
// FindPairs time per step (Stats::pairSeconds), heap bytes per proxy (Stats::memoryBytes) and threads.
// --threads sets quadphase::Config::threads (0: OpenMP's default); "default" leaves the Config as the adapter
// made it (the library's defaults: parallel only from Config::parallelMinProxies proxies, on as many threads
// as OMP_NUM_THREADS allows); the stock build accepts 1 or default. --ccd sets
// b2World::SetContinuousPhysics (default "scene": as the scene built it; every scene leaves Box2D's default,
// on); the JSON line says which. The
// quadtree build's --validate checks every UpdatePairs against a shadow b2DynamicTree (exit status 1 on a
// mismatch) and --timing also times proxy updates; the side-by-side demo (scripts/demo.sh) uses both.
// --busy runs a second thread that spins from the warm-up to the last timed step, as a game's renderer
// would beside its physics thread. Over the timed steps the line also gives wall_s and the process's CPU time
// (user plus system, every thread: process_cpu_s), and cpu_s, that less the busy thread's own (busy_cpu_s):
// what the physics and its broadphase took from the machine, worker threads spinning or waiting included.
// --jobs N (quadtree build) hands pair generation to a job system of N workers (quadphase_jobs/job_system.h: a
// std::thread pool) through quadphase::SetTaskSystem, as a game with its own job system would; --threads still
// applies (with --threads default, the library's defaults decide whether a step goes parallel at all).
//
// --interval I (the soak, scripts/soak.sh): prints resident memory from the start to the end of the run (warm-up
// and timed steps, counted together): a line at step 0, after the warm-up, every I steps and at the last step,
// each with step, bodies, proxies, VmRSS, VmHWM (KiB) and, in the quadtree build, the broadphase's own heap
// (Stats::memoryBytes; -1 in stock). The warm-up here is the soak's: the first interval, or 10% of the run if
// shorter. Exit status 1 when VmRSS at the end exceeds VmRSS after it by more than --max-growth percent (default
// 10). The timed steps keep a few numbers per step, so a soak runs as warm-up (--warmup N-1 --steps 1).
//
// Phases (of the timed steps, from the world's state after each step, untimed): with D dynamic bodies,
// "falling" while fewer than 1% of them touch a static body (nothing has landed yet: in rain, until the
// bottom row of the spawn grid reaches the floor), "resting" once fewer than 5% are awake and faster than 0.5
// m/s, "piling" in between. A step's phase never goes back (falling, piling, resting in that order), so each
// phase is one range of steps; the line gives each phase's first step, step count and the medians of
// b2Profile step and broadphase over its steps. The builds create new contacts in different orders (equally
// valid), so their simulations, and their phases' ranges, may drift apart.
//
// b2Profile::broadphase is the time b2World::Solve spends after the solver synchronising fixtures (MoveProxy
// of every awake body's proxies) and in FindNewContacts (UpdatePairs, its AddPair callbacks creating
// contacts); the time-of-impact phase's broadphase work is in solveTOI. The time inside the broadphase alone
// is measured by the replay (qp-replay*), on a recorded trace of the same scene.
#include <algorithm>
#include <atomic>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "box2d/box2d.h"
#include "quadphase_scenes/scenes.h"
#include "quadphase_tools/counting_filter.h"
#include "tool_common.h"

#include "box2d_variant.h"
#include "phase.h"
#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase_jobs/job_system.h"
#endif

namespace
{

using namespace qpbench;

/// A field of /proc/self/status in KiB ("VmRSS:", "VmHWM:"); -1 when unknown.
long StatusKiB(const char* field)
{
    return std::atol(ProcField("/proc/self/status", field, "-1").c_str());
}

struct PhaseSamples
{
    int first = -1;
    std::vector<double> step, broadphase;
};

} // namespace

int main(int argc, char** argv)
{
    namespace scenes = quadphase::scenes;
    const Args args(argc, argv, "qp-step-" + std::string(kVariant),
                    {"scene", "size", "seed", "warmup", "steps", "threads", "ccd", "json", "label", "jobs",
                     "interval", "max-growth"},
                    {"list", "per-step", "validate", "timing", "busy"});
    if (args.Has("list"))
    {
        for (const scenes::SceneInfo& info : scenes::AllScenes())
        {
            std::printf("%s %d %d %d\t%s\t%s\n", info.name, info.minSize, info.maxSize, info.defaultSize,
                        info.sizeMeaning, info.description);
        }
        return 0;
    }
    const std::string ccd = args.Get("ccd", "scene");
    const std::string threads = args.Get("threads", "1");
    const bool validate = args.Has("validate"), timing = args.Has("timing"), busy = args.Has("busy");
    const int jobs = int(args.GetIntIn("jobs", 0, 0, 256));
    const long interval = args.GetIntIn("interval", 0, 0, 100000000); // 0: no memory lines
    const double maxGrowth = double(args.GetIntIn("max-growth", 10, 0, 10000));
    args.Check(
        args.Has("scene") && args.Has("size") && (ccd == "scene" || ccd == "on" || ccd == "off") &&
            (kQuadtree || !(validate || timing || jobs > 0)),
        "usage: qp-step-%s --scene NAME --size N [--seed S] [--warmup W] [--steps S]"
        " [--threads T|default]\n"
        "       [--ccd scene|on|off] [--json FILE] [--label TEXT] [--per-step] [--validate] [--timing]\n"
        "       [--busy] [--jobs N] [--interval I [--max-growth PCT]]\n"
        "       (--list: scene names and size ranges; --validate, --timing, --jobs: quadtree build only)\n"
        "scenes: %s\n",
        kVariant, scenes::SceneNameList().c_str());
    const auto sceneId = scenes::ParseSceneName(args.Get("scene"));
    if (!sceneId)
    {
        Die(2, "qp-step-%s: unknown scene '%s' (%s)\n", kVariant, args.Get("scene").c_str(),
            scenes::SceneNameList().c_str());
    }
    const int size = int(args.GetInt("size", 0));
    const uint32_t seed = uint32_t(args.GetInt("seed", 1));
    const int warmup = int(args.GetInt("warmup", 30));
    const int steps = int(args.GetInt("steps", 60));
    if (warmup < 0 || steps <= 0)
    {
        Die(2, "qp-step-%s: --warmup must be >= 0 and --steps > 0\n", kVariant);
    }

    CountingFilter filter; // outlives the world
#if QUADPHASE_VARIANT_QUADPHASE
    std::unique_ptr<qpjobs::JobSystem> jobSystem; // outlives the world too (SetTaskSystem's contract)
#endif
    scenes::Scene scene;
    const long rssBeforeKiB = StatusKiB("VmRSS:");
    const int64_t build0 = NowNs();
    try
    {
        scene = scenes::BuildScene(*sceneId, size, seed);
    }
    catch (const std::exception& e)
    {
        Die(2, "qp-step-%s: %s\n", kVariant, e.what());
    }
    const double buildSeconds = double(NowNs() - build0) * 1e-9;
    b2World& world = *scene.world;
    world.SetContactFilter(&filter);
    if (ccd != "scene")
    {
        world.SetContinuousPhysics(ccd == "on");
    }
    ApplyThreads(world, threads);
#if QUADPHASE_VARIANT_QUADPHASE
    if (validate)
    {
        quadphase::SetValidation(world, true);
    }
    if (timing)
    {
        quadphase::SetTiming(world, true);
    }
    if (jobs > 0)
    {
        jobSystem = std::make_unique<qpjobs::JobSystem>(jobs);
        quadphase::SetTaskSystem(world, jobSystem->Tasks());
    }
#endif
    std::atomic<bool> stopBusy{false};
    std::thread busyThread;
    if (busy)
    {
        busyThread = std::thread([&stopBusy] {
            volatile uint64_t spins = 0; // work the compiler cannot drop
            while (!stopBusy.load(std::memory_order_relaxed))
            {
                spins = spins + 1;
            }
        });
    }

    // --interval: resident memory after `done` steps of the run, when due (see the top of the file).
    const long total = long(warmup) + steps, warmStep = std::min(interval, total / 10);
    long startKiB = 0, warmKiB = 0, endKiB = 0;
    const auto memoryLine = [&](long done) {
        if (interval == 0 || (done != 0 && done != warmStep && done % interval != 0 && done != total))
        {
            return;
        }
        long heapKiB = -1;
#if QUADPHASE_VARIANT_QUADPHASE
        heapKiB = long(quadphase::GetStats(world).memoryBytes / 1024);
#endif
        endKiB = StatusKiB("VmRSS:");
        std::printf("%10ld %8d %8d %10ld %10ld %12ld\n", done, world.GetBodyCount(), world.GetProxyCount(),
                    endKiB, StatusKiB("VmHWM:"), heapKiB);
        std::fflush(stdout);
        startKiB = done == 0 ? endKiB : startKiB;
        warmKiB = done == warmStep ? endKiB : warmKiB;
    };
    if (interval > 0)
    {
        std::printf("qp-step-%s: %ld steps, size %d, seed %u; world: scene library \"%s\": %s\n", kVariant,
                    total, size, seed, args.Get("scene").c_str(), scenes::GetSceneInfo(*sceneId).description);
        std::printf("%10s %8s %8s %10s %10s %12s\n", "step", "bodies", "proxies", "VmRSS_KiB", "VmHWM_KiB",
                    "bp_heap_KiB");
        std::printf("(before building the world: VmRSS %ld KiB)\n", rssBeforeKiB);
        memoryLine(0);
    }

    Phase phase = Falling;
    double contactsAll = 0.0; // over the warm-up steps too
    const int64_t run0 = NowNs();
    for (int s = 0; s < warmup; ++s)
    {
        scenes::StepScene(scene);
        contactsAll += world.GetContactCount();
        phase = Classify(world, phase);
        memoryLine(s + 1);
    }
#if QUADPHASE_VARIANT_QUADPHASE
    quadphase::ResetCounters(world);
#endif
    const int64_t filtered0 = filter.calls;
    std::vector<double> step, collide, solve, broadphase, toi;
    PhaseSamples phases[PhaseCount];
    // per step: for comparing phases over the same steps in both builds
    std::vector<int> stepPhase, stepAwake;
    double contacts = 0.0;
    // The busy thread's CPU is read on its own clock, so that cpu_s leaves it out.
    const auto busyCpu = [&] {
        return busy ? ThreadCpuSeconds(busyThread.native_handle()) : 0.0;
    };
    const double cpu0 = ProcessCpuSeconds(), busyCpu0 = busyCpu();
    const int64_t t0 = NowNs();
    for (int s = 0; s < steps; ++s)
    {
        scenes::StepScene(scene);
        const b2Profile& p = world.GetProfile();
        step.push_back(p.step);
        collide.push_back(p.collide);
        solve.push_back(p.solve);
        broadphase.push_back(p.broadphase);
        toi.push_back(p.solveTOI);
        contacts += world.GetContactCount();
        contactsAll += world.GetContactCount();
        int awake = 0;
        phase = Classify(world, phase, &awake); // outside b2Profile (wall_s includes it)
        PhaseSamples& ph = phases[phase];
        ph.first = ph.first < 0 ? warmup + s : ph.first;
        ph.step.push_back(p.step);
        ph.broadphase.push_back(p.broadphase);
        stepPhase.push_back(int(phase));
        stepAwake.push_back(awake);
        memoryLine(warmup + s + 1);
    }
    const int64_t end = NowNs();
    const double processCpu = ProcessCpuSeconds() - cpu0, busyCpuUsed = busyCpu() - busyCpu0;
    if (busy)
    {
        stopBusy.store(true);
        busyThread.join();
    }
    const double wall = double(end - t0) * 1e-9;
    const double growth = warmKiB > 0 ? 100.0 * double(endKiB - warmKiB) / double(warmKiB) : 0.0;
    if (interval > 0)
    {
        std::printf("qp-step-%s: VmRSS start %ld KiB, after warm-up (step %ld) %ld KiB, end %ld KiB (%+.1f%% "
                    "since the warm-up), peak %ld KiB\n",
                    kVariant, startKiB, warmStep, warmKiB, endKiB, growth, StatusKiB("VmHWM:"));
    }
    char positionHash[32];
    std::snprintf(positionHash, sizeof positionHash, "%016" PRIx64, scenes::HashBodyPositions(world));

    JsonLine j;
    j.Str("tool", "qp-step")
        .Str("variant", kVariant)
        .Str("label", args.Get("label"))
        .Str("scene", args.Get("scene"))
        .Int("size", size)
        .Int("seed", seed)
        .Int("warmup", warmup)
        .Int("steps", steps)
        .Int("threads", threads == "default" ? 0 : std::atoi(threads.c_str()))
        .Str("threads_arg", threads)
        .Int("omp_num_threads", OmpNumThreadsEnv())
        .Int("continuous", world.GetContinuousPhysics() ? 1 : 0)
        .Int("bodies", scenes::CountBodies(world))
        .Int("fixtures", scenes::CountFixtures(world))
        .Int("proxies", world.GetProxyCount())
        .Num("step_ms", Median(step))
        .Num("collide_ms", Median(collide))
        .Num("solve_ms", Median(solve))
        .Num("broadphase_ms", Median(broadphase))
        .Num("toi_ms", Median(toi))
        .Num("step_ms_mean", Mean(step))
        .Num("collide_ms_mean", Mean(collide))
        .Num("solve_ms_mean", Mean(solve))
        .Num("broadphase_ms_mean", Mean(broadphase))
        .Num("toi_ms_mean", Mean(toi))
        .Num("step_ms_p50", Median(step))
        .Num("step_ms_p99", Quantile(step, 0.99))
        .Num("step_ms_max", Quantile(step, 1.0))
        .Num("step_ms_total", Mean(step) * steps)
        .Num("broadphase_ms_p50", Median(broadphase))
        .Num("broadphase_ms_p99", Quantile(broadphase, 0.99))
        .Num("broadphase_ms_max", Quantile(broadphase, 1.0))
        .Num("broadphase_ms_total", Mean(broadphase) * steps)
        .Int("busy", busy ? 1 : 0)
        .Int("jobs", jobs)
        .Num("contacts_mean", contacts / steps)
        .Num("new_pairs_per_step", double(filter.calls - filtered0) / steps)
        .Int("new_pairs", filter.calls - filtered0)
        .Int("new_pairs_all_steps", filter.calls)
        .Num("contacts_mean_all_steps", contactsAll / (warmup + steps))
        .Int("contacts_end", world.GetContactCount())
        .Str("position_hash", positionHash)
        .Num("build_s", buildSeconds)
        .Num("run_s", double(end - run0) * 1e-9)
        .Num("wall_s", wall)
        .Num("cpu_s", processCpu - busyCpuUsed)
        .Num("process_cpu_s", processCpu)
        .Num("busy_cpu_s", busyCpuUsed)
        .Int("peak_rss_bytes", PeakRss());
    if (args.Has("per-step"))
    {
        j.Array("steps_step_ms", step)
            .Array("steps_bp_ms", broadphase)
            .Array("steps_phase", stepPhase)
            .Array("steps_awake", stepAwake);
    }
    for (int k = 0; k < PhaseCount; ++k)
    {
        const std::string name = kPhaseName[k];
        j.Int((name + "_first").c_str(), phases[k].first)
            .Int((name + "_steps").c_str(), int64_t(phases[k].step.size()))
            .Num((name + "_step_ms").c_str(), Median(phases[k].step))
            .Num((name + "_broadphase_ms").c_str(), Median(phases[k].broadphase));
    }
    int status = interval > 0 && growth > maxGrowth ? 1 : 0;
#if QUADPHASE_VARIANT_QUADPHASE
    const quadphase::Stats st = quadphase::GetStats(world);
    j.Num("pairs_reported_per_step", double(st.pairsReported) / steps)
        .Int("qt_depth", st.depth)
        .Num("qt_parallel_calls_per_step", double(st.parallelCalls) / steps)
        .Num("qt_serial_by_choice_per_step", double(st.serialByChoice) / steps)
        .Num("qt_find_ms_per_step", 1000.0 * st.pairSeconds / steps)
        .Int("bp_bytes", st.memoryBytes)
        .Num("bp_bytes_per_proxy", double(st.memoryBytes) / std::max(1, st.proxyCount))
        .Num("qt_leaf_size", st.leafSize)
        .Int("qt_proxies", st.proxyCount)
        .Int("qt_outside", st.outsideCount)
        .Int("qt_occupied_cells", st.occupiedCells)
        .Int("qt_largest_cell", st.largestCell)
        .Int("qt_rebuilds", st.rebuilds)
        .Int("qt_update_pairs_calls", st.updatePairsCalls)
        .Int("qt_pairs_reported", st.pairsReported)
        .Int("qt_proxies_queried", st.proxiesQueried)
        .Num("qt_update_ms_per_step", timing ? 1000.0 * st.updateSeconds / steps : NAN);
    if (validate)
    {
        const quadphase::ValidationReport v = quadphase::GetValidationReport(world);
        j.Int("validation_checks", v.checks)
            .Int("validation_pairs_compared", v.pairsCompared)
            .Int("validation_mismatches", v.mismatches)
            .Str("validation_first_mismatch", v.firstMismatch);
        if (v.mismatches != 0 || v.checks == 0)
        {
            status = 1;
            std::fprintf(stderr, "qp-step-%s: validation FAILED (see validation_* in the JSON line)\n",
                         kVariant);
        }
        if (interval > 0)
        {
            std::printf("qp-step-%s: validation %lld checks, %lld pairs, %lld mismatches\n", kVariant,
                        (long long)v.checks, (long long)v.pairsCompared, (long long)v.mismatches);
        }
    }
#endif
    AppendLine(args.Get("json"), j.Text());
    std::printf("%s %s %d: step %.3f ms, broadphase %.3f ms (medians over %d steps), %.0f contacts, peak RSS "
                "%.1f MB\n",
                kVariant, args.Get("scene").c_str(), size, Median(step), Median(broadphase), steps,
                contacts / steps, double(PeakRss()) / 1048576.0);
    if (interval > 0)
    {
        std::printf(growth > maxGrowth ? "qp-step-%s: FAIL: resident memory grew by more than %.0f%%\n"
                                       : "qp-step-%s: memory flat (within %.0f%% of the warm-up)\n",
                    kVariant, maxGrowth);
    }
    return status;
}
