// qp-replay's engines other than the quadtree core (replay_peers.cpp lists them and their two modes).
#pragma once

#include <functional>
#include <string>

#include "replay_common.h"

namespace qpbench
{

struct PeerRun
{
    const Args& args;          // --check, --repeats, --json, --hashes-out, --compare-hashes, --levels, --threads, ...
    const LoadedTrace& loaded;
    std::string engine;        // its --engine name
    std::function<void(JsonLine&, const char*)> base; // the JSON line's common fields (kind: "run", "check", ...)
};

/// Checks (untimed) and times `run.engine` on the trace; returns the exit code (3: a pair-set mismatch, 2: an
/// engine that is unknown or not built here).
int RunPeer(const PeerRun& run);

} // namespace qpbench
