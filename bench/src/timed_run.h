// SPDX-License-Identifier: MIT
// One timed run of any qp-replay engine: its JSON line (heap bytes, per-step arrays), its printed line, and the
// times per step of an engine configuration's runs.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "heap_bytes.h"
#include "loaded_trace.h"
#include "replay_loop.h"
#include "tool_common.h"

namespace qpbench
{

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
