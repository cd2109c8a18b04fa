// SPDX-License-Identifier: MIT
// qp-accuracy-stock / qp-accuracy-quadphase / qp-accuracy-paper: one scene, one broadphase configuration, one
// set of step settings; prints ONE JSON line with the run time per simulated second and the error measures
// (bench/accuracy/README.md). The same source is compiled against the three Box2D builds:
//   QUADPHASE_VARIANT_STOCK      stock Box2D 2.4.1 (b2DynamicTree)
//   QUADPHASE_VARIANT_QUADPHASE  quadphase (--depth, --threads)
//   QP_ACCURACY_VARIANT_PAPER    the paper's static quadtree, approximate (--levels, --threads)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact_check.h"
#include "quadphase_scenes/scenes.h"
#include "tool_common.h"

#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include "quadphase/box2d.h"
static const char* const kBuild = "quadphase";
#elif defined(QP_ACCURACY_VARIANT_PAPER)
#include "quadphase_paper/paper_settings.h"
static const char* const kBuild = "paper";
#elif defined(QUADPHASE_VARIANT_STOCK)
static const char* const kBuild = "stock";
#else
#error "compile with one of QUADPHASE_VARIANT_STOCK, QUADPHASE_VARIANT_QUADPHASE, QP_ACCURACY_VARIANT_PAPER"
#endif

namespace
{

namespace qs = quadphase::scenes;
namespace qa = quadphase::accuracy;

// The scenes' per-step hooks (spawning, relaunching) count steps of the scenes' own 60 Hz clock.
constexpr int kSceneHz = 60;

// The command line; members are read in declaration order, `args` first. An integer outside its range exits
// (Args::GetIntIn).
struct Options
{
    const qpbench::Args& args;
    std::string scene = args.Get("scene");
    int size = int(args.GetInt("size", -1));
    uint32_t seed = uint32_t(args.GetInt("seed", 1));
    double seconds = args.GetDouble("seconds", 10.0);
    int hz = int(args.GetIntIn("hz", 60, 1, 1000000));
    int velocityIterations = int(args.GetIntIn("vel-iters", 8, 1, 1000000));
    int positionIterations = int(args.GetIntIn("pos-iters", 3, 0, 1000000));
    std::string depth = args.Get("depth", "auto");   // quadphase: auto | N | auto+K | auto-K
    std::string levels = args.Get("levels", "auto"); // paper: auto | N | auto+K | auto-K
    int threads = int(args.GetIntIn("threads", 1, 1, 256));
    int checkEvery = int(args.GetIntIn("check-every", 1, 1, 1000000));
    double sampleEvery = args.GetDouble("sample-every", 0.5);
    std::string positionsOut = args.Get("positions-out");
};

[[noreturn]] void Fail(const std::string& message)
{
    qpbench::Die(2, "qp-accuracy-%s: %s\n", kBuild, message.c_str());
}

void CheckOptions(const Options& o)
{
    if (o.seconds <= 0.0)
        Fail("--seconds must be > 0");
    const double perSample = o.sampleEvery * o.hz;
    if (o.sampleEvery <= 0.0 || std::fabs(perSample - std::round(perSample)) > 1e-9 ||
        std::round(perSample) < 1)
        Fail("--sample-every times --hz must be a positive whole number of steps");
}

// "auto" -> {true, 0}; "auto+2" -> {true, 2}; "7" -> {false, 7}.
struct Relative
{
    bool automatic;
    int value;

