// SPDX-License-Identifier: MIT
// qp-replay: replays a trace (qp-record) through a broadphase and times the broadphase work of each recorded
// step (definition in replay_loop.h): quadphase::QuadtreeBroadPhase (this file; any Config), stock
// Box2D 2.4.1's b2BroadPhase and the peers (replay_peers.cpp: brute force, the paper's design, Chipmunk2D,
// Bullet, the oracle floor, and a null engine: the replay loop alone). Also: --triad (the memory floor's
// bandwidth), --omp-overhead (the cost of a parallel region), --print-config (the core's defaults). Usage:
// qp-replay --help.
//
// Every --config is the base settings (--threads ... --threshold) with some keys overridden; without --config
// there is one configuration, the base. The timed runs go round the configurations R times (configuration
// order within each round), so slow phases of a noisy machine hit every configuration alike.
//
// --check first|all: before the timed runs, one untimed checking run per configuration (first: only the first
// one) hashes the pair set of every UpdatePairs call (--hashes-out writes the first configuration's hashes;
// --compare-hashes compares each checked configuration against a file, e.g. --engine stock's) and gathers
// query statistics (cells and candidates per query, buffered proxies per UpdatePairs call). --brute also
// replays through BruteForceBroadPhase (small traces only) and compares.
//
// --per-call adds to the JSON lines the FindPairs time of every timed UpdatePairs call (timed runs) and its
// number of buffered proxies (checking runs; the same for every configuration, since it depends only on the
// trace), so the cost of a call can be studied by its size (where a parallel region starts paying).
#include <cstdio>
#include <memory>
#include <sstream>
#include <string>

#include <omp.h>

#include "brute_force_broad_phase.h"
#include "core_engine.h"
#include "loaded_trace.h"
#include "pair_hash.h"
#include "quadphase/config.h"
#include "quadtree_broad_phase.h"
#include "replay_loop.h"
#include "step_index.h"
#include "timed_run.h"

namespace
{

using namespace qpbench;
using quadphase::Config;
using quadphase::ProxyId;
using quadphase::Schedule;

// Indexed by quadphase::Schedule.
const char* const kScheduleNames[] = {"static", "dynamic", "guided", "auto"};
static_assert(omp_sched_static == 1 && omp_sched_dynamic == 2 && omp_sched_guided == 3,
              "--omp-overhead's order");

int ToInt(const std::string& key, const std::string& v)
{
    long x = 0;
    if (!ParseLong(v, x))
    {
        Die(2, "qp-replay: %s: '%s' is not an integer\n", key.c_str(), v.c_str());
    }
    return int(x);
}

void SetKey(Config& c, const std::string& key, const std::string& value)
{
    if (key == "threads")
        c.threads = ToInt(key, value);
    else if (key == "chunk")
        c.chunk = ToInt(key, value);
    else if (key == "depth")
        c.depth = value == "auto" ? -1 : ToInt(key, value);
    else if (key == "threshold")
        c.parallelThreshold = ToInt(key, value);
    else if (key == "schedule")
    {
        const auto* k = std::find(std::begin(kScheduleNames), std::end(kScheduleNames), value);
        if (k == std::end(kScheduleNames))
        {
            Die(2, "qp-replay: unknown schedule '%s'\n", value.c_str());
        }
        c.schedule = Schedule(k - std::begin(kScheduleNames));
    }
    else
    {
        Die(2, "qp-replay: unknown --config key '%s'\n", key.c_str());
    }
}

std::string Describe(const Config& c)
{
    char buf[160];
    std::snprintf(buf, sizeof(buf), "threads=%d schedule=%s chunk=%d depth=%s threshold=%d", c.threads,
                  kScheduleNames[int(c.schedule)], c.chunk,
                  c.depth < 0 ? "auto" : std::to_string(c.depth).c_str(), c.parallelThreshold);
    return buf;
}

// ---------------------------------------------------------------------------------------------------------------
// Query statistics for the checking run (timed steps only).
// ---------------------------------------------------------------------------------------------------------------
struct QueryStats
{
    // Buckets of buffered proxies per UpdatePairs call, by the thresholds the sweep uses.
    static constexpr int kBuckets = 8;
    // Bucket b: [edge b, edge b+1).
    static constexpr int kEdges[kBuckets] = {0, 1, 64, 128, 256, 512, 1024, 4096};
    int64_t callsIn[kBuckets] = {};
    int64_t queriesIn[kBuckets] = {};

