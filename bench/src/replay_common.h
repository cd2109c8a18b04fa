// qp-replay's trace replay, for every engine: a trace and its step index (qp-record writes them), the replay
// loop and its timing definition, pair-set hashes, heap bytes (tool_common.h: the rest).
//
// Timing definition (the same for every engine):
// - The ops before the first timed step (scene creation and the warm-up steps) are replayed untimed: they
// bring
//   the broadphase to the state the recorded world had.
// - A timed step is the ops between two step boundaries of the ".steps" file. Its time is one clock read pair
//   around all of them: every CreateProxy/DestroyProxy/MoveProxy/TouchProxy/ShiftOrigin plus every
//   UpdatePairs (FindPairs into a vector; for the stock class, its AddPair callback appends to a vector). The
//   dispatch over the recorded ops and the recorded-id -> engine-id lookup are inside it (the null engine of
//   qp-replay measures that overhead alone).
// - "FindPairs time" is the sum of clock read pairs around each UpdatePairs of the step.
// - Work done only for checking (hashing pair sets, query statistics) is done on a separate, untimed run.
#pragma once

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <malloc.h>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h> // instruction counts of the timed steps only: valgrind --tool=callgrind --instr-atstart=no
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include "box2d/b2_collision.h"
#include "tool_common.h"
#include "trace.h"

namespace qpbench
{

using quadphase::Box;
using quadphase::Trace;
using quadphase::TraceOp;
using quadphase::Vec2;

// ---------------------------------------------------------------------------------------------------------------
// The ".steps" side file qp-record writes next to a trace: which scene it came from and the op index of every
// world-step boundary, so a replay can time the broadphase work of each step.
//
// Text format, one "key value..." per line:
//     qp-steps 1
//     scene particles
//     size 50000
//     seed 1
//     warmup 60            steps replayed untimed (they bring the broadphase to the recorded state)
//     steps 30             steps timed
//     bodies 50001         at the end of the recording
//     proxies 50004        at the end of the recording
//     boundary 50004       op index where step 0 starts (the ops before it create the scene's proxies)
//     boundary 100321      op index where step 1 starts / step 0 ends
//     ...                  warmup + steps + 1 boundary lines in all
// Step k (0-based) is ops [boundary[k], boundary[k+1]): everything the broadphase was asked between the start
// of world.Step number k and the start of world.Step number k+1 (including what the scene's perStep did in
// between).
// ---------------------------------------------------------------------------------------------------------------
struct StepIndex
{
    std::string scene;
    int size = 0, warmup = 0, steps = 0;
    uint32_t seed = 0;
    int64_t bodies = 0, proxies = 0; // at the end of the recording
    std::vector<uint64_t> boundary;  // warmup + steps + 1 entries

    bool Save(const std::string& path, std::string& error) const
    {
        std::ofstream out(path);
        const bool opened = out.is_open(); // a stream that failed to open writes nothing below
        out << "qp-steps 1\n";
        out << "scene " << scene << "\nsize " << size << "\nseed " << seed << "\n";
        out << "warmup " << warmup << "\nsteps " << steps << "\n";
        out << "bodies " << bodies << "\nproxies " << proxies << "\n";
        for (uint64_t b : boundary)
        {
            out << "boundary " << b << "\n";
        }
        error = !opened ? "cannot open " + path + " for writing" : !out ? "cannot write " + path : "";
        return error.empty();
    }

