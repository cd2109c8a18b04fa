// SPDX-License-Identifier: MIT
// The replay loop of every qp-replay engine, and its timing definition (the same for every engine):
// - The ops before the first timed step (scene creation and the warm-up steps) are replayed untimed: they bring
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
#include <numeric>
#include <vector>

#include "callgrind_markers.h"
#include "loaded_trace.h"
#include "pair_hash.h"
#include "tool_common.h"
#include "trace.h"

namespace qpbench
{

using quadphase::Box;
using quadphase::TraceOp;
using quadphase::Vec2;

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

} // namespace qpbench
