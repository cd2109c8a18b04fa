// qp-soak / qp-soak-stock: a long run of a churn world (bodies created and destroyed every step) with
// resident memory printed at the start, at intervals and at the end, to show that memory stays flat.
//
//   qp-soak [--steps N] [--size S] [--seed K] [--interval I] [--validate] [--max-growth PCT]
//
// The world is the scene library's "churn" scene when the library has one
// (quadphase::scenes::ParseSceneName), else the built-in loop below (an open box of S bodies; every step
// destroys S/20 of them at random and creates as many at random places). Prints one line per interval: step,
// bodies, proxies, VmRSS, VmHWM (and, in the quadphase build, the broadphase's own heap bytes). Exit status 1
// when VmRSS at the end exceeds VmRSS after the warm-up (the first interval, or 10% of the run) by more than
// --max-growth percent (default 10), else 0.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "quadphase_scenes/scenes.h"
#include "tool_common.h"
#if defined(QUADPHASE_VARIANT_QUADPHASE)
#include "quadphase/box2d.h"
constexpr const char* kVariant = "quadphase";
#else
constexpr const char* kVariant = "stock";
#endif

namespace
{

using quadphase::scenes::Rng;

struct Options
{
    long steps = 100000;
    int size = 2000;
    uint32_t seed = 1;
    long interval = 10000;
    bool validate = false;
    double maxGrowth = 10.0;
};

[[noreturn]] void Usage(const std::string& error)
{
    qpbench::Die(2,
                 "qp-soak: %s\nusage: qp-soak [--steps N] [--size S] [--seed K] [--interval I] [--validate] "
                 "[--max-growth PCT]\n",
                 error.c_str());
}

Options Parse(int argc, char** argv)
{
    const qpbench::Args args(argc, argv, {"validate", "help"});
    const std::vector<std::string> problems =
        args.Problems({"steps", "size", "seed", "interval", "max-growth", "validate", "help"});
    if (args.Has("help") || !problems.empty())
    {
        Usage(problems.empty() ? "help" : problems.front());
    }
    Options o;
    o.steps = args.GetIntIn("steps", o.steps, 1, 100000000);
    o.size = int(args.GetIntIn("size", o.size, 20, 1000000));
    o.seed = uint32_t(args.GetIntIn("seed", o.seed, 0, 2147483647));
    o.interval = args.GetIntIn("interval", o.interval, 1, 100000000);
    o.maxGrowth = double(args.GetIntIn("max-growth", long(o.maxGrowth), 0, 10000));
    o.validate = args.Has("validate");
    return o;
}

/// The built-in churn world, used when the scene library has no "churn" scene.
class OwnChurn
{
public:
    OwnChurn(int size, uint32_t seed)
        : m_world(std::make_unique<b2World>(b2Vec2(0.0f, -10.0f))), m_rng(seed), m_size(size)
    {
        const float half = 0.5f * float(size) / 40.0f + 10.0f; // about 40 bodies per metre of width
        b2BodyDef groundDef;
        b2Body* ground = m_world->CreateBody(&groundDef);
        b2PolygonShape shape;
        shape.SetAsBox(half, 0.5f, b2Vec2(0.0f, -0.5f), 0.0f);
        ground->CreateFixture(&shape, 0.0f);
        shape.SetAsBox(0.5f, 20.0f, b2Vec2(-half - 0.5f, 20.0f), 0.0f);
        ground->CreateFixture(&shape, 0.0f);
        shape.SetAsBox(0.5f, 20.0f, b2Vec2(half + 0.5f, 20.0f), 0.0f);
        ground->CreateFixture(&shape, 0.0f);
        m_half = half;
        for (int i = 0; i < size; ++i)
        {
            Spawn();
        }
    }

    void Step()
    {
        m_world->Step(1.0f / 60.0f, 8, 3);
        const int churn = m_size / 20 > 0 ? m_size / 20 : 1;
        for (int k = 0; k < churn; ++k)
        {
            const uint32_t victim = m_rng.Index(uint32_t(m_bodies.size()));
            m_world->DestroyBody(m_bodies[victim]);
            m_bodies[victim] = m_bodies.back();
            m_bodies.pop_back();
        }
        for (int k = 0; k < churn; ++k)
        {
            Spawn();
        }
    }

    b2World& World() { return *m_world; }

private:
    void Spawn()
    {
        b2BodyDef def;
        def.type = b2_dynamicBody;
        def.position.Set(m_rng.Uniform(-m_half + 1.0f, m_half - 1.0f), m_rng.Uniform(1.0f, 30.0f));
        b2Body* body = m_world->CreateBody(&def);
        const float r = m_rng.Uniform(0.1f, 0.5f);
        if (m_rng.Index(2) == 0)
        {
            b2CircleShape c;
            c.m_radius = r;
            body->CreateFixture(&c, 1.0f);
        }
        else
        {
            b2PolygonShape p;
            p.SetAsBox(r, r);
            body->CreateFixture(&p, 1.0f);
        }
        m_bodies.push_back(body);
    }

