// What a quadphase b2BroadPhase holds behind its opaque pointer. Private to the library: b2_broad_phase.h declares
// only stock Box2D's members (see the rules at its top).
#pragma once

#include <memory>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "quadphase/quadtree_broad_phase.h"
#include "quadphase/shadow_validator.h"
#include "quadphase/trace.h"

namespace quadphase
{
namespace detail
{

struct BroadPhaseState
{
    explicit BroadPhaseState(const FatPolicy& policy) : core(policy) {}

    QuadtreeBroadPhase core;
    std::vector<Pair> pairs;                 // UpdatePairs' buffer, kept between calls
    std::unique_ptr<ShadowValidator> shadow; // validation mode when set
    Trace* trace = nullptr;                  // records every call when set
    ValidationReport totalsAdded;            // the part of shadow's report already in the process-wide totals
};

/// The state of `broadPhase`. quadphase's free functions (<quadphase/box2d.h>) cannot name b2BroadPhase's private
/// members, so they read the opaque pointer from the object's bytes at kStateOffset, which b2BroadPhase's
/// constructor checks against offsetof at compile time.
constexpr size_t kStateOffset = 40;
BroadPhaseState& StateOf(b2BroadPhase& broadPhase);
const BroadPhaseState& StateOf(const b2BroadPhase& broadPhase);

/// Validation totals of every broadphase of the process, printed to stderr at exit once validation ran:
/// "quadphase: validation: N UpdatePairs checked, M mismatches". Called when a validator is destroyed, and at
/// exit for those still alive; with QUADPHASE_VALIDATE_LOG, also appended to that file as they grow
/// (validation_log.h).
void AddValidationTotals(const ValidationReport& report);

} // namespace detail
} // namespace quadphase
