// SPDX-License-Identifier: MIT
// For the tools compiled twice, against stock Box2D 2.4.1 and against Box2D with the quadtree
// (quadphase_link_box2d_variant): the variant's name and the one quadphase setting they take from the command
// line.
#pragma once

#include <cstdlib>
#include <string>

#include "box2d/box2d.h"
#include "tool_common.h"

#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase/box2d.h"
constexpr const char* kVariant = "quadtree";
constexpr bool kQuadtree = true;
#elif QUADPHASE_VARIANT_STOCK
constexpr const char* kVariant = "stock";
constexpr bool kQuadtree = false;
#else
#error "define QUADPHASE_VARIANT_QUADPHASE=1 or QUADPHASE_VARIANT_STOCK=1 (quadphase_link_box2d_variant)"
#endif

namespace qpbench
{

/// --threads: "default" leaves the adapter's Config as it is (the library's defaults: threads = 0, parallel only
/// in scenes of Config::parallelMinProxies proxies and up, on OMP_NUM_THREADS threads); a number sets
/// quadphase::Config::threads. The stock build is single-threaded: only 1 or
/// "default". Exits with status 2 (after a message) for anything else.
inline void ApplyThreads(b2World& world, const std::string& value)
{
    if (value == "default")
    {
        return;
    }
    long threads = 0;
    if (!ParseLong(value, threads) || threads < 0 || (!kQuadtree && threads != 1))
    {
        Die(2, "qp-%s: --threads must be %s, got '%s'\n", kVariant,
            kQuadtree ? "a count >= 0 or default" : "1 or default (stock is single-threaded)", value.c_str());
    }
#if QUADPHASE_VARIANT_QUADPHASE
    quadphase::Config config = quadphase::GetConfig(world);
    config.threads = int(threads);
    quadphase::Configure(world, config);
#else
    (void)world;
#endif
}

/// OMP_NUM_THREADS as a number (0 when unset): what the quadtree's default Config follows; the JSON lines say
/// it.
inline int OmpNumThreadsEnv()
{
    const char* v = std::getenv("OMP_NUM_THREADS");
    return v != nullptr ? std::atoi(v) : 0;
}

} // namespace qpbench