    bool Load(const std::string& path, std::string& error)
    {
        std::ifstream in(path);
        if (!in)
        {
            error = "cannot open " + path;
            return false;
        }
        int version = 0;
        std::string line;
        boundary.clear();
        while (std::getline(in, line))
        {
            std::istringstream fields(line);
            std::string key;
            fields >> key;
            const auto field = [&](const char* name, auto& value) {
                if (key == name)
                {
                    fields >> value;
                }
            };
            if (key == "boundary")
            {
                fields >> boundary.emplace_back();
            }
            field("qp-steps", version);
            field("scene", scene);
            field("size", size);
            field("seed", seed);
            field("warmup", warmup);
            field("steps", steps);
            field("bodies", bodies);
            field("proxies", proxies);
        }
        const bool counted =
            warmup >= 0 && steps > 0 && boundary.size() == size_t(warmup) + size_t(steps) + 1;
        error = version != 1 ? path + " is not a qp-steps v1 file"
                : !counted   ? path + ": expected warmup + steps + 1 boundary lines"
                : !std::is_sorted(boundary.begin(), boundary.end()) ? path + ": boundaries are not increasing"
                                                                    : "";
        return error.empty();
    }
};

// Heap bytes in use by the process (glibc's mallinfo2: small blocks in use plus mmap'ed blocks). The replay
// tools read it before building an engine and after replaying the whole trace through it: the difference is
// what the engine holds (its index, id maps, buffers and its pair vector), measured the same way for every
// engine, whatever allocator wrapper it uses internally (Box2D's b2Alloc, Chipmunk's cpcalloc and Bullet's
// btAlignedAlloc all end in malloc).
inline int64_t HeapBytes()
{
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    const struct mallinfo2 mi = mallinfo2();
    return int64_t(mi.uordblks) + int64_t(mi.hblkhd);
#else
    return 0; // unknown: reported as 0 bytes
#endif
}

/// quadphase's Box as Box2D's b2AABB, for the tools that drive stock Box2D's b2BroadPhase (qp-replay,
/// qp-circles).
inline b2AABB ToAabb(const quadphase::Box& b)
{
    b2AABB a;
    a.lowerBound.Set(b.minX, b.minY);
    a.upperBound.Set(b.maxX, b.maxY);
    return a;
}

/// The paper's design's level count (bench/baselines) for leaves at least `leaf` wide in a square of side
/// `side`: the most levels, up to `maxLevels`, that keep them so; 1 when none does (qp-replay's and
/// qp-circles' auto).
inline int PaperLevelsFor(double side, double leaf, int maxLevels)
{
    int levels = 1;
    while (levels < maxLevels && side / double(1 << levels) >= leaf)
    {
        ++levels;
    }
    return levels;
}

// ---------------------------------------------------------------------------------------------------------------
// Pair-set hashes: for each UpdatePairs call, the sorted unique list of pairs in recorded ids (a < b) is
// hashed (FNV-1a over the 64-bit keys a << 32 | b). Duplicates (the stock class may report a pair twice) do
// not count.
// ---------------------------------------------------------------------------------------------------------------
struct CallHash
{
    uint64_t count = 0; // unique pairs
    uint64_t hash = 0;
};

inline uint64_t PairKey(int32_t a, int32_t b)
{
    if (a > b)
    {
        std::swap(a, b);
    }
    return (uint64_t(uint32_t(a)) << 32) | uint64_t(uint32_t(b));
}

inline CallHash HashPairKeys(std::vector<uint64_t>& keys)
{
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return CallHash{uint64_t(keys.size()), Fnv1a64(keys)};
}

/// Writes "call count hash" lines (call = index of the UpdatePairs call in the trace, from 0); exits when it
/// cannot.
inline void SaveHashesOrDie(const std::string& path, const std::vector<CallHash>& hashes)
{
    std::FILE* out = std::fopen(path.c_str(), "w");
    bool ok =
        out != nullptr &&
        std::fprintf(out,
                     "# qp-pairhash 1: call unique_pairs fnv1a64(sorted unique pairs in recorded ids)\n") > 0;
    for (size_t i = 0; ok && i < hashes.size(); ++i)
    {
        ok = std::fprintf(out, "%zu %llu %016llx\n", i, static_cast<unsigned long long>(hashes[i].count),
                          static_cast<unsigned long long>(hashes[i].hash)) > 0;
    }
    if (out == nullptr || std::fclose(out) != 0 || !ok)
    {
        Die(1, "qp-replay: cannot write %s\n", path.c_str());
    }
}

/// The hashes SaveHashesOrDie wrote to `path` (none when `path` is empty); exits when they cannot be read.
inline std::vector<CallHash> LoadHashesOrDie(const std::string& path)
{
    std::vector<CallHash> hashes;
    if (path.empty())
    {
        return hashes;
    }
    std::ifstream in(path);
    bool ok = in.is_open();
    std::string line;
    while (ok && std::getline(in, line))
    {
        unsigned long long index = 0, count = 0, hash = 0;
        if (!line.empty() && line[0] != '#')
        {
            ok = std::sscanf(line.c_str(), "%llu %llu %llx", &index, &count, &hash) == 3 &&
                 index == hashes.size();
            hashes.push_back(CallHash{count, hash});
        }
    }
    if (!ok)
    {
        Die(1, "qp-replay: cannot read hashes from %s\n", path.c_str());
    }
    return hashes;
}

/// Number of calls whose hashes differ (a length difference counts as mismatches); prints the first few.
inline int64_t CompareHashes(const std::vector<CallHash>& mine, const std::vector<CallHash>& reference,
                             const char* mineName, const char* referenceName)
{
    int64_t mismatches = 0;
    const size_t n = std::max(mine.size(), reference.size());
    for (size_t i = 0; i < n; ++i)
    {
        const bool same = i < mine.size() && i < reference.size() && mine[i].hash == reference[i].hash &&
                          mine[i].count == reference[i].count;
        if (!same)
        {
            if (mismatches < 5)
            {
                std::fprintf(
                    stderr, "MISMATCH at UpdatePairs call %zu: %s %llu pairs, %s %llu pairs\n", i, mineName,
                    i < mine.size() ? static_cast<unsigned long long>(mine[i].count) : 0ull, referenceName,
                    i < reference.size() ? static_cast<unsigned long long>(reference[i].count) : 0ull);
            }
            ++mismatches;
        }
    }
    return mismatches;
}

// ---------------------------------------------------------------------------------------------------------------
// Loading.
// ---------------------------------------------------------------------------------------------------------------
struct LoadedTrace
{
    std::string path;
    std::string name; // file name without directory and extension
    Trace trace;
    StepIndex steps;
    int32_t idBound = 0; // 1 + the largest recorded id
};

/// Loads `path` and `path + ".steps"`, and checks that the ops form a valid call sequence:
/// every id is live where it is used, and boundaries lie within the trace. Exits on error.
inline void LoadOrDie(const std::string& path, LoadedTrace& loaded)
{
    std::string error;
    loaded.path = path;
    const std::string file = path.substr(path.find_last_of('/') + 1); // npos + 1: no directory
    loaded.name = file.substr(0, file.find('.'));
    if (!loaded.trace.Load(path, error) || !loaded.steps.Load(path + ".steps", error))
    {
        Die(1, "%s\n", error.c_str());
    }
    const std::vector<TraceOp>& ops = loaded.trace.Ops();
    if (loaded.steps.boundary.back() != ops.size())
    {
        Die(1, "%s: the step file ends at op %llu but the trace has %zu ops\n", path.c_str(),
            static_cast<unsigned long long>(loaded.steps.boundary.back()), ops.size());
    }
    std::vector<uint8_t> live; // grows to 1 + the largest created id
    for (size_t i = 0; i < ops.size(); ++i)
    {
        const TraceOp& op = ops[i];
        const bool usesId =
            op.kind == TraceOp::Destroy || op.kind == TraceOp::Move || op.kind == TraceOp::Touch;
        if (op.kind == TraceOp::Create)
        {
            live.resize(std::max(live.size(), size_t(std::max(op.id, 0)) + 1), 0);
            if (op.id < 0 || live[size_t(op.id)])
            {
                Die(1, "%s: op %zu creates id %d, which is live\n", path.c_str(), i, int(op.id));
            }
            live[size_t(op.id)] = 1;
        }
        else if (usesId && (op.id < 0 || size_t(op.id) >= live.size() || !live[size_t(op.id)]))
        {
            Die(1, "%s: op %zu uses id %d, which is not live\n", path.c_str(), i, int(op.id));
        }
        else if (op.kind == TraceOp::Destroy)
        {
            live[size_t(op.id)] = 0;
        }
    }
    loaded.idBound = int32_t(live.size());
}

// ---------------------------------------------------------------------------------------------------------------
// The replay loop.
// ---------------------------------------------------------------------------------------------------------------
struct StepSample
{
    int64_t ns = 0;      // whole broadphase work of the step
    int64_t findNs = 0;  // UpdatePairs calls only
    int32_t calls = 0;   // UpdatePairs calls
    int64_t pairs = 0;   // pairs reported (as the engine reports them: the stock class may repeat a pair)
    int32_t proxies = 0; // live proxies when the step starts
    int32_t ops = 0;     // recorded calls other than UpdatePairs
};

struct RunResult
{
    std::vector<StepSample> steps;
    // Every UpdatePairs call of the timed steps, in order: its own clock-read pair.
    std::vector<int32_t> callNs;
    double setupSeconds = 0.0; // untimed prefix (creation + warm-up)

