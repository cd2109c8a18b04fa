// quadphase-demo-stock / quadphase-demo-quadtree: steps one scene with one Box2D build and prints a summary.
//
// The same source is compiled twice (see CMakeLists.txt): against stock Box2D 2.4.1 (QUADPHASE_VARIANT_STOCK)
// and against Box2D with the quadtree broadphase (QUADPHASE_VARIANT_QUADPHASE). quadphase-demo runs both and
// compares their --json output.
//
// Measures, per step after the warmup steps: b2Profile::broadphase (the time Box2D spends in b2World::Solve
// synchronising the proxies and finding new pairs, callbacks included) and b2Profile::step. Counts with a
// b2ContactFilter the new pairs that reached Box2D's filtering (the same metric in both builds, whatever the
// broadphase reports internally).
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "box2d/box2d.h"
#include "demo_options.h"
#include "quadphase_scenes/scenes.h"

#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase/box2d.h"
#elif !QUADPHASE_VARIANT_STOCK
#error                                                                                                       \
    "compile with QUADPHASE_VARIANT_QUADPHASE=1 or QUADPHASE_VARIANT_STOCK=1 (quadphase_link_box2d_variant)"
#endif

namespace
{

#if QUADPHASE_VARIANT_QUADPHASE
constexpr const char* kVariant = "quadtree";
#else
constexpr const char* kVariant = "stock";
#endif

/// Counts the pairs Box2D asks the user filter about, and keeps Box2D's default decision.
class CountingFilter : public b2ContactFilter
{
public:
    bool ShouldCollide(b2Fixture* fixtureA, b2Fixture* fixtureB) override
    {
        ++calls;
        return b2ContactFilter::ShouldCollide(fixtureA, fixtureB);
    }

    int64_t calls = 0;
};

double Median(std::vector<double> values)
{
    if (values.empty())
    {
        return 0.0;
    }
    const size_t mid = values.size() / 2;
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
    const double upper = values[mid];
    if (values.size() % 2 == 1)
    {
        return upper;
    }
    const double lower = *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid));
    return 0.5 * (lower + upper);
}

