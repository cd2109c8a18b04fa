// What a quadphase b2BroadPhase holds behind its opaque pointer. Private to the library: b2_broad_phase.h declares
// only stock Box2D's members (see the rules at its top).
#pragma once

#include <memory>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "quadtree_broad_phase.h"
#include "shadow_validator.h"
#include "trace.h"

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

    // QUADPHASE_STOCK_TREE=1: a real b2DynamicTree in b2BroadPhase::m_tree's storage, kept as stock's b2BroadPhase
    // keeps it (with its move and pair buffers), beside the quadtree, so that stock's inline templates compiled
    // into a program give stock's answers. The proxy ids b2BroadPhase hands out are then the tree's; the core's
    // are mapped to and from them. nullptr otherwise.
    b2DynamicTree* stockTree = nullptr;
    std::vector<int32> coreOfTree; // tree id -> core id, -1 when none
    std::vector<int32> treeOfCore; // core id -> tree id, -1 when none
};

/// b2BroadPhase's m_state (stock's m_moveBuffer) points kStateHeader bytes into a block that starts with the
/// BroadPhaseState pointer. What follows the header is an int32 array: stock's move buffer in stock-tree mode
/// (stock's inline UpdatePairs reads it), empty otherwise.
constexpr size_t kStateHeader = 16;

/// The state of `broadPhase`. quadphase's free functions (<quadphase/box2d.h>) cannot name b2BroadPhase's private
/// members, so they read the opaque pointer from the object's bytes at kStateOffset, which b2BroadPhase's
/// constructor checks against offsetof at compile time, and the state pointer in the block's header. Stock's
/// m_moveBuffer follows b2DynamicTree (an int32, a pointer, four int32) and m_proxyCount.
constexpr size_t kStateOffset = sizeof(void*) == 8 ? 40 : 28;
BroadPhaseState& StateOf(b2BroadPhase& broadPhase);
const BroadPhaseState& StateOf(const b2BroadPhase& broadPhase);

/// Validation totals of every broadphase of the process, printed to stderr at exit once validation ran:
/// "quadphase: validation: N UpdatePairs checked, M mismatches". Called when a validator is destroyed, and at
/// exit for those still alive; with QUADPHASE_VALIDATE_LOG, also appended to that file as they grow
/// (validation_log.h).
void AddValidationTotals(const ValidationReport& report);

} // namespace detail
} // namespace quadphase
