// qp-step-stock / qp-step-quadtree: the in-engine step benchmark. One source, compiled against stock
// Box2D 2.4.1 (QUADPHASE_VARIANT_STOCK) and against Box2D with the quadtree broadphase
// (QUADPHASE_VARIANT_QUADPHASE); bench/bench.py runs the two alternately, in random order, within one
// invocation, and takes medians over repeats.
//
//   qp-step-<variant> --scene NAME --size N [--seed S] [--warmup W] [--steps S] [--threads T] [--json FILE]
//                     [--label TEXT]      (qp-step-<variant> --list prints the scene names)
//
// Builds the scene, steps it W times untimed (warm-up), then S timed steps, and appends one JSON line with,
// per timed step, the median and the mean of Box2D's own b2Profile fields (step, collide, solve, broadphase,
// solveTOI; milliseconds), the mean contact count, the new pairs per step that reached Box2D's contact filter
// (the same count in both builds), the process's peak resident memory (VmHWM) and, for the quadtree build,
// the quadtree's pairs reported, FindPairs time per step (Stats::pairSeconds), heap bytes per proxy
// (Stats::memoryBytes) and threads. --threads sets quadphase::Config::threads (0: OpenMP's default); the stock
// build accepts only 1.
//
// b2Profile::broadphase is the time b2World::Solve spends after the solver synchronising fixtures (MoveProxy
// of every awake body's proxies) and in FindNewContacts (UpdatePairs, its AddPair callbacks creating
// contacts); the time-of-impact phase's broadphase work is in solveTOI. The time inside the broadphase alone
// is measured by the replay (qp-replay*), on a recorded trace of the same scene.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "box2d/box2d.h"
#include "quadphase_scenes/scenes.h"
#include "replay_common.h"

#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase/box2d.h"
constexpr const char* kVariant = "quadtree";
#elif QUADPHASE_VARIANT_STOCK
constexpr const char* kVariant = "stock";
#else
#error                                                                                                       \
    "compile with QUADPHASE_VARIANT_QUADPHASE=1 or QUADPHASE_VARIANT_STOCK=1 (quadphase_link_box2d_variant)"
#endif

namespace
{

using namespace qpbench;

class CountingFilter : public b2ContactFilter
{
public:
    bool ShouldCollide(b2Fixture* a, b2Fixture* b) override
    {
        ++calls;
        return b2ContactFilter::ShouldCollide(a, b);
    }
    int64_t calls = 0;
};

/// Peak resident set size of this process in bytes (VmHWM of /proc/self/status); 0 when unknown.
int64_t PeakRss()
{
    std::ifstream in("/proc/self/status");
    std::string line;
    while (std::getline(in, line))
    {
        if (line.rfind("VmHWM:", 0) == 0)
        {
            return std::atoll(line.c_str() + 6) * 1024;
        }
    }
    return 0;
}

double Mean(const std::vector<double>& v)
{
    double s = 0.0;
    for (double x : v)
    {
        s += x;
    }
    return v.empty() ? 0.0 : s / double(v.size());
}

} // namespace