    /// The value asked for, given the automatic one. Relative values are clamped into [lo, hi] (the JSON line
    /// reports the value used); `arg` (flag and text) names an absolute one outside it in the error.
    int Resolve(const std::string& arg, int automaticValue, int lo, int hi) const
    {
        const int v = automatic ? std::clamp(automaticValue + value, lo, hi) : value;
        if (v < lo || v > hi)
            Fail(arg + " gives " + std::to_string(v) + ", outside [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]");
        return v;
    }
};

[[maybe_unused]] Relative ParseRelative(const std::string& flag, const std::string& text)
{
    const bool automatic = text.rfind("auto", 0) == 0;
    const std::string rest = automatic ? text.substr(4) : text;
    if (automatic && rest.empty())
        return {true, 0};
    if (automatic && rest[0] != '+' && rest[0] != '-')
        Fail(flag + ": expected auto, auto+K, auto-K or a number, got '" + text + "'");
    long value = 0;
    if (!qpbench::ParseLong(rest, value) || value < -1000000000L || value > 1000000000L)
        Fail(flag + ": not an integer: '" + rest + "'");
    return {automatic, static_cast<int>(value)};
}

// The box around all the `boxes`; zeros when there are none.
[[maybe_unused]] b2AABB Bounds(const std::vector<qa::ChildBox>& boxes)
{
    b2AABB bounds = boxes.empty() ? b2AABB() : boxes[0].box; // b2AABB(): value-initialized, zeros
    for (const qa::ChildBox& c : boxes)
        bounds.Combine(c.box);
    return bounds;
}

// qs::BuildScene, exiting with its message (a size outside the scene's range).
qs::Scene MakeScene(qs::SceneId id, int size, uint32_t seed)
{
    try
    {
        return qs::BuildScene(id, size, seed);
    }
    catch (const std::exception& e)
    {
        Fail(e.what());
    }
}

// The dynamic body that starts highest (the pyramid's top box); nullptr when there is none.
const b2Body* TopBody(const b2World& world)
{
    const b2Body* top = nullptr;
    for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
    {
        if (b->GetType() == b2_dynamicBody && (top == nullptr || b->GetPosition().y > top->GetPosition().y))
            top = b;
    }
    return top;
}

} // namespace

