// quadphase-demo: the same scene stepped with stock Box2D 2.4.1 and with the quadtree broadphase, side by
// side.
//
// Runs quadphase-demo-stock and quadphase-demo-quadtree (found in the directory of this executable) with the
// same options, alternately (stock, quadtree, stock, quadtree, ... --repeat times), reads their --json
// output and prints one table of medians over the repeats, with stock / quadtree ratios of the times.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "demo_options.h"

extern char** environ;

#ifndef QUADPHASE_DEMO_COMPILER
#define QUADPHASE_DEMO_COMPILER "unknown compiler"
#endif
#ifndef QUADPHASE_DEMO_BUILD_TYPE
#define QUADPHASE_DEMO_BUILD_TYPE ""
#endif
#ifndef QUADPHASE_DEMO_CXX_FLAGS
#define QUADPHASE_DEMO_CXX_FLAGS ""
#endif

namespace
{

using quadphase::demo::Options;
using quadphase::demo::UsageError;

/// A run's flat JSON object: key -> value (strings unescaped, numbers and literals as written).
struct RunResult
{
    std::map<std::string, std::string> values;
    std::map<std::string, bool> isString;

    std::optional<double> Number(const std::string& key) const
    {
        const auto it = values.find(key);
        if (it == values.end() || isString.at(key))
        {
            return std::nullopt;
        }
        char* end = nullptr;
        const double value = std::strtod(it->second.c_str(), &end);
        if (end == it->second.c_str())
        {
            return std::nullopt;
        }
        return value;
    }
    std::string Text(const std::string& key) const
    {
        const auto it = values.find(key);
        return it == values.end() ? std::string() : it->second;
    }
};

/// Parses the flat JSON object written by step_scene.cpp ({"key": string|number|true|false, ...}).
RunResult ParseFlatJson(const std::string& text)
{
    RunResult result;
    size_t i = 0;
    auto skipSpace = [&]() {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i])))
        {
            ++i;
        }
    };
    auto fail = [&](const char* what) -> std::runtime_error {
        return std::runtime_error(std::string("cannot parse the worker's JSON output: ") + what +
                                  " at offset " + std::to_string(i));
    };
    auto parseString = [&]() {
        if (i >= text.size() || text[i] != '"')
        {
            throw fail("expected a string");
        }
        ++i;
        std::string out;
        while (i < text.size() && text[i] != '"')
        {
            char c = text[i++];
            if (c == '\\' && i < text.size())
            {
                const char e = text[i++];
                switch (e)
                {
                case 'n':
                    c = '\n';
                    break;
                case 't':
                    c = '\t';
                    break;
                case 'u':
                    c = static_cast<char>(std::strtol(text.substr(i, 4).c_str(), nullptr, 16));
                    i += 4;
                    break;
                default:
                    c = e;
                }
            }
            out += c;
        }
        if (i >= text.size())
        {
            throw fail("unterminated string");
        }
        ++i;
        return out;
    };

    skipSpace();
    if (i >= text.size() || text[i] != '{')
    {
        throw fail("expected '{'");
    }
    ++i;
    skipSpace();
    while (i < text.size() && text[i] != '}')
    {
        const std::string key = parseString();
        skipSpace();
        if (i >= text.size() || text[i] != ':')
        {
            throw fail("expected ':'");
        }
        ++i;
        skipSpace();
        if (i < text.size() && text[i] == '"')
        {
            result.values[key] = parseString();
            result.isString[key] = true;
        }
        else
        {
            const size_t start = i;
            while (i < text.size() && text[i] != ',' && text[i] != '}' &&
                   !std::isspace(static_cast<unsigned char>(text[i])))
            {
                ++i;
            }
            result.values[key] = text.substr(start, i - start);
            result.isString[key] = false;
        }
        skipSpace();
        if (i < text.size() && text[i] == ',')
        {
            ++i;
            skipSpace();
        }
    }
    if (i >= text.size())
    {
        throw fail("expected '}'");
    }
    return result;
}

