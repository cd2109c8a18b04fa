// qp-soak / qp-soak-stock: a long run of the scene library's churn world (bodies created and destroyed every
// step) with resident memory printed at the start, at intervals and at the end, to show that memory stays
// flat.
//
//   qp-soak [--steps N] [--size S] [--seed K] [--interval I] [--validate] [--max-growth PCT]
//
// Prints one line per interval: step, bodies, proxies, VmRSS, VmHWM (and, in the quadphase build, the
// broadphase's own heap bytes). Exit status 1 when VmRSS at the end exceeds VmRSS after the warm-up (the
// first interval, or 10% of the run) by more than --max-growth percent (default 10), else 0.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "quadphase_scenes/scenes.h"
#include "tool_common.h"
#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include "quadphase/box2d.h"
#endif

namespace
{

constexpr const char* kUsage =
    "usage: qp-soak [--steps N] [--size S] [--seed K] [--interval I] [--validate] [--max-growth PCT]\n";

[[noreturn]] void Usage(const std::string& error)
{
    qpbench::Die(2, "qp-soak: %s\n%s", error.c_str(), kUsage);
}

/// A field of /proc/self/status in KiB ("VmRSS:", "VmHWM:"); -1 when unknown. C stdio: a std::ifstream would
/// add its own few hundred KiB to the figures.
long ProcStatusKiB(const char* field)
{
    long kib = -1;
    if (std::FILE* f = std::fopen("/proc/self/status", "r"))
    {
        char line[256];
        while (kib < 0 && std::fgets(line, sizeof(line), f) != nullptr)
        {
            kib = std::strncmp(line, field, std::strlen(field)) == 0 ? std::atol(line + std::strlen(field))
                                                                     : -1;
        }
        std::fclose(f);
    }
    return kib;
}

/// Resident memory of this process: now (VmRSS) and its peak so far (VmHWM).
struct Rss
{
    long currentKiB = ProcStatusKiB("VmRSS:");
    long peakKiB = ProcStatusKiB("VmHWM:");
};

} // namespace

int main(int argc, char** argv)
{
    namespace scenes = quadphase::scenes;
    const qpbench::Args args(argc, argv, "qp-soak", {"steps", "size", "seed", "interval", "max-growth"},
                             {"validate"});
    args.Check(true, "%s", kUsage);
    const long steps = args.GetIntIn("steps", 100000, 1, 100000000);
    const int size = int(args.GetIntIn("size", 2000, 20, 1000000));
    const uint32_t seed = uint32_t(args.GetIntIn("seed", 1, 0, 2147483647));
    const long interval = args.GetIntIn("interval", 10000, 1, 100000000);
    const double maxGrowth = double(args.GetIntIn("max-growth", 10, 0, 10000));
    const bool validate = args.Has("validate");
    const Rss before;

    const scenes::SceneId churn = *scenes::ParseSceneName("churn");
    const scenes::SceneInfo& info = scenes::GetSceneInfo(churn);
    if (size < info.minSize || size > info.maxSize)
    {
        Usage("--size must be in [" + std::to_string(info.minSize) + ", " + std::to_string(info.maxSize) +
              "] for the churn scene");
    }
    scenes::Scene scene = scenes::BuildScene(churn, size, seed);
    b2World* world = scene.world.get();
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    quadphase::SetValidation(*world, validate);
#else
    if (validate)
    {
        Usage("--validate needs the quadphase build");
    }
#endif

    std::printf("qp-soak (%s build): %ld steps, size %d, seed %u; world: scene library \"churn\": %s\n",
                QP_SOAK_VARIANT, steps, size, seed, info.description);
    std::printf("%10s %8s %8s %10s %10s %12s\n", "step", "bodies", "proxies", "VmRSS_KiB", "VmHWM_KiB",
                "bp_heap_KiB");
    auto report = [&](long step) {
        const Rss rss;
        long heap = -1;
#if defined(QUADPHASE_VARIANT_QUADPHASE)
        heap = long(quadphase::GetStats(*world).memoryBytes / 1024);
#endif
        std::printf("%10ld %8d %8d %10ld %10ld %12ld\n", step, world->GetBodyCount(), world->GetProxyCount(),
                    rss.currentKiB, rss.peakKiB, heap);
        std::fflush(stdout);
        return rss;
    };
    std::printf("(before building the world: VmRSS %ld KiB)\n", before.currentKiB);
    const Rss start = report(0);
    const long warmupStep = interval < steps / 10 ? interval : steps / 10;
    Rss warm = start;
    for (long step = 1; step <= steps; ++step)
    {
        scenes::StepScene(scene);
        if (step == warmupStep)
        {
            warm = report(step);
        }
        else if (step % interval == 0 || step == steps)
        {
            report(step);
        }
    }
    const Rss end;
    const double growth = warm.currentKiB > 0
                              ? 100.0 * double(end.currentKiB - warm.currentKiB) / double(warm.currentKiB)
                              : 0.0;
    std::printf(
        "qp-soak: VmRSS start %ld KiB, after warm-up (step %ld) %ld KiB, end %ld KiB (%+.1f%% since the "
        "warm-up), peak %ld KiB\n",
        start.currentKiB, warmupStep, warm.currentKiB, end.currentKiB, growth, end.peakKiB);
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    if (validate)
    {
        const quadphase::ValidationReport v = quadphase::GetValidationReport(*world);
        std::printf("qp-soak: validation %lld checks, %lld pairs, %lld mismatches\n", (long long)v.checks,
                    (long long)v.pairsCompared, (long long)v.mismatches);
        if (v.mismatches != 0)
        {
            return 1;
        }
    }
#endif
    if (growth > maxGrowth)
    {
        std::printf("qp-soak: FAIL: resident memory grew by more than %.0f%%\n", maxGrowth);
        return 1;
    }
    std::printf("qp-soak: memory flat (within %.0f%% of the warm-up)\n", maxGrowth);
    return 0;
}
