// quadphase's API for Box2D users: settings, statistics and validation of a b2World's broadphase.
// Only available when linking quadphase::box2d (the stock build has no quadtree).
#pragma once

#include "box2d/b2_world.h"
#include "quadphase/config.h"
#include "quadphase/shadow_validator.h"
#include "quadphase/stats.h"
#include "quadphase/trace.h"

namespace quadphase
{

/// Applies settings to the world's broadphase. A changed layout setting (depth, maxDepth, autoBounds, bounds,
/// cellToProxyRatio) rebuilds its quadtree (O(proxies)); thread and task-system settings alone do not, so they
/// leave the pairs, their order and the simulation as they were. Call between steps.
void Configure(b2World& world, const Config& config);

/// Hands pair generation to the game's own job system (quadphase/task_system.h): from the next step on it runs
/// on the game's workers and quadphase starts no OpenMP thread. TaskSystem{} goes back to OpenMP (to serial in a
/// build without it, see Config::threads). The pairs and their order, hence the simulation, do not change. Call
/// between steps; the callbacks must outlive the world or be replaced first. Throws std::invalid_argument for a half-set TaskSystem. Same as Config::taskSystem
/// through Configure.
void SetTaskSystem(b2World& world, const TaskSystem& tasks);

/// The world's current settings.
Config GetConfig(const b2World& world);

/// Shape and work counters of the world's broadphase. O(cells).
Stats GetStats(const b2World& world);

/// Zeroes the work counters (pairs, calls, times).
void ResetCounters(b2World& world);

/// Times MoveProxy/CreateProxy/DestroyProxy into Stats::updateSeconds (costs two clock reads per call).
void SetTiming(b2World& world, bool enabled);

/// Switches validation mode (a shadow b2DynamicTree checked at every UpdatePairs; see ShadowValidator).
/// QUADPHASE_VALIDATE=1 in the environment switches it on for every world from its creation.
void SetValidation(b2World& world, bool enabled);

/// What validation found; all zero when it is off.
ValidationReport GetValidationReport(const b2World& world);

/// Records every later broadphase call of the world into `trace` (nullptr stops); see quadphase/trace.h.
void SetTrace(b2World& world, Trace* trace);

/// The world's quadtree, for drawing and inspection. Valid while the world lives.
const QuadtreeBroadPhase& GetQuadtree(const b2World& world);

// The same for a b2BroadPhase used on its own (tests, fuzzing, programs that drive the broadphase directly).
// b2BroadPhase declares only stock Box2D 2.4.1's members, so its extras are these free functions.

/// The broadphase's quadtree. Valid while the broadphase lives.
QuadtreeBroadPhase& GetQuadtree(b2BroadPhase& broadPhase);
const QuadtreeBroadPhase& GetQuadtree(const b2BroadPhase& broadPhase);

/// Validation mode of one broadphase (see SetValidation(b2World&, bool)).
void SetValidation(b2BroadPhase& broadPhase, bool enabled);
bool IsValidating(const b2BroadPhase& broadPhase);

/// What validation found; all zero when it is off.
ValidationReport GetValidationReport(const b2BroadPhase& broadPhase);

/// Records every later call of the broadphase into `trace` (nullptr stops).
void SetTrace(b2BroadPhase& broadPhase, Trace* trace);

} // namespace quadphase
