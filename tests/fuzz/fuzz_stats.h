// SPDX-License-Identifier: MIT
// Work counters of a fuzz target, printed at exit when QP_FUZZ_STATS=1: libFuzzer counts executions, and
// these say how much each execution checked (operations run against the reference, full Validate() calls), so
// that a speed-up that came from shorter programs would show.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace quadphase
{
namespace fuzz
{

struct Stats
{
    int64_t inputs = 0;
    int64_t operations = 0;     // program operations executed and checked
    int64_t validations = 0;    // QuadtreeBroadPhase::Validate() calls
    int64_t reentrant = 0;      // broadphase calls made from inside Query and RayCast callbacks
    int64_t stockRayMisses = 0; // box2d: proxies stock's tree culled that its own leaf test accepts
    ~Stats()
    {
        const char* on = std::getenv("QP_FUZZ_STATS");
        if (on != nullptr && std::strcmp(on, "1") == 0)
        {
            std::fprintf(stderr,
                         "qp_fuzz_stats: inputs %" PRId64 " operations %" PRId64 " validations %" PRId64
                         " reentrant_calls %" PRId64 " stock_ray_misses %" PRId64 "\n",
                         inputs, operations, validations, reentrant, stockRayMisses);
        }
    }
};

inline Stats g_stats;

} // namespace fuzz
} // namespace quadphase
