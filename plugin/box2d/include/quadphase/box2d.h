// SPDX-License-Identifier: MIT
// quadphase's API for Box2D users: settings, statistics and validation of a b2World's broadphase.
// Only available when linking quadphase::box2d (the stock build has no quadtree).
#pragma once

#include <cstdint>
#include <string>

#include "box2d/b2_world.h"
#include "quadphase/config.h"
#include "quadphase/error.h"
#include "quadphase/export.h"
#include "quadphase/stats.h"

namespace quadphase
{

/// The code of every mismatch validation reports through quadphase's error handler (quadphase/error.h); the
/// message starts with "validation mismatch: " and names the call and the proxies.
constexpr ErrorCode kValidationMismatch = ErrorCode::FirstAdapterCode;

/// What validation found so far.
struct ValidationReport
{
    int64_t checks = 0;        ///< UpdatePairs calls compared
    int64_t pairsCompared = 0; ///< distinct pairs compared, summed over checks
    int64_t mismatches = 0;    ///< checks (or fat-AABB comparisons) that disagreed
    std::string firstMismatch; ///< description of the first mismatch, empty when none
};

/// Applies settings to the world's broadphase. A changed layout setting (depth, maxDepth, autoBounds, bounds,
/// cellToProxyRatio) rebuilds its quadtree (O(proxies)); thread and task-system settings alone do not, so they
/// leave the pairs, their order and the simulation as they were. Call between steps.
QUADPHASE_API void Configure(b2World& world, const Config& config);

/// Hands pair generation to the game's own job system (quadphase/task_system.h): from the next step on it runs on the
/// game's workers and quadphase starts no thread of its own. TaskSystem{} goes back to Config::executor (the library's
/// pool by default; see Config::threads). The pairs and their order, hence the simulation, do not change. Call between
/// steps; the callbacks must outlive the world or be replaced first. Throws std::invalid_argument for a half-set
/// TaskSystem. Same as Config::taskSystem through Configure.
QUADPHASE_API void SetTaskSystem(b2World& world, const TaskSystem& tasks);

/// The world's current settings.
QUADPHASE_API Config GetConfig(const b2World& world);

/// Shape and work counters of the world's broadphase. O(cells).
QUADPHASE_API Stats GetStats(const b2World& world);

/// Zeroes the work counters (pairs, calls, times).
QUADPHASE_API void ResetCounters(b2World& world);

/// Times MoveProxy/CreateProxy/DestroyProxy into Stats::updateSeconds (costs two clock reads per call).
QUADPHASE_API void SetTiming(b2World& world, bool enabled);

/// Switches validation mode: a shadow b2DynamicTree fed the same calls with Box2D 2.4.1's own b2BroadPhase logic,
/// whose pairs are compared with the quadtree's at every UpdatePairs, and whose fat AABBs with the quadtree's bit
/// for bit. Costs about as much as a second broadphase; meant for tests and debugging.
/// QUADPHASE_VALIDATE=1 in the environment switches it on for every world from its creation (except in set-user-ID
/// and set-group-ID programs, which ignore every QUADPHASE_* variable).
QUADPHASE_API void SetValidation(b2World& world, bool enabled);

/// What validation found; all zero when it is off.
QUADPHASE_API ValidationReport GetValidationReport(const b2World& world);

// The same for a b2BroadPhase used on its own (tests, fuzzing, programs that drive the broadphase directly).
// b2BroadPhase declares only stock Box2D 2.4.1's members, so its extras are these free functions.

/// Validation mode of one broadphase (see SetValidation(b2World&, bool)).
QUADPHASE_API void SetValidation(b2BroadPhase& broadPhase, bool enabled);
QUADPHASE_API bool IsValidating(const b2BroadPhase& broadPhase);

/// What validation found; all zero when it is off.
QUADPHASE_API ValidationReport GetValidationReport(const b2BroadPhase& broadPhase);

} // namespace quadphase
