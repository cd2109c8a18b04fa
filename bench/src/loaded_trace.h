// SPDX-License-Identifier: MIT
// A trace and its step index, loaded and checked to be a valid call sequence.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "step_index.h"
#include "tool_common.h"
#include "trace.h"

namespace qpbench
{

using quadphase::Trace;
using quadphase::TraceOp;

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

} // namespace qpbench
