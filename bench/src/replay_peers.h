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
    std::function<JsonLine(const char*)> base; // a JSON line with the common fields (kind: "run", "check", ...)
};

/// Checks (untimed) and times `run.engine` on the trace; returns the exit code (3: a pair-set mismatch). Exits
/// with 2 on an engine that is unknown or not built here, or refused settings.
int RunPeer(const PeerRun& run);

} // namespace qpbench