    /// One field of every step, in order, and its sum.
    template <typename T>
    std::vector<int64_t> Column(T StepSample::*field) const
    {
        std::vector<int64_t> column;
        for (const StepSample& s : steps)
        {
            column.push_back(s.*field);
        }
        return column;
    }
    template <typename T>
    int64_t Total(T StepSample::*field) const
    {
        const std::vector<int64_t> column = Column(field);
        return std::accumulate(column.begin(), column.end(), int64_t(0));
    }
};

/// Hooks for the untimed checking run. `BeforeUpdatePairs(engine, timed)` runs before each UpdatePairs;
/// `AfterUpdatePairs(engine, timed)` after it. Neither is called in timed runs.
struct NoObserver
{
    template <typename Engine>
    void BeforeUpdatePairs(Engine&, bool)
    {
    }
    template <typename Engine>
    void AfterUpdatePairs(Engine&, bool)
    {
    }
};

/// Engine concept:
///   int32_t Create(const Box& tight, int32_t recordedId);   // returns the engine's id
///   void Destroy(int32_t id); void Move(int32_t id, const Box& tight, Vec2 d); void Touch(int32_t id);
///   void UpdatePairs(); void ShiftOrigin(Vec2); int32_t ProxyCount() const; size_t PairCount() const;
///   void PairKeys(std::vector<uint64_t>& keys) const;         // the last call's pairs in recorded ids
///   void BeginTimedSteps();                                   // e.g. reset counters (outside any timing)
template <typename Engine>
inline void ApplyOp(Engine& engine, const TraceOp& op, std::vector<int32_t>& map)
{
    switch (op.kind)
    {
    case TraceOp::Create:
        map[size_t(op.id)] = engine.Create(op.box, op.id);
        break;
    case TraceOp::Destroy:
        engine.Destroy(map[size_t(op.id)]);
        map[size_t(op.id)] = -1;
        break;
    case TraceOp::Move:
        engine.Move(map[size_t(op.id)], op.box, op.displacement);
        break;
    case TraceOp::Touch:
        engine.Touch(map[size_t(op.id)]);
        break;
    case TraceOp::ShiftOrigin:
        engine.ShiftOrigin(op.displacement);
        break;
    case TraceOp::UpdatePairs:
        break; // handled by the caller
    }
}

/// Replays the whole trace through `engine`. With `hashes` (untimed checking run), the pair set of every
/// UpdatePairs call is hashed; `observer` hooks run around every call. Timings of a checking run are
/// meaningless.
template <typename Engine, typename Observer = NoObserver>
RunResult Replay(const LoadedTrace& loaded, Engine& engine, std::vector<CallHash>* hashes = nullptr,
                 Observer* observer = nullptr)
{
    const std::vector<TraceOp>& ops = loaded.trace.Ops();
    const StepIndex& index = loaded.steps;
    std::vector<int32_t> map(size_t(loaded.idBound), -1);
    std::vector<uint64_t> keys;
    const bool checking = hashes != nullptr || observer != nullptr;
    if (hashes != nullptr)
    {
        hashes->clear();
    }

    RunResult result;
    // Replays ops [begin, end) into `sample` (timed: also the calls' own times); returns the time spent on
    // checking, which the step's time excludes.
    const auto replayOps = [&](size_t begin, size_t end, bool timed, StepSample& sample) {
        int64_t excluded = 0;
        for (size_t i = begin; i < end; ++i)
        {
            // The ops stream from memory (32 B each, 3.2 MB per step on particles 100k) while the engine's
            // own data fills the caches; without this hint the loop stalled on them: particles 100k, 1
            // thread, 3 interleaved runs each: 4.68-4.86 -> 4.21-4.29 ms per step, the null engine 0.23 ->
            // 0.20 ms. Stock's replay (40-41 ms per step) did not measurably change.
            __builtin_prefetch(ops.data() + std::min(i + 32, ops.size() - 1));
            const TraceOp& op = ops[i];
            if (op.kind != TraceOp::UpdatePairs)
            {
                ApplyOp(engine, op, map);
                sample.ops += 1;
                continue;
            }
            if (observer != nullptr)
            {
                const int64_t o0 = NowNs();
                observer->BeforeUpdatePairs(engine, timed);
                excluded += NowNs() - o0;
            }
            const int64_t f0 = NowNs();
            engine.UpdatePairs();
            const int64_t f1 = NowNs();
            sample.findNs += f1 - f0;
            if (timed)
            {
                result.callNs.push_back(int32_t(std::min<int64_t>(f1 - f0, INT32_MAX)));
            }
            sample.calls += 1;
            sample.pairs += int64_t(engine.PairCount());
            if (hashes != nullptr)
            {
                keys.clear();
                engine.PairKeys(keys);
                hashes->push_back(HashPairKeys(keys));
            }
            if (observer != nullptr)
            {
                observer->AfterUpdatePairs(engine, timed);
            }
            excluded += checking ? NowNs() - f1 : 0;
        }
        return excluded;
    };

    const int64_t setupStart = NowNs();
    const size_t firstTimed = size_t(index.boundary[size_t(index.warmup)]);
    StepSample setup;
    replayOps(0, firstTimed, false, setup);
    result.setupSeconds = double(NowNs() - setupStart) * 1e-9;
    engine.BeginTimedSteps();

    result.steps.resize(size_t(index.steps));
    size_t timedCalls = 0;
    for (size_t i = firstTimed; i < ops.size(); ++i)
    {
        timedCalls += ops[i].kind == TraceOp::UpdatePairs ? 1 : 0;
    }
    result.callNs.reserve(timedCalls); // no allocation inside the timed loop
    if (!checking)
    {
        CALLGRIND_START_INSTRUMENTATION; // a no-op outside valgrind
    }
    for (int s = 0; s < index.steps; ++s)
    {
        StepSample& sample = result.steps[size_t(s)];
        sample.proxies = engine.ProxyCount();
        const int64_t t0 = NowNs();
        const int64_t excluded =
            replayOps(size_t(index.boundary[size_t(index.warmup + s)]),
                      size_t(index.boundary[size_t(index.warmup + s + 1)]), true, sample);
        sample.ns = NowNs() - t0 - excluded;
    }
    if (!checking)
    {
        CALLGRIND_STOP_INSTRUMENTATION;
    }
    return result;
}

/// Adds the per-step arrays and totals of a run to a JSON line.
inline void AddRun(JsonLine& j, const RunResult& r)
{
    const double steps = double(std::max<size_t>(1, r.steps.size()));
    const int64_t totalNs = r.Total(&StepSample::ns);
    const double proxySum = double(r.Total(&StepSample::proxies));
    j.Int("steps", int64_t(r.steps.size()))
        .Num("mean_proxies", proxySum / steps)
        .Num("step_ns", double(totalNs) / steps)
        .Num("find_ns", double(r.Total(&StepSample::findNs)) / steps)
        .Num("calls_per_step", double(r.Total(&StepSample::calls)) / steps)
        .Num("pairs_per_step", double(r.Total(&StepSample::pairs)) / steps)
        .Num("ns_per_proxy_step", proxySum > 0.0 ? double(totalNs) / proxySum : 0.0)
        .Num("setup_s", r.setupSeconds)
        .Array("steps_ns", r.Column(&StepSample::ns))
        .Array("steps_find_ns", r.Column(&StepSample::findNs))
        .Array("steps_calls", r.Column(&StepSample::calls))
        .Array("steps_pairs", r.Column(&StepSample::pairs))
        .Array("steps_ops", r.Column(&StepSample::ops));
}

/// The times per step of one engine configuration's timed runs (TimedRun), for the medians printed at the end.
struct Timings
{
    std::string name;
    std::vector<double> ms, findMs; // per run: the whole broadphase work and its UpdatePairs calls