int main(int argc, char** argv)
{
    const qpbench::Args args(argc, argv, std::string("qp-accuracy-") + kBuild,
                             {"scene", "size", "seed", "seconds", "hz", "vel-iters", "pos-iters", "threads",
                              "depth", "levels", "check-every", "sample-every", "positions-out"});
    args.Check(
        args.Has("scene"),
        "usage: qp-accuracy-%s --scene NAME [--size N] [--seed 1] [--seconds 10 (simulated)] [--hz 60]\n"
        "       [--vel-iters 8] [--pos-iters 3] [--threads 1] [--depth auto|N|auto+K|auto-K (quadphase)]\n"
        "       [--levels auto|N|auto+K|auto-K (paper)] [--check-every 1] [--sample-every 0.5 (seconds)]\n"
        "       [--positions-out FILE]: one JSON line on stdout (bench/accuracy/README.md)\n"
        "scenes: %s\n",
        kBuild, qs::SceneNameList().c_str());
    const Options o{args};
    CheckOptions(o);
    const std::optional<qs::SceneId> id = qs::ParseSceneName(o.scene);
    if (!id)
        Fail("unknown scene '" + o.scene + "' (" + qs::SceneNameList() + ")");
    const int size = o.size >= 0 ? o.size : qs::GetSceneInfo(*id).defaultSize;

    int depthUsed = -1;
    int autoDepth = -1;
    int levelsUsed = -1;
    int autoLevels = -1;
    std::string boundsText = "null";
#if defined(QP_ACCURACY_VARIANT_PAPER)
    {
        // The paper's tree covers a fixed region (its window). Here: the box of every shape of the scene as
        // built and after kProbeSteps steps at the scene's own settings (spawned bodies, a settled pile),
        // grown by 5% per side, measured on a probe build (scenes are deterministic, so the measured build is
        // the same). The probe runs with ONE leaf (levels = 1): every pair is tested, so it is exact (and
        // O(proxies^2)).
        constexpr int kProbeSteps = 250;
        using Paper = quadphase::bench::PaperQuadtreeBroadPhase;
        quadphase::bench::PaperSettings& settings = quadphase::bench::g_paperSettings;
        settings.levels = 1;
        settings.threads = 1;
        qs::Scene probe = MakeScene(*id, size, o.seed);
        b2AABB b = Bounds(qa::ChildBoxes(*probe.world));
        for (int i = 0; i < kProbeSteps; ++i)
            qs::StepScene(probe);
        const std::vector<qa::ChildBox> later = qa::ChildBoxes(*probe.world);
        b.Combine(Bounds(later));
        // The median extent after the probe steps: the population that is simulated most of the time.
        const float medianExtent = qa::MedianExtent(later);
        const float mx = 0.05f * (b.upperBound.x - b.lowerBound.x) + 1.0f;
        const float my = 0.05f * (b.upperBound.y - b.lowerBound.y) + 1.0f;
        settings.bounds = {b.lowerBound.x - mx, b.lowerBound.y - my, b.upperBound.x + mx,
                           b.upperBound.y + my};
        // Automatic level count, by quadphase's rule of thumb: leaf side about twice the median fat box
        // (tight extent + 2 x b2_aabbExtension) along the longer side of the bounds, to the nearest power of
        // two.
        const float side = std::max(settings.bounds.maxX - settings.bounds.minX,
                                    settings.bounds.maxY - settings.bounds.minY);
        const float fat = medianExtent + 2.0f * b2_aabbExtension;
        autoLevels = 1 + static_cast<int>(std::lround(std::log2(std::max(1.0f, side / (2.0f * fat)))));
        autoLevels = std::clamp(autoLevels, Paper::kMinLevels, Paper::kMaxLevels);
        levelsUsed = ParseRelative("--levels", o.levels)
                         .Resolve("--levels " + o.levels, autoLevels, Paper::kMinLevels, Paper::kMaxLevels);
        settings.levels = levelsUsed;
        settings.threads = o.threads;
        char buffer[160];
        std::snprintf(buffer, sizeof buffer, "[%.6g, %.6g, %.6g, %.6g]", settings.bounds.minX,
                      settings.bounds.minY, settings.bounds.maxX, settings.bounds.maxY);
        boundsText = buffer;
    }
#endif

    qs::Scene scene = MakeScene(*id, size, o.seed);
    b2World& world = *scene.world;

#if defined(QUADPHASE_VARIANT_QUADPHASE)
    {
        quadphase::Config config = quadphase::GetConfig(world);
        config.depth = -1;
        config.threads = o.threads;
        quadphase::Configure(world, config);
        autoDepth = quadphase::GetStats(world).depth;
        const Relative rel = ParseRelative("--depth", o.depth);
        if (!rel.automatic || rel.value != 0) // plain "auto" leaves the depth automatic (depth: null)
        {
            depthUsed = rel.Resolve("--depth " + o.depth, autoDepth, 0, quadphase::kMaxDepth);
            config.depth = depthUsed;
            quadphase::Configure(world, config);
        }
    }
#else
    if (o.threads != 1 && std::strcmp(kBuild, "stock") == 0)
        Fail("--threads: the stock tree has no threads");
    if (o.depth != "auto" && std::strcmp(kBuild, "quadphase") != 0)
        Fail("--depth is for the quadphase build");
#endif
#if !defined(QP_ACCURACY_VARIANT_PAPER)
    if (o.levels != "auto")
        Fail("--levels is for the paper build");
#endif

    std::ofstream positions;
    if (!o.positionsOut.empty())
    {
        positions.open(o.positionsOut);
        if (!positions)
            Fail("cannot write " + o.positionsOut);
        positions.precision(9);
    }

    const b2Body* top = TopBody(world);
    const b2Vec2 topStart = top != nullptr ? top->GetPosition() : b2Vec2(0.0f, 0.0f);
    const double energyStart = qa::KineticEnergy(world);
    double energyMaxDev = 0.0;

    const float dt = 1.0f / static_cast<float>(o.hz);
    const int64_t steps = static_cast<int64_t>(std::llround(o.seconds * o.hz));
    const int64_t stepsPerSample = std::llround(o.sampleEvery * o.hz);
    int64_t sceneSteps = 0; // per-step hook calls made (the scene's 60 Hz clock)

    double stepSeconds = 0.0;
    int64_t checks = 0, overlapping = 0, missed = 0, missedMax = 0, checksWithMiss = 0, missedNew = 0;
    int64_t missedStatic = 0; // missed pairs with a static body (grounds, walls, tiles)
    // Missed pairs of the previous check: a pair that stays missed for many checks (two bodies passing
    // through each other) is counted once in missedNew, at the check where it starts being missed.
    std::set<qa::ChildPair> previousMissed;
    double penMax = 0.0, penSum = 0.0;
    int64_t penPoints = 0;
    double checkSeconds = 0.0;

    for (int64_t n = 1; n <= steps; ++n)
    {
        const auto t0 = std::chrono::steady_clock::now();
        world.Step(dt, o.velocityIterations, o.positionIterations);
        const auto t1 = std::chrono::steady_clock::now();
        stepSeconds += std::chrono::duration<double>(t1 - t0).count();

        // Checks before the hook: the hook may teleport or create bodies, whose contacts come in the next
        // Step.
        if (n % o.checkEvery == 0)
        {
            const qa::MissedContacts m = qa::CheckMissedContacts(world, true);
            // each pair ordered
            std::set<qa::ChildPair> nowMissed(m.missedPairs.begin(), m.missedPairs.end());
            for (const auto& pair : m.missedPairs)
            {
                if (pair.first.fixture->GetBody()->GetType() == b2_staticBody ||
                    pair.second.fixture->GetBody()->GetType() == b2_staticBody)
                    ++missedStatic;
            }
            for (const auto& pair : nowMissed)
                missedNew += previousMissed.count(pair) == 0 ? 1 : 0;
            previousMissed.swap(nowMissed);
            ++checks;
            overlapping += m.overlapping;
            missed += m.missed;
            missedMax = std::max(missedMax, m.missed);
            checksWithMiss += m.missed > 0 ? 1 : 0;
            const qa::Penetration p = qa::MeasurePenetration(world);
            penMax = std::max(penMax, p.maxDepth);
            penSum += p.sumDepth;
            penPoints += p.points;
            if (energyStart > 0.0)
                energyMaxDev =
                    std::max(energyMaxDev, std::fabs(qa::KineticEnergy(world) / energyStart - 1.0));
            checkSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        }
        if (positions.is_open() && n % stepsPerSample == 0)
        {
            positions << static_cast<double>(n) / o.hz;
            for (const b2Body* b = world.GetBodyList(); b != nullptr; b = b->GetNext())
            {
                if (b->GetType() == b2_dynamicBody)
                    positions << ' ' << b->GetPosition().x << ' ' << b->GetPosition().y;
            }
            positions << '\n';
        }
        // The scene's hook at its own 60 Hz clock: hook k runs once simulated time reaches (k + 1) / 60 s.
        if (scene.perStep)
        {
            while ((sceneSteps + 1) * o.hz <= n * kSceneHz)
            {
                scene.perStep(world, static_cast<int>(sceneSteps));
                ++sceneSteps;
            }
        }
    }

    const double energyEnd = qa::KineticEnergy(world);
    const double simulated = static_cast<double>(steps) / o.hz;
    const b2Vec2 topEnd = top != nullptr ? top->GetPosition() : b2Vec2(0.0f, 0.0f);

    auto optional = [](int v) {
        return v >= 0 ? std::to_string(v) : std::string("null");
    };
    qpbench::JsonLine j;
    j.Str("build", kBuild);
    j.Str("scene", qs::SceneName(*id));
    j.Int("size", size);
    j.Int("seed", o.seed);
    j.Int("hz", o.hz);
    j.Int("vel_iters", o.velocityIterations);
    j.Int("pos_iters", o.positionIterations);
    j.Int("threads", o.threads);
    j.Str("depth_arg", o.depth);
    j.Raw("depth", optional(depthUsed));
    j.Raw("auto_depth", optional(autoDepth));
    j.Str("levels_arg", o.levels);
    j.Raw("levels", optional(levelsUsed));
    j.Raw("auto_levels", optional(autoLevels));
    j.Raw("paper_bounds", boundsText);
    j.Int("steps", steps);
    j.Num("simulated_s", simulated);
    j.Int("bodies", qs::CountBodies(world));
    j.Int("fixtures", qs::CountFixtures(world));
    j.Num("step_s", stepSeconds);
    j.Num("run_s_per_sim_s", stepSeconds / simulated);
    j.Num("check_s", checkSeconds);
    j.Int("checks", checks);
    j.Int("overlapping", overlapping);
    j.Int("missed", missed);
    j.Int("missed_new", missedNew);
    j.Int("missed_static", missedStatic);
    j.Int("missed_max", missedMax);
    j.Int("checks_with_miss", checksWithMiss);
    j.Num("pen_max", penMax);
    j.Num("pen_mean", penPoints > 0 ? penSum / static_cast<double>(penPoints) : 0.0);
    j.Int("pen_points", penPoints);
    j.Num("energy_start", energyStart);
    j.Num("energy_end", energyEnd);
    j.Num("energy_drift", energyStart > 0.0 ? energyEnd / energyStart - 1.0 : NAN);
    j.Num("energy_max_dev", energyStart > 0.0 ? energyMaxDev : NAN);
    j.Num("top_dx", top != nullptr ? double(topEnd.x) - double(topStart.x) : NAN);
    j.Num("top_dy", top != nullptr ? double(topEnd.y) - double(topStart.y) : NAN);
    j.Str("cxx_flags", QP_ACCURACY_CXX_FLAGS);
    std::printf("%s\n", j.Text().c_str());
    return 0;
}