    int64_t calls = 0;
    int64_t queries = 0;     // buffered live proxies queried
    int64_t cells = 0;       // cells read over the non-empty levels (Pyramid::VisitCost)
    int64_t candidates = 0;  // entries read, the query's own entry excluded
    int64_t overlaps = 0;    // candidates whose fat box overlaps (before the "both buffered" de-duplication)
    int64_t pairs = 0;       // pairs reported
    int64_t maxBuffered = 0; // largest call
    std::vector<int32_t> callBuffered; // buffered proxies of every timed call, in order

    template <typename Engine>
    void BeforeUpdatePairs(Engine& engine, bool timed)
    {
        std::vector<ProxyId> buffered = engine.TakeBuffered();
        if (!timed)
        {
            return;
        }
        const int64_t n = int64_t(buffered.size());
        const int b = int(std::upper_bound(kEdges, kEdges + kBuckets, n) - kEdges) - 1; // the last edge <= n
        callsIn[b] += 1;
        queriesIn[b] += n;
        calls += 1;
        queries += n;
        maxBuffered = std::max(maxBuffered, n);
        callBuffered.push_back(int32_t(n));

        m_pending = std::move(buffered);
    }
    template <typename Engine>
    void AfterUpdatePairs(Engine& engine, bool timed)
    {
        if (!timed)
        {
            return;
        }
        pairs += int64_t(engine.PairCount());
        // After the call the pyramid is the one its queries read (stale entries written, any re-tune done),
        // and FindPairs reads, per buffered proxy, exactly what Pyramid::Visit reads: these counts are exact.
        const quadphase::QuadtreeBroadPhase& bp = engine.Get();
        const quadphase::Pyramid& pyramid = bp.GetPyramid();
        for (ProxyId q : m_pending)
        {
            const quadphase::Box qb = bp.GetFatBox(q);
            for (int level = 0; level <= pyramid.Depth(); ++level)
            {
                cells += pyramid.LevelCount(level) > 0 ? pyramid.VisitCost(level, qb) : 0;
            }
            pyramid.Visit(qb, [&](const quadphase::Entry& e) {
                if (e.id != q)
                {
                    candidates += 1;
                    overlaps += quadphase::Overlaps(e.box, qb) ? 1 : 0;
                }
                return true;
            });
        }
    }
    std::vector<ProxyId> m_pending;
};

/// Cost of one parallel region (an OpenMP loop over `blocks` empty iterations at `threads`), median of many.
double ParallelRegionMicros(int threads, omp_sched_t kind, int blocks)
{
    std::vector<double> samples;
    volatile int sink = 0;
    omp_set_schedule(kind, 0);
    for (int round = 0; round < 41; ++round)
    {
        const int64_t t0 = NowNs();
        for (int r = 0; r < 200; ++r)
        {
#pragma omp parallel for schedule(runtime) num_threads(threads)
            for (int b = 0; b < blocks; ++b)
            {
                sink = sink + 0;
            }
        }
        samples.push_back(double(NowNs() - t0) / 200.0 / 1000.0);
    }
    return Median(samples);
}

/// STREAM's triad a[i] = b[i] + s * c[i] over three arrays of `n` doubles, one thread: the best of `repeats`
/// passes, in bytes per second (24 bytes per element, STREAM's count).
double TriadBytesPerSecond(size_t n, int repeats)
{
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    double best = 1e30;
    for (int r = 0; r < repeats; ++r)
    {
        const int64_t t0 = NowNs();
        const double scalar = 3.0 + r;
        for (size_t i = 0; i < n; ++i)
        {
            a[i] = b[i] + scalar * c[i];
        }
        best = std::min(best, double(NowNs() - t0) * 1e-9);
        b[r % n] = a[(r * 7) % n]; // keeps the passes from being merged
    }
    return 24.0 * double(n) / best;
}

} // namespace