int main(int argc, char** argv)
{
    namespace scenes = quadphase::scenes;
    const Args args(argc, argv, {"help", "list"});
    const std::vector<std::string> problems = args.Problems(
        {"scene", "size", "seed", "warmup", "steps", "threads", "json", "label", "help", "list"});
    if (args.Has("list"))
    {
        for (const scenes::SceneInfo& info : scenes::AllScenes())
        {
            std::printf("%s %d %d %d\n", info.name, info.minSize, info.maxSize, info.defaultSize);
        }
        return 0;
    }
    if (args.Has("help") || !problems.empty() || !args.Has("scene") || !args.Has("size"))
    {
        for (const std::string& p : problems)
        {
            std::fprintf(stderr, "qp-step-%s: %s\n", kVariant, p.c_str());
        }
        std::fprintf(
            stderr,
            "usage: qp-step-%s --scene NAME --size N [--seed S] [--warmup W] [--steps S] [--threads T]\n"
            "       [--json FILE] [--label TEXT]     (--list: scene names and size ranges)\n"
            "scenes: %s\n",
            kVariant, scenes::SceneNameList().c_str());
        return args.Has("help") ? 0 : 2;
    }
    const auto sceneId = scenes::ParseSceneName(args.Get("scene"));
    if (!sceneId)
    {
        std::fprintf(stderr, "qp-step-%s: unknown scene '%s' (%s)\n", kVariant, args.Get("scene").c_str(),
                     scenes::SceneNameList().c_str());
        return 2;
    }
    const int size = int(args.GetInt("size", 0));
    const uint32_t seed = uint32_t(args.GetInt("seed", 1));
    const int warmup = int(args.GetInt("warmup", 30));
    const int steps = int(args.GetInt("steps", 60));
    const int threads = int(args.GetInt("threads", 1));
    if (warmup < 0 || steps <= 0)
    {
        std::fprintf(stderr, "qp-step-%s: --warmup must be >= 0 and --steps > 0\n", kVariant);
        return 2;
    }
#if QUADPHASE_VARIANT_STOCK
    if (threads != 1)
    {
        std::fprintf(stderr, "qp-step-stock: stock Box2D is single-threaded (--threads 1)\n");
        return 2;
    }
#endif

    CountingFilter filter; // outlives the world
    scenes::Scene scene;
    try
    {
        scene = scenes::BuildScene(*sceneId, size, seed);
    }
    catch (const std::exception& e)
    {
        std::fprintf(stderr, "qp-step-%s: %s\n", kVariant, e.what());
        return 2;
    }
    b2World& world = *scene.world;
    world.SetContactFilter(&filter);
#if QUADPHASE_VARIANT_QUADPHASE
    quadphase::Config config = quadphase::GetConfig(world);
    config.threads = threads;
    quadphase::Configure(world, config);
#endif

    for (int s = 0; s < warmup; ++s)
    {
        scenes::StepScene(scene);
    }
#if QUADPHASE_VARIANT_QUADPHASE
    quadphase::ResetCounters(world);
#endif
    const int64_t filtered0 = filter.calls;
    std::vector<double> step, collide, solve, broadphase, toi;
    double contacts = 0.0;
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
    }
    const double wall = double(NowNs() - t0) * 1e-9;

    JsonLine j;
    j.Str("tool", "qp-step")
        .Str("variant", kVariant)
        .Str("label", args.Get("label"))
        .Str("scene", args.Get("scene"))
        .Int("size", size)
        .Int("seed", seed)
        .Int("warmup", warmup)
        .Int("steps", steps)
        .Int("threads", threads)
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
        .Num("contacts_mean", contacts / steps)
        .Num("new_pairs_per_step", double(filter.calls - filtered0) / steps)
        .Num("wall_s", wall)
        .Int("peak_rss_bytes", PeakRss());
#if QUADPHASE_VARIANT_QUADPHASE
    const quadphase::Stats st = quadphase::GetStats(world);
    j.Num("pairs_reported_per_step", double(st.pairsReported) / steps)
        .Int("qt_depth", st.depth)
        .Num("qt_find_ms_per_step", 1000.0 * st.pairSeconds / steps)
        .Int("bp_bytes", st.memoryBytes)
        .Num("bp_bytes_per_proxy", double(st.memoryBytes) / std::max(1, st.proxyCount));
#endif
    AppendLine(args.Get("json"), j.Text());
    std::printf("%s %s %d: step %.3f ms, broadphase %.3f ms (medians over %d steps), %.0f contacts, peak RSS "
                "%.1f MB\n",
                kVariant, args.Get("scene").c_str(), size, Median(step), Median(broadphase), steps,
                contacts / steps, double(PeakRss()) / 1048576.0);
    return 0;
}