double Mean(const std::vector<double>& values)
{
    double sum = 0.0;
    for (double v : values)
    {
        sum += v;
    }
    return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

std::string JsonString(const std::string& text)
{
    std::string out = "\"";
    for (unsigned char c : text)
    {
        switch (c)
        {
        case '"':
            out += "\\\"";
            break;
        case '\\':
            out += "\\\\";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\t':
            out += "\\t";
            break;
        default:
            if (c < 0x20)
            {
                char buffer[8];
                std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
                out += buffer;
            }
            else
            {
                out += static_cast<char>(c);
            }
        }
    }
    return out + "\"";
}

/// Flat JSON object writer (one "key": value per line), or a human-readable "key: value" list.
class Report
{
public:
    explicit Report(bool json) : m_json(json) {}

    void Add(const char* key, const std::string& rawJson, const std::string& human)
    {
        m_entries.push_back({key, rawJson, human});
    }
    void Int(const char* key, int64_t value) { Add(key, std::to_string(value), std::to_string(value)); }
    void Real(const char* key, double value, int decimals = 4)
    {
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
        Add(key, buffer, buffer);
    }
    void Text(const char* key, const std::string& value) { Add(key, JsonString(value), value); }
    void Bool(const char* key, bool value) { Add(key, value ? "true" : "false", value ? "yes" : "no"); }

    void Print() const
    {
        if (m_json)
        {
            std::printf("{\n");
            for (size_t i = 0; i < m_entries.size(); ++i)
            {
                std::printf("  \"%s\": %s%s\n", m_entries[i].key, m_entries[i].json.c_str(),
                            i + 1 < m_entries.size() ? "," : "");
            }
            std::printf("}\n");
        }
        else
        {
            for (const Entry& entry : m_entries)
            {
                std::printf("%-28s %s\n", entry.key, entry.human.c_str());
            }
        }
    }

private:
    struct Entry
    {
        const char* key;
        std::string json;
        std::string human;
    };
    bool m_json;
    std::vector<Entry> m_entries;
};

void PrintHelp(const char* program)
{
    std::printf(
        "usage: %s [options]\n"
        "Steps one scene with the %s broadphase and prints a summary (the worker of quadphase-demo).\n"
        "\n"
        "options:\n"
        "  --scene NAME   scene to step (default rain)\n"
        "  --size N       scene size (default: the scene's default, see below)\n"
        "  --steps N      steps to take (default 300)\n"
        "  --warmup N     first steps left out of the timing statistics (default 10)\n"
        "  --seed N       scene seed, 0..4294967295 (default 1)\n"
        "  --validate     quadtree only: check every UpdatePairs against a shadow b2DynamicTree (slow);\n"
        "                 exits with status 1 on a mismatch\n"
        "  --timing       quadtree only: also time proxy updates (Stats::updateSeconds; adds clock reads)\n"
        "  --json         print one flat JSON object instead of text\n"
        "  --help         this text\n"
        "\n"
        "scenes:\n%s",
        program, kVariant, quadphase::demo::SceneHelp().c_str());
}

int Run(const quadphase::demo::Options& options)
{
    using quadphase::scenes::Scene;
    namespace scenes = quadphase::scenes;

#if !QUADPHASE_VARIANT_QUADPHASE
    if (options.validate || options.timing)
    {
        throw quadphase::demo::UsageError("--validate and --timing need the quadtree build "
                                          "(quadphase-demo-quadtree)");
    }
#endif

    CountingFilter filter; // declared before the scene: must outlive the world
    const auto buildStart = std::chrono::steady_clock::now();
    Scene scene = scenes::BuildScene(options.sceneId, options.size, options.seed);
    const double buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();
    b2World& world = *scene.world;
    world.SetContactFilter(&filter);

#if QUADPHASE_VARIANT_QUADPHASE
    if (options.validate)
    {
        quadphase::SetValidation(world, true);
    }
    if (options.timing)
    {
        quadphase::SetTiming(world, true);
    }
#endif

    std::vector<double> broadphaseMs;
    std::vector<double> stepMs;
    broadphaseMs.reserve(static_cast<size_t>(options.steps));
    stepMs.reserve(static_cast<size_t>(options.steps));
    double collideMs = 0.0;
    double solveMs = 0.0;
    double toiMs = 0.0;
    double contactSum = 0.0;
    int64_t filteredMeasured = 0;

    const auto runStart = std::chrono::steady_clock::now();
    for (int step = 0; step < options.steps; ++step)
    {
        if (step == options.warmup)
        {
            filteredMeasured = -filter.calls;
#if QUADPHASE_VARIANT_QUADPHASE
            quadphase::ResetCounters(world);
#endif
        }
        scenes::StepScene(scene);
        contactSum += world.GetContactCount();
        if (step >= options.warmup)
        {
            const b2Profile& profile = world.GetProfile();
            broadphaseMs.push_back(profile.broadphase);
            stepMs.push_back(profile.step);
            collideMs += profile.collide;
            solveMs += profile.solve;
            toiMs += profile.solveTOI;
        }
    }
    filteredMeasured += filter.calls;
    const double runSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - runStart).count();
    const double measured = static_cast<double>(options.steps - options.warmup);

    Report report(options.json);
    report.Text("variant", kVariant);
    report.Text("scene", options.scene);
    report.Int("size", options.size);
    report.Int("steps", options.steps);
    report.Int("warmup", options.warmup);
    report.Int("seed", options.seed);
    report.Int("bodies", scenes::CountBodies(world));
    report.Int("fixtures", scenes::CountFixtures(world));
    report.Int("contacts_end", world.GetContactCount());
    report.Real("contacts_mean", contactSum / options.steps, 1);
    report.Int("pairs_filtered", filteredMeasured);
    report.Int("pairs_filtered_all_steps", filter.calls);
    report.Real("pairs_filtered_per_step", static_cast<double>(filteredMeasured) / measured, 2);
    report.Real("broadphase_ms_median", Median(broadphaseMs));
    report.Real("broadphase_ms_mean", Mean(broadphaseMs));
    report.Real("step_ms_median", Median(stepMs));
    report.Real("step_ms_mean", Mean(stepMs));
    report.Real("collide_ms_mean", collideMs / measured);
    report.Real("solve_ms_mean", solveMs / measured);
    report.Real("toi_ms_mean", toiMs / measured);
    report.Real("build_s", buildSeconds, 3);
    report.Real("run_s", runSeconds, 3);
    char hash[32];
    std::snprintf(hash, sizeof hash, "%016" PRIx64, scenes::HashBodyPositions(world));
    report.Text("position_hash", hash);

    int status = 0;
#if QUADPHASE_VARIANT_QUADPHASE
    const quadphase::Stats stats = quadphase::GetStats(world);
    report.Int("qt_depth", stats.depth);
    report.Real("qt_leaf_size", stats.leafSize, 3);
    report.Int("qt_proxies", stats.proxyCount);
    report.Int("qt_outside", stats.outsideCount);
    report.Int("qt_occupied_cells", stats.occupiedCells);
    report.Int("qt_largest_cell", stats.largestCell);
    report.Int("qt_memory_bytes", stats.memoryBytes);
    report.Int("qt_rebuilds", stats.rebuilds);
    report.Int("qt_update_pairs_calls", stats.updatePairsCalls);
    report.Int("qt_pairs_reported", stats.pairsReported);
    report.Int("qt_proxies_queried", stats.proxiesQueried);
    report.Int("qt_reinserts", stats.reinserts);
    report.Real("qt_pair_ms_per_step", 1000.0 * stats.pairSeconds / measured);
    if (options.timing)
    {
        report.Real("qt_update_ms_per_step", 1000.0 * stats.updateSeconds / measured);
    }
    if (options.validate)
    {
        const quadphase::ValidationReport validation = quadphase::GetValidationReport(world);
        report.Int("validation_checks", validation.checks);
        report.Int("validation_pairs_compared", validation.pairsCompared);
        report.Int("validation_mismatches", validation.mismatches);
        report.Text("validation_first_mismatch", validation.firstMismatch);
        if (validation.mismatches != 0 || validation.checks == 0)
        {
            status = 1;
        }
    }
    report.Bool("validate", options.validate);
#endif
    report.Print();
    std::fflush(stdout);
    if (status != 0)
    {
        std::fprintf(stderr, "quadphase-demo-%s: validation FAILED (see validation_* above)\n", kVariant);
    }
    return status;
}

} // namespace

int main(int argc, char** argv)
{
    const char* program = argc > 0 ? argv[0] : "quadphase-demo-worker";
    try
    {
        const std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
        const quadphase::demo::Options options = quadphase::demo::ParseOptions(args, {});
        if (options.help)
        {
            PrintHelp(program);
            return 0;
        }
        return Run(options);
    }
    catch (const quadphase::demo::UsageError& error)
    {
        std::fprintf(stderr, "%s: error: %s\n(try --help)\n", program, error.what());
        return 2;
    }
    catch (const std::exception& error)
    {
        std::fprintf(stderr, "%s: error: %s\n", program, error.what());
        return 1;
    }
}
