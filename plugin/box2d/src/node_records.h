// SPDX-License-Identifier: MIT
// Stock's node records: m_tree's node array, kept exact at every moment for stock's inline readers (GetFatAABB,
// GetUserData, TestOverlap), which a program compiled against stock's headers runs on this library.
#pragma once

#include <cstdint>
#include <cstring>

#include "box2d_types.h"
#include "box_simd.h"
#include "quadtree_broad_phase.h"
#include "stock_members.h"

namespace quadphase
{
namespace detail
{

/// The record of proxy id is m_tree.nodes[id]: its fat AABB and user data, height 0 and child1 b2_nullNode (a
/// leaf) while it lives, height -1 and user data nullptr once destroyed (docs/design.md, "Binary compatibility").
/// The array grows by doubling and is handed to the core as its BoxMirror, which copies the fat boxes it changes
/// itself (ShiftOrigin) into it; the fat box of a move is written here, once.
class NodeRecords
{
public:
    /// Keeps m_tree's node array, empty at first; with `members` null (stock-tree mode: m_tree holds a real
    /// b2DynamicTree), keeps nothing, and every move goes to the core as it came.
    explicit NodeRecords(const StockMembers* members);
    ~NodeRecords();
    NodeRecords(const NodeRecords&) = delete;
    NodeRecords& operator=(const NodeRecords&) = delete;

    /// Writes the record of the proxy the core has just created, growing the array first when it is too short.
    void Create(QuadtreeBroadPhase& core, ProxyId id, void* userData);

    /// Frees the record of a proxy the core has just destroyed; nothing for an id without a record.
    void Destroy(const QuadtreeBroadPhase& core, ProxyId id);

    /// b2BroadPhase::MoveProxy. The record gets the move's outcome now, as stock's tree does inside MoveProxy, so
    /// stock's inline GetFatAABB and TestOverlap never read a box the core has not applied yet. The record holds
    /// the fat box after every earlier call, so the fat-box test runs here, once, on it (branch-free, SSE where
    /// available), and the core is handed the outcome (QueueFatMove) and applies it in its batch, neither testing
    /// again nor writing the record back. A move that keeps its fat box changes nothing, in the core either, and
    /// is not queued: most moves, so the queue and its batch see only the fat boxes that changed. A bad box that
    /// keeps it goes to the core as it came, to be reported; so does an id without a record (an unknown one, or
    /// any in stock-tree mode).
    void Move(QuadtreeBroadPhase& core, ProxyId id, const Box& tight, Vec2 displacement)
    {
        if (!HasRecord(id))
        {
            core.QueueMove(id, tight, displacement);
            return;
        }
        b2AABB& record = m_nodes[id].aabb;
        Box fat;
        std::memcpy(&fat, static_cast<const void*>(&record), sizeof fat);
        if (RefattenSimd(Box2DFatPolicy(), fat, tight, displacement))
        {
            // Queued before the record is written: an error hook that throws for a bad box leaves both as they were.
            core.QueueFatMove(id, tight, fat);
            std::memcpy(static_cast<void*>(&record), &fat, sizeof fat);
        }
        else if (!IsSaneSimd(tight))
        {
            core.QueueMove(id, tight, displacement);
        }
    }

    /// Whether the records are kept (not stock-tree mode).
    bool Kept() const { return m_kept; }

    /// Move's common case that changes something, inline in b2BroadPhase::MoveProxy after KeptAndSaneSimd found a
    /// sane box whose fat box changed: `node` is the record of `id` (m_tree.nodes[id], height 0), `fat` the moved fat
    /// box. The core's fast path queues it (the id appended), and the record is written. Returns false, having
    /// changed nothing, for a move the core cannot queue on its fast path: Move then does it all.
    static bool TryMoveChanged(QuadtreeBroadPhase& core, b2TreeNode& node, ProxyId id, const Box& fat)
    {
        if (!core.TryQueueFatMove(id, fat))
        {
            return false;
        }
        std::memcpy(static_cast<void*>(&node.aabb), &fat, sizeof fat);
        return true;
    }

private:
    // Unsigned: one compare for both bounds.
    bool HasRecord(ProxyId id) const
    {
        return uint32_t(id) < uint32_t(m_capacity) && m_nodes[id].height == 0;
    }
    void Grow(QuadtreeBroadPhase& core, int32 capacity);

    StockMembers m_members{};
    bool m_kept = false;
    b2TreeNode* m_nodes = nullptr; // m_tree.nodes, read here on the hot path (MoveProxy)
    int32 m_capacity = 0;          // m_tree.nodeCapacity
};

} // namespace detail
} // namespace quadphase
