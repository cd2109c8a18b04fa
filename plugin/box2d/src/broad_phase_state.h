// SPDX-License-Identifier: MIT
// What a quadphase b2BroadPhase holds behind its opaque pointer. Private to the library: b2_broad_phase.h declares
// only stock Box2D's members (see the rules at its top).
#pragma once

#include <cstring>
#include <memory>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "broad_phase_observer.h"
#include "node_records.h"
#include "quadtree_broad_phase.h"
#include "trace.h"
#include "stock_members.h"
#include "stock_tree_mode.h"

namespace quadphase
{
namespace detail
{

/// The quadtree, stock's node records and what watches the calls. b2_broad_phase.cpp forwards each call to the
/// core and the records, then tells `observers`.
struct BroadPhaseState
{
    /// With a stock tree (stock-tree mode) in m_tree's storage, or node records in it.
    BroadPhaseState(const StockMembers& members, bool withStockTree);

    QuadtreeBroadPhase core;
    NodeRecords records;
    std::vector<Pair> pairs; // UpdatePairs' buffer, kept between calls
    // Told of every call, in this order: stockTree, trace, validation (those that are set).
    ObserverList observers;
    std::unique_ptr<StockTreeMode> stockTree;       // QUADPHASE_STOCK_TREE=1; nullptr otherwise
    std::unique_ptr<BroadPhaseObserver> trace;      // quadphase::SetTrace (trace_observer.h)
    std::unique_ptr<BroadPhaseObserver> validation; // validation mode (validation_observer.h)

    /// Whether MoveProxy may take its inline path, which reads m_tree's node array as the records and tells no
    /// observer: node records kept (not stock-tree mode) and no observer. Kept in m_state's block header
    /// (FastMovesAt), rewritten whenever the observers change.
    bool FastMoves() const { return records.Kept() && observers.Empty(); }

    /// Whether the ids b2BroadPhase hands out are the core's: always, except in stock-tree mode.
    bool HandsOutCoreIds() const { return stockTree == nullptr; }

    /// The core's id of an id b2BroadPhase handed out.
    int32 CoreId(int32 id) const { return stockTree == nullptr ? id : stockTree->CoreId(id); }

    /// The id b2BroadPhase hands out for a live proxy's core id.
    int32 HandedOutId(ProxyId id) const { return stockTree == nullptr ? id : stockTree->TreeId(id); }

    void SetTrace(Trace* recording);
    void SetValidation(bool enabled);

private:
    void ListObservers();

    void* const* m_block; // b2BroadPhase::m_state: its header's fast-moves flag follows FastMoves()
};

/// b2BroadPhase's m_state (stock's m_moveBuffer) points kStateHeader bytes into a block whose header holds the
/// BroadPhaseState pointer, then (kFastMovesOffset) the fast-moves flag. What follows the header is an int32 array:
/// stock's move buffer in stock-tree mode (stock's inline UpdatePairs reads it), empty otherwise.
constexpr size_t kStateHeader = 16;
constexpr size_t kFastMovesOffset = 8;
static_assert(sizeof(void*) <= kFastMovesOffset && kFastMovesOffset + sizeof(int32) <= kStateHeader,
              "the state pointer and the fast-moves flag must fit m_state's block header");

/// The state m_state's block holds. Inline: every b2BroadPhase call starts here.
inline BroadPhaseState& StateAt(const void* block)
{
    BroadPhaseState* state;
    std::memcpy(&state, static_cast<const unsigned char*>(block) - kStateHeader, sizeof state);
    return *state;
}

/// The fast-moves flag of m_state's block (BroadPhaseState::FastMoves), read by b2BroadPhase::MoveProxy beside
/// m_tree's members, one load from m_state instead of three through the state: 1 or 0.
inline int32 FastMovesAt(const void* block)
{
    int32 flag;
    std::memcpy(&flag, static_cast<const unsigned char*>(block) - kStateHeader + kFastMovesOffset, sizeof flag);
    return flag;
}

/// Writes the fast-moves flag of m_state's block (`block`, as b2BroadPhase holds it): 1 when `fast`, else 0.
inline void SetFastMovesAt(void* block, bool fast)
{
    const int32 flag = fast ? 1 : 0;
    std::memcpy(static_cast<unsigned char*>(block) - kStateHeader + kFastMovesOffset, &flag, sizeof flag);
}

/// b2BroadPhase's constructor, after it has set m_tree and the counts: the state and m_state's block. Stock's move
/// and pair buffers (the members from m_state on) are set by the mode: stock's with a stock tree
/// (QUADPHASE_STOCK_TREE=1 in the environment), empty otherwise. QUADPHASE_VALIDATE=1 validates.
void NewState(const StockMembers& members);

/// b2BroadPhase's destructor: the state and m_state's block.
void DeleteState(void* block);

/// A block with the same state and room for `capacity` moves, holding the first `count` of `block`'s, which is
/// freed (stock's BufferMove growing its buffer).
void* GrowStateBlock(void* block, int32 count, int32 capacity);

/// The state of `broadPhase`. quadphase's free functions (<quadphase/box2d.h>) cannot name b2BroadPhase's private
/// members, so they read the opaque pointer from the object's bytes at kStateOffset, which b2BroadPhase's
/// constructor checks against offsetof at compile time, and the state pointer in the block's header. Stock's
/// m_moveBuffer follows b2DynamicTree (an int32, a pointer, four int32) and m_proxyCount.
constexpr size_t kStateOffset = sizeof(void*) == 8 ? 40 : 28;
BroadPhaseState& StateOf(b2BroadPhase& broadPhase);
const BroadPhaseState& StateOf(const b2BroadPhase& broadPhase);

} // namespace detail
} // namespace quadphase