    void PrintMedians() const
    {
        if (!ms.empty())
        {
            std::printf("%s: median %.3f ms/step, FindPairs %.3f ms/step\n", name.c_str(), Median(ms),
                        Median(findMs));
        }
    }
};

/// One timed run, of any engine: a fresh engine from make() replays the trace. Appends its JSON line (`j`, the
/// run's number, the heap bytes the engine holds after the whole trace as HeapBytes measures them, the per-step
/// arrays, then what more(j, engine, result) adds), prints a line and adds the run's times to `t`.
template <typename Make, typename More>
void TimedRun(const LoadedTrace& loaded, const std::string& jsonPath, JsonLine j, Timings& t, Make make,
              More more)
{
    const int64_t heap0 = HeapBytes();
    auto engine = make();
    const RunResult result = Replay(loaded, *engine);
    const int64_t heap = HeapBytes() - heap0;
    const double perProxy = double(heap) / std::max(1, engine->ProxyCount());
    j.Int("rep", int64_t(t.ms.size()))
        .Int("heap_bytes", heap)
        .Int("proxies_end", engine->ProxyCount())
        .Num("bytes_per_proxy", perProxy);
    AddRun(j, result);
    more(j, *engine, result);
    AppendLine(jsonPath, j.Text());
    const double total = double(result.Total(&StepSample::ns));
    t.ms.push_back(total / loaded.steps.steps * 1e-6);
    t.findMs.push_back(double(result.Total(&StepSample::findNs)) / loaded.steps.steps * 1e-6);
    std::printf("%s rep %zu: %.3f ms/step, %.1f ns/proxy/step, %.0f bytes/proxy\n", t.name.c_str(),
                t.ms.size() - 1, t.ms.back(),
                total / std::max(1.0, double(result.Total(&StepSample::proxies))), perProxy);
}

} // namespace qpbench