int main(int argc, char** argv)
{
    const Args args(argc, argv, "qp-replay",
                    {"trace", "threads", "schedule", "chunk", "depth", "threshold", "config", "repeats",
                     "check", "hashes-out", "compare-hashes", "engine", "json", "label", "levels",
                     "max-proxies"},
                    {"brute", "omp-overhead", "per-call", "print-config", "triad"});
    args.Check(
        args.Has("trace") || args.Has("omp-overhead") || args.Has("print-config") || args.Has("triad"),
        "usage: qp-replay --trace FILE [--engine NAME] [--repeats R] [--check none|first|all]\n"
        "                 [--hashes-out FILE] [--compare-hashes FILE] [--json FILE] [--label TEXT]\n"
        "  quadtree (default): [--threads N] [--schedule static|dynamic|guided|auto] [--chunk C]\n"
        "                 [--depth D|auto] [--threshold T] [--config k=v,k=v]... [--per-call]\n"
        "                 [--brute [--max-proxies N]]\n"
        "  null: the replay loop alone; stock, brute ([--max-proxies N]), paper ([--levels L|auto]\n"
        "  [--threads N]), oracle, cp-hash-xK, cp-tree, bt-dbvt, and -native[-mM] modes of cp-hash-xK,\n"
        "  cp-tree, bt-dbvt, bt-sap (replay_peers.cpp)\n"
        "  qp-replay --omp-overhead | --triad | --print-config\n"
        "available here: stock brute paper oracle%s%s\n",
        QP_HAVE_CHIPMUNK ? " cp-hash cp-tree" : "", QP_HAVE_BULLET ? " bt-dbvt bt-sap" : "");
    if (args.Has("print-config"))
    {
        // The core's defaults, for scripts (bench/parallel.py reads the default parallelThreshold).
        std::printf("default_config %s\n", Describe(Config{}).c_str());
        return 0;
    }
    PrintMachine(stdout);
    const std::string jsonPath = args.Get("json");
    const auto toolJson = [&](const char* kind) {
        JsonLine j;
        j.Str("tool", "qp-replay").Str("kind", kind).Str("label", args.Get("label"));
        return j;
    };

    if (args.Has("triad"))
    {
        // The memory floor's bandwidth: 3 x 64 MB, far beyond the caches.
        const double bps = TriadBytesPerSecond(size_t(8) << 20, 10);
        std::printf("triad, 1 thread: %.2f GB/s\n", bps * 1e-9);
        AppendLine(jsonPath, toolJson("triad").Num("bytes_per_s", bps).Text());
        if (!args.Has("trace"))
        {
            return 0;
        }
    }
    if (args.Has("omp-overhead"))
    {
        // The fixed cost FindPairs pays to go parallel, for the threshold discussion. Schedules static, dynamic
        // and guided: omp_sched_t numbers them from 1 in kScheduleNames' order.
        for (int blocks : {1, 8, 64})
        {
            for (int k = 0; k < 3; ++k)
            {
                const double us = ParallelRegionMicros(2, omp_sched_t(k + 1), blocks);
                std::printf("omp parallel region, 2 threads, %s, %d empty iterations: %.2f us\n",
                            kScheduleNames[k], blocks, us);
                AppendLine(jsonPath, toolJson("omp_overhead")
                                         .Str("schedule", kScheduleNames[k])
                                         .Int("threads", 2)
                                         .Int("blocks", blocks)
                                         .Num("us", us)
                                         .Text());
            }
        }
        if (!args.Has("trace"))
        {
            return 0;
        }
    }

    LoadedTrace loaded;
    LoadOrDie(args.Get("trace"), loaded);
    const StepIndex& index = loaded.steps;
    std::printf("trace %s: scene %s size %d, %zu ops, %lld UpdatePairs calls, %d warm-up + %d timed steps, "
                "%lld proxies at the end\n",
                loaded.path.c_str(), index.scene.c_str(), index.size, loaded.trace.Ops().size(),
                static_cast<long long>(loaded.trace.UpdatePairsCount()), index.warmup, index.steps,
                static_cast<long long>(index.proxies));

    Config base;
    for (const char* key : {"threads", "schedule", "chunk", "depth", "threshold"})
    {
        if (args.Has(key))
        {
            SetKey(base, key, args.Get(key));
        }
    }
    std::vector<Config> configs;
    for (const std::string& spec : args.GetAll("config"))
    {
        Config c = base;
        std::stringstream fields(spec);
        std::string kv;
        while (std::getline(fields, kv, ','))
        {
            const size_t eq = kv.find('=');
            if (eq == std::string::npos)
            {
                Die(2, "qp-replay: --config '%s': expected key=value\n", spec.c_str());
            }
            SetKey(c, kv.substr(0, eq), kv.substr(eq + 1));
        }
        configs.push_back(c);
    }
    if (configs.empty())
    {
        configs.push_back(base);
    }
    const int repeats = int(args.GetInt("repeats", 5));
    const std::string engineName = args.Get("engine", "quadtree");
    const std::string check = args.Get("check", "first");
    const bool perCall = args.Has("per-call");

    const auto baseJson = [&](const char* kind) {
        JsonLine j = toolJson(kind);
        j.Str("trace", loaded.name)
            .Str("scene", index.scene)
            .Int("size", index.size)
            .Int("warmup", index.warmup);
        return j;
    };
    // Checking runs: the first configuration (first) or every one (all).
    const size_t checked = check == "none" ? 0 : check == "first" ? 1 : configs.size();
    std::vector<Contender> contenders;
    if (engineName != "quadtree")
    {
        const PeerRun run{args, loaded, engineName, [&](const char* kind) {
                              JsonLine j = baseJson(kind);
                              j.Str("engine", engineName).Int("threads", int(args.GetInt("threads", 1)));
                              return j;
                          }};
        contenders.push_back(PeerContender(run));
        Drive(contenders, checked, repeats);
        return 0;
    }
    auto configJson = [&](JsonLine& j, const Config& c) {
        j.Int("threads", c.threads)
            .Str("schedule", kScheduleNames[int(c.schedule)])
            .Int("chunk", c.chunk)
            .Int("depth", c.depth)
            .Int("threshold", c.parallelThreshold);
    };

    std::vector<CallHash> brute;
    if (checked > 0 && args.Has("brute"))
    {
        RefuseLargeBrute(args, loaded);
        CoreEngine<quadphase::BruteForceBroadPhase> engine;
        Replay(loaded, engine, &brute);
        std::printf("brute force: %zu UpdatePairs calls hashed\n", brute.size());
    }
    const std::string compareWith = args.Get("compare-hashes");
    const std::vector<CallHash> reference = LoadHashesOrDie(checked > 0 ? compareWith : "");
    using Quadtree = CoreEngine<quadphase::QuadtreeBroadPhase>;
    for (const Config& c : configs)
    {
        const bool first = contenders.empty();
        const auto checkRun = [&, c, first] {
            Quadtree engine(quadphase::FatPolicy{}, c);
            engine.SetTracking(true);
            QueryStats qs;
            std::vector<CallHash> hashes;
            Replay(loaded, engine, &hashes, &qs);
            const quadphase::Stats st = engine.Get().GetStats();
            int64_t bad = 0;
            if (!brute.empty())
            {
                bad += CompareHashes(hashes, brute, "quadtree", "brute force");
            }
            if (!reference.empty())
            {
                bad += CompareHashes(hashes, reference, "quadtree", compareWith.c_str());
            }
            if (first && args.Has("hashes-out"))
            {
                SaveHashesOrDie(args.Get("hashes-out"), hashes);
            }
            const double q = double(std::max<int64_t>(1, qs.queries));
            std::printf(
                "check [%s]: %zu calls hashed, %s; depth %d, leaf %.3g m, %.3g buffered/call, %.3g cells, "
                "%.3g candidates, %.3g overlaps, %.3g pairs per query\n",
                Describe(c).c_str(), hashes.size(),
                bad != 0 ? "MISMATCH" : (brute.empty() && reference.empty() ? "not compared" : "identical"),
                st.depth, double(st.leafSize), double(qs.queries) / double(std::max<int64_t>(1, qs.calls)),
                double(qs.cells) / q, double(qs.candidates) / q, double(qs.overlaps) / q,
                double(qs.pairs) / q);
            JsonLine j = baseJson("check");
            configJson(j, c);
            j.Int("calls_hashed", int64_t(hashes.size()))
                .Int("mismatches", bad)
                .Int("compared_brute", brute.empty() ? 0 : 1)
                .Int("compared_file", reference.empty() ? 0 : 1)
                .Int("depth_used", st.depth)
                .Num("leaf_size", st.leafSize)
                .Int("proxies", st.proxyCount)
                .Int("occupied_cells", st.occupiedCells)
                .Int("largest_cell", st.largestCell)
                .Int("memory_bytes", st.memoryBytes)
                .Int("timed_calls", qs.calls)
                .Int("queries", qs.queries)
                .Int("cells", qs.cells)
                .Int("candidates", qs.candidates)
                .Int("overlaps", qs.overlaps)
                .Int("pairs", qs.pairs)
                .Int("max_buffered", qs.maxBuffered)
                // The memory floor's bytes over the timed steps: each query's fat box, the entries it reads
                // (its own included), the pairs written.
                .Int("floor_bytes", int64_t(sizeof(quadphase::Box)) * qs.queries +
                                        int64_t(sizeof(quadphase::Entry)) * (qs.candidates + qs.queries) +
                                        int64_t(sizeof(quadphase::Pair)) * qs.pairs)
                .Int("timed_steps", index.steps)
                .Array("bucket_edges", QueryStats::kEdges)
                .Array("bucket_calls", qs.callsIn)
                .Array("bucket_queries", qs.queriesIn)
                .Array("proxies_per_level", st.proxiesPerLevel);
            if (perCall)
            {
                j.Array("calls_buffered", qs.callBuffered);
            }
            AppendLine(jsonPath, j.Text());
            return bad;
        };
        const auto timed = [&, c](Timings& t) {
            JsonLine j = baseJson("run");
            j.Str("engine", "quadtree");
            configJson(j, c);
            const auto make = [&] {
                return std::make_unique<Quadtree>(quadphase::FatPolicy{}, c);
            };
            TimedRun(
                loaded, jsonPath, j, t, make, [&](JsonLine& line, Quadtree& engine, const RunResult& result) {
                    const quadphase::Stats st = engine.Get().GetStats();
                    // updateSeconds: the time the core itself booked as grid maintenance during the timed steps
                    // (MoveProxy timing is off, so with deferred maintenance this is the batched re-placement inside
                    // FindPairs).
                    line.Int("depth_used", st.depth)
                        .Int("parallel_calls", st.parallelCalls)
                        .Int("reinserts", st.reinserts)
                        .Int("proxies_queried", st.proxiesQueried)
                        .Int("rebuilds", st.rebuilds)
                        .Num("replace_s", st.updateSeconds);
                    if (perCall)
                    {
                        line.Array("calls_ns", result.callNs);
                    }
                });
        };
        contenders.push_back(Contender{{Describe(c), {}, {}}, checkRun, timed});
    }
    Drive(contenders, checked, repeats);
    return 0;
}