std::string SelfDirectory()
{
    std::vector<char> buffer(4096);
    const ssize_t length = readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
    if (length <= 0)
    {
        throw std::runtime_error(std::string("cannot read /proc/self/exe: ") + std::strerror(errno));
    }
    std::string path(buffer.data(), static_cast<size_t>(length));
    const size_t slash = path.rfind('/');
    return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

/// Runs `program` with `args`, capturing its stdout (stderr is inherited). Returns the exit status (or
/// 128 + signal) and the output.
int RunCapture(const std::string& program, const std::vector<std::string>& args, std::string& output)
{
    int pipeFds[2];
    if (pipe(pipeFds) != 0)
    {
        throw std::runtime_error(std::string("pipe: ") + std::strerror(errno));
    }
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addclose(&actions, pipeFds[0]);
    posix_spawn_file_actions_adddup2(&actions, pipeFds[1], STDOUT_FILENO);
    posix_spawn_file_actions_addclose(&actions, pipeFds[1]);

    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (const std::string& arg : args)
    {
        argv.push_back(const_cast<char*>(arg.c_str()));
    }
    argv.push_back(nullptr);

    pid_t pid = 0;
    const int spawnError = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    close(pipeFds[1]);
    if (spawnError != 0)
    {
        close(pipeFds[0]);
        throw std::runtime_error("cannot run " + program + ": " + std::strerror(spawnError) +
                                 " (build the targets quadphase-demo-stock and quadphase-demo-quadtree)");
    }

    output.clear();
    char chunk[4096];
    for (;;)
    {
        const ssize_t n = read(pipeFds[0], chunk, sizeof chunk);
        if (n > 0)
        {
            output.append(chunk, static_cast<size_t>(n));
        }
        else if (n == 0 || errno != EINTR)
        {
            break;
        }
    }
    close(pipeFds[0]);

    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
    {
        if (errno != EINTR)
        {
            throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
        }
    }
    if (WIFEXITED(status))
    {
        return WEXITSTATUS(status);
    }
    return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
}

std::string CpuModel()
{
    std::ifstream cpuinfo("/proc/cpuinfo");
    std::string line;
    for (const char* key : {"model name", "Hardware", "Processor", "cpu model"})
    {
        cpuinfo.clear();
        cpuinfo.seekg(0);
        while (std::getline(cpuinfo, line))
        {
            if (line.rfind(key, 0) == 0)
            {
                const size_t colon = line.find(':');
                if (colon != std::string::npos)
                {
                    std::string value = line.substr(colon + 1);
                    value.erase(0, value.find_first_not_of(" \t"));
                    return value;
                }
            }
        }
    }
    return "unknown";
}

std::string LoadAverage()
{
    std::ifstream file("/proc/loadavg");
    std::string one, five, fifteen;
    if (file >> one >> five >> fifteen)
    {
        return one + " " + five + " " + fifteen;
    }
    return "unknown";
}

std::string Trim(std::string text)
{
    text.erase(0, text.find_first_not_of(' '));
    while (!text.empty() && text.back() == ' ')
    {
        text.pop_back();
    }
    std::string out;
    for (char c : text)
    {
        if (!(c == ' ' && !out.empty() && out.back() == ' '))
        {
            out += c;
        }
    }
    return out;
}

double Median(std::vector<double> values)
{
    if (values.empty())
    {
        return std::nan("");
    }
    std::sort(values.begin(), values.end());
    const size_t mid = values.size() / 2;
    return values.size() % 2 == 1 ? values[mid] : 0.5 * (values[mid - 1] + values[mid]);
}

/// Median over the runs of one numeric key; NaN when absent.
double MedianOf(const std::vector<RunResult>& runs, const std::string& key)
{
    std::vector<double> values;
    for (const RunResult& run : runs)
    {
        if (const auto value = run.Number(key))
        {
            values.push_back(*value);
        }
    }
    return Median(values);
}

std::string JsonNumber(double value)
{
    if (!std::isfinite(value))
    {
        return "null";
    }
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

std::string Format(double value, int decimals)
{
    if (std::isnan(value))
    {
        return "-";
    }
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
    return buffer;
}

void PrintHelp(const char* program)
{
    std::printf(
        "usage: %s [options]\n"
        "Steps one scene with stock Box2D 2.4.1 (dynamic AABB tree) and with the quadphase quadtree "
        "broadphase,\n"
        "running quadphase-demo-stock and quadphase-demo-quadtree (next to this program) alternately, and "
        "prints\n"
        "a side-by-side table of medians over the repeats, with stock/quadtree time ratios (> 1: quadtree "
        "faster).\n"
        "\n"
        "options:\n"
        "  --scene NAME   scene to step (default rain)\n"
        "  --size N       scene size (default: 16000 for rain, else the scene's default; see below)\n"
        "  --steps N      steps per run (default 300)\n"
        "  --warmup N     first steps left out of the timing statistics (default 10)\n"
        "  --seed N       scene seed, 0..4294967295 (default 1)\n"
        "  --repeat R     run stock, quadtree, stock, quadtree, ... R times each; report medians (default "
        "1)\n"
        "  --validate     quadtree run checks every UpdatePairs against a shadow b2DynamicTree; its times "
        "then\n"
        "                 include the shadow tree, so its ratios are meaningless; fails on a mismatch\n"
        "  --timing       quadtree run also times proxy updates (Stats::updateSeconds)\n"
        "  --json         print the medians as one JSON object instead of the table\n"
        "  --help         this text\n"
        "\n"
        "Broadphase ms is Box2D's b2Profile::broadphase (proxy synchronisation and new-pair search in\n"
        "b2World::Solve, pair callbacks included); step ms is b2Profile::step. 'new pairs at filtering' "
        "counts\n"
        "b2ContactFilter::ShouldCollide calls, the same metric in both builds. Positions may legitimately\n"
        "differ between the builds: the two broadphases report the same pairs in a different order.\n"
        "\n"
        "scenes:\n%s"
        "\n"
        "exit status: 0 ok, 1 a run failed (or validation found a mismatch), 2 bad options\n",
        program, quadphase::demo::SceneHelp().c_str());
}

struct Row
{
    const char* label;
    const char* key;
    int decimals;
    bool ratio; ///< print stock / quadtree
};

int Run(const Options& options)
{
    const std::string directory = SelfDirectory();
    const std::string stockProgram = directory + "/quadphase-demo-stock";
    const std::string quadtreeProgram = directory + "/quadphase-demo-quadtree";
    for (const std::string& program : {stockProgram, quadtreeProgram})
    {
        if (access(program.c_str(), X_OK) != 0)
        {
            std::fprintf(stderr,
                         "quadphase-demo: error: %s is missing or not executable\n"
                         "(build the targets quadphase-demo-stock and quadphase-demo-quadtree)\n",
                         program.c_str());
            return 1;
        }
    }

    std::vector<std::string> common = {"--scene",  options.scene,
                                       "--size",   std::to_string(options.size),
                                       "--steps",  std::to_string(options.steps),
                                       "--warmup", std::to_string(options.warmup),
                                       "--seed",   std::to_string(options.seed),
                                       "--json"};
    std::vector<std::string> quadtreeArgs = common;
    if (options.validate)
    {
        quadtreeArgs.push_back("--validate");
    }
    if (options.timing)
    {
        quadtreeArgs.push_back("--timing");
    }

    std::vector<RunResult> stockRuns;
    std::vector<RunResult> quadtreeRuns;
    bool validationFailed = false;
    for (int r = 0; r < options.repeat; ++r)
    {
        for (int v = 0; v < 2; ++v)
        {
            const bool quadtree = v == 1;
            const std::string& program = quadtree ? quadtreeProgram : stockProgram;
            if (!options.json)
            {
                std::fprintf(stderr, "quadphase-demo: run %d/%d %-8s ...", r + 1, options.repeat,
                             quadtree ? "quadtree" : "stock");
                std::fflush(stderr);
            }
            std::string output;
            const int status = RunCapture(program, quadtree ? quadtreeArgs : common, output);
            if (status != 0 && !(quadtree && options.validate && status == 1 && !output.empty()))
            {
                std::fprintf(stderr, "\nquadphase-demo: error: %s exited with status %d\n", program.c_str(),
                             status);
                return 1;
            }
            RunResult result = ParseFlatJson(output);
            if (!options.json)
            {
                std::fprintf(stderr, " %s s\n", result.Text("run_s").c_str());
            }
            if (quadtree)
            {
                validationFailed = validationFailed || status != 0;
                quadtreeRuns.push_back(std::move(result));
            }
            else
            {
                stockRuns.push_back(std::move(result));
            }
        }
    }

    const std::vector<Row> rows = {
        {"bodies", "bodies", 0, false},
        {"fixtures (proxies)", "fixtures", 0, false},
        {"contacts at end", "contacts_end", 0, false},
        {"contacts, mean per step", "contacts_mean", 1, false},
        {"new pairs at filtering", "pairs_filtered", 0, false},
        {"  per measured step", "pairs_filtered_per_step", 1, false},
        {"broadphase ms/step, median", "broadphase_ms_median", 3, true},
        {"broadphase ms/step, mean", "broadphase_ms_mean", 3, true},
        {"step ms, median", "step_ms_median", 3, true},
        {"step ms, mean", "step_ms_mean", 3, true},
        {"  collide ms, mean", "collide_ms_mean", 3, true},
        {"  solve ms (incl. bp), mean", "solve_ms_mean", 3, true},
        {"  time of impact ms, mean", "toi_ms_mean", 3, true},
        {"build s", "build_s", 3, false},
        {"run s (all steps)", "run_s", 3, true},
    };

    const std::string compiler = QUADPHASE_DEMO_COMPILER;
    const std::string buildType = QUADPHASE_DEMO_BUILD_TYPE;
    const std::string flags = Trim(QUADPHASE_DEMO_CXX_FLAGS);
    const std::string cpu = CpuModel();
    const unsigned cores = std::thread::hardware_concurrency();
    const long online = sysconf(_SC_NPROCESSORS_ONLN);

    if (options.json)
    {
        std::printf("{\n  \"scene\": \"%s\", \"size\": %d, \"steps\": %d, \"warmup\": %d, \"seed\": %u, "
                    "\"repeat\": %d,\n",
                    options.scene.c_str(), options.size, options.steps, options.warmup, options.seed,
                    options.repeat);
        std::printf("  \"cpu\": \"%s\", \"cores\": %ld, \"compiler\": \"%s\", \"build_type\": \"%s\", "
                    "\"flags\": \"%s\",\n",
                    cpu.c_str(), online, compiler.c_str(), buildType.c_str(), flags.c_str());
        for (const char* variant : {"stock", "quadtree"})
        {
            const std::vector<RunResult>& runs =
                std::strcmp(variant, "stock") == 0 ? stockRuns : quadtreeRuns;
            std::printf("  \"%s\": {", variant);
            bool first = true;
            for (const auto& entry : runs.front().values)
            {
                if (runs.front().isString.at(entry.first))
                {
                    continue;
                }
                std::printf("%s\"%s\": %s", first ? "" : ", ", entry.first.c_str(),
                            JsonNumber(MedianOf(runs, entry.first)).c_str());
                first = false;
            }
            std::printf(", \"position_hash\": \"%s\"},\n", runs.front().Text("position_hash").c_str());
        }
        std::printf("  \"ratio_stock_over_quadtree\": {");
        bool first = true;
        for (const Row& row : rows)
        {
            if (row.ratio)
            {
                std::printf(
                    "%s\"%s\": %s", first ? "" : ", ", row.key,
                    JsonNumber(MedianOf(stockRuns, row.key) / MedianOf(quadtreeRuns, row.key)).c_str());
                first = false;
            }
        }
        std::printf("},\n  \"validation_failed\": %s\n}\n", validationFailed ? "true" : "false");
        return validationFailed ? 1 : 0;
    }

    std::printf(
        "\nquadphase demo: scene %s, size %d, %d steps (%d warmup steps not timed), seed %u, %d run%s each\n",
        options.scene.c_str(), options.size, options.steps, options.warmup, options.seed, options.repeat,
        options.repeat == 1 ? "" : "s");
    std::printf("  %s\n", quadphase::scenes::GetSceneInfo(options.sceneId).description);
    std::printf("CPU: %s, %ld cores online (%u hardware threads), load average %s\n", cpu.c_str(), online,
                cores, LoadAverage().c_str());
    std::printf("Build: %s, %s, flags: %s\n", compiler.c_str(),
                buildType.empty() ? "(no build type)" : buildType.c_str(),
                flags.empty() ? "(none)" : flags.c_str());
    if (options.repeat > 1)
    {
        std::printf("Values are medians over the %d runs of each build.\n", options.repeat);
    }
    std::printf("\n%-30s %14s %14s %16s\n", "", "stock tree", "quadtree", "stock/quadtree");
    std::printf("%-30s %14s %14s %16s\n", "", "----------", "--------", "--------------");
    for (const Row& row : rows)
    {
        const double stock = MedianOf(stockRuns, row.key);
        const double quadtree = MedianOf(quadtreeRuns, row.key);
        std::string ratio;
        if (row.ratio && quadtree > 0.0 && !std::isnan(stock))
        {
            ratio = Format(stock / quadtree, 2) + "x";
        }
        std::printf("%-30s %14s %14s %16s\n", row.label, Format(stock, row.decimals).c_str(),
                    Format(quadtree, row.decimals).c_str(), ratio.c_str());
    }
    const std::string stockHash = stockRuns.back().Text("position_hash");
    const std::string quadtreeHash = quadtreeRuns.back().Text("position_hash");
    std::printf("%-30s %14s %14s %16s\n", "final position hash", stockHash.substr(0, 12).c_str(),
                quadtreeHash.substr(0, 12).c_str(), stockHash == quadtreeHash ? "same" : "differ");

    const RunResult& q = quadtreeRuns.back();
    std::printf("\nquadtree broadphase (state at the end of the run; counters cover the measured steps):\n");
    std::printf("  depth %s (leaf cells %s m), %s proxies (%s outside the bounds), %s occupied cells, "
                "largest cell %s\n",
                Format(MedianOf(quadtreeRuns, "qt_depth"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_leaf_size"), 3).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_proxies"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_outside"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_occupied_cells"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_largest_cell"), 0).c_str());
    std::printf("  memory %s MiB, %s rebuilds, %s UpdatePairs calls, %s pairs reported, %s proxies queried\n",
                Format(MedianOf(quadtreeRuns, "qt_memory_bytes") / (1024.0 * 1024.0), 2).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_rebuilds"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_update_pairs_calls"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_pairs_reported"), 0).c_str(),
                Format(MedianOf(quadtreeRuns, "qt_proxies_queried"), 0).c_str());
    std::printf("  pair generation %s ms/step (UpdatePairs without Box2D's callbacks)",
                Format(MedianOf(quadtreeRuns, "qt_pair_ms_per_step"), 3).c_str());
    if (options.timing)
    {
        std::printf(", proxy updates %s ms/step",
                    Format(MedianOf(quadtreeRuns, "qt_update_ms_per_step"), 3).c_str());
    }
    std::printf("\n");
    if (options.validate)
    {
        std::printf("  validation: %s checks, %s pairs compared, %s mismatches%s%s\n",
                    Format(MedianOf(quadtreeRuns, "validation_checks"), 0).c_str(),
                    Format(MedianOf(quadtreeRuns, "validation_pairs_compared"), 0).c_str(),
                    q.Text("validation_mismatches").c_str(), validationFailed ? ": FAILED, first: " : "",
                    q.Text("validation_first_mismatch").c_str());
        std::printf("  (validation on: the quadtree times include the shadow tree; ignore the ratios)\n");
    }
    return validationFailed ? 1 : 0;
}

} // namespace

int main(int argc, char** argv)
{
    const char* program = "quadphase-demo";
    try
    {
        const std::vector<std::string> args(argv + (argc > 0 ? 1 : 0), argv + argc);
        Options options = quadphase::demo::ParseOptions(args, {/*repeat=*/true});
        if (options.help)
        {
            PrintHelp(program);
            return 0;
        }
        return Run(options);
    }
    catch (const UsageError& error)
    {
        std::fprintf(stderr, "%s: error: %s\n(try %s --help)\n", program, error.what(), program);
        return 2;
    }
    catch (const std::exception& error)
    {
        std::fprintf(stderr, "%s: error: %s\n", program, error.what());
        return 1;
    }
}