    std::unique_ptr<b2World> m_world;
    Rng m_rng;
    int m_size;
    float m_half = 0.0f;
    std::vector<b2Body*> m_bodies;
};

/// Resident memory of this process, from /proc/self/status (Linux).
struct Rss
{
    long currentKiB = -1; ///< VmRSS: resident now
    long peakKiB = -1;    ///< VmHWM: the largest VmRSS so far
};

/// Reads VmRSS and VmHWM; -1 where /proc is not available.
Rss ReadRss()
{
    Rss rss;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (f == nullptr)
    {
        return rss;
    }
    char line[256];
    while (std::fgets(line, sizeof(line), f) != nullptr)
    {
        if (std::strncmp(line, "VmRSS:", 6) == 0)
        {
            rss.currentKiB = std::strtol(line + 6, nullptr, 10);
        }
        else if (std::strncmp(line, "VmHWM:", 6) == 0)
        {
            rss.peakKiB = std::strtol(line + 6, nullptr, 10);
        }
    }
    std::fclose(f);
    return rss;
}

} // namespace

int main(int argc, char** argv)
{
    const Options o = Parse(argc, argv);
    const Rss before = ReadRss();

    // The scene library's churn scene when it has one, else OwnChurn.
    std::optional<quadphase::scenes::SceneId> churnId = quadphase::scenes::ParseSceneName("churn");
    quadphase::scenes::Scene scene;
    std::unique_ptr<OwnChurn> own;
    b2World* world = nullptr;
    std::string source;
    if (churnId)
    {
        const quadphase::scenes::SceneInfo& info = quadphase::scenes::GetSceneInfo(*churnId);
        if (o.size < info.minSize || o.size > info.maxSize)
        {
            Usage("--size must be in [" + std::to_string(info.minSize) + ", " + std::to_string(info.maxSize) +
                  "] for the churn scene");
        }
        scene = quadphase::scenes::BuildScene(*churnId, o.size, o.seed);
        world = scene.world.get();
        source = std::string("scene library \"churn\": ") + info.description;
    }
    else
    {
        own = std::make_unique<OwnChurn>(o.size, o.seed);
        world = &own->World();
        source = "built-in churn loop (the scene library has no churn scene)";
    }
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    quadphase::SetValidation(*world, o.validate);
#else
    if (o.validate)
    {
        Usage("--validate needs the quadphase build");
    }
#endif

    std::printf("qp-soak (%s build): %ld steps, size %d, seed %u; world: %s\n", kVariant, o.steps, o.size,
                o.seed, source.c_str());
    std::printf("%10s %8s %8s %10s %10s %12s\n", "step", "bodies", "proxies", "VmRSS_KiB", "VmHWM_KiB",
                "bp_heap_KiB");
    auto report = [&](long step)
    {
        const Rss rss = ReadRss();
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
    const long warmupStep = o.interval < o.steps / 10 ? o.interval : o.steps / 10;
    Rss warm = start;
    for (long step = 1; step <= o.steps; ++step)
    {
        if (own)
        {
            own->Step();
        }
        else
        {
            quadphase::scenes::StepScene(scene);
        }
        const bool atWarmup = step == warmupStep;
        if (step % o.interval == 0 || step == o.steps || atWarmup)
        {
            const Rss now = report(step);
            if (atWarmup)
            {
                warm = now;
            }
        }
    }
    const Rss end = ReadRss();
    const double growth = warm.currentKiB > 0
                              ? 100.0 * double(end.currentKiB - warm.currentKiB) / double(warm.currentKiB)
                              : 0.0;
    std::printf(
        "qp-soak: VmRSS start %ld KiB, after warm-up (step %ld) %ld KiB, end %ld KiB (%+.1f%% since the "
        "warm-up), peak %ld KiB\n",
        start.currentKiB, warmupStep, warm.currentKiB, end.currentKiB, growth, end.peakKiB);
#if defined(QUADPHASE_VARIANT_QUADPHASE)
    if (o.validate)
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
    if (growth > o.maxGrowth)
    {
        std::printf("qp-soak: FAIL: resident memory grew by more than %.0f%%\n", o.maxGrowth);
        return 1;
    }
    std::printf("qp-soak: memory flat (within %.0f%% of the warm-up)\n", o.maxGrowth);
    return 0;
}
