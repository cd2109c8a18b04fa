// SPDX-License-Identifier: MIT
// Validation mode of the Box2D adapter: a shadow b2DynamicTree fed the same calls as the quadtree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "box2d/b2_collision.h"
#include "box2d/b2_dynamic_tree.h"
#include "quadphase/box2d.h" // ValidationReport, kValidationMismatch: what users see of validation
#include "quadtree_broad_phase.h"

namespace quadphase
{

/// Mirrors every broadphase call into a b2DynamicTree with Box2D 2.4.1's own b2BroadPhase logic, and at each
/// UpdatePairs compares the set of pairs the quadtree reported with the set the stock logic gives: every proxy
/// overlapping a proxy in the move buffer. It also compares the fat AABB bits after every create, and after the
/// moves of each step once the quadtree has applied them (it queues moves; see QuadtreeBroadPhase::QueueMove),
/// which checks every fat-AABB decision, and runs the quadtree's own Validate() every 64th check.
/// Costs about as much as a second broadphase; meant for tests and debugging.
class ShadowValidator
{
public:
    /// Starts validating `core`. Applies its queued moves, then copies the proxies that already exist into the
    /// shadow tree with the exact fat AABBs the quadtree stores. A fat AABB that b2DynamicTree::CreateProxy cannot
    /// reproduce bit for bit (after a move's displacement or ShiftOrigin) is seeded one float off, and its proxy is
    /// left out of the comparisons until a move gives both trees the same bits.
    explicit ShadowValidator(const QuadtreeBroadPhase& core);

    void OnCreate(ProxyId id, const b2AABB& aabb);
    void OnDestroy(ProxyId id);
    void OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement);
    void OnTouch(ProxyId id);
    void OnShiftOrigin(const b2Vec2& newOrigin);

    /// Compares `reported` (the quadtree's pairs of this UpdatePairs) with the stock logic's, then clears the
    /// shadow move buffer.
    void OnUpdatePairs(const std::vector<Pair>& reported);

    const ValidationReport& Report() const { return m_report; }

    // Called back by b2DynamicTree::Query.
    bool QueryCallback(int32 shadowId);

private:
    void AddShadow(ProxyId id, const b2AABB& aabb);
    void SetInexact(ProxyId id, bool inexact);
    bool IsInexact(ProxyId id) const;
    void Mismatch(const std::string& what);
    void CompareFat(ProxyId id, const char* call);
    std::string Describe(ProxyId id) const;

    const QuadtreeBroadPhase& m_core;
    b2DynamicTree m_tree;
    std::vector<int32> m_shadowOf; // quadtree id -> shadow id, -1 when none
    std::vector<ProxyId> m_buffer; // quadtree ids, stock b2BroadPhase move-buffer semantics
    // quadtree ids moved since the last check: their fat AABBs are compared then
    std::vector<ProxyId> m_moved;
    // By quadtree id: seeded (validation switched on mid-run) with a fat AABB b2DynamicTree cannot reproduce bit
    // for bit; left out of the comparisons until a move gives both trees the same bits (m_exactAgain).
    std::vector<uint8_t> m_inexact;
    std::vector<ProxyId> m_exactAgain;
    std::vector<Pair> m_expected;
    std::vector<Pair> m_actual;
    ProxyId m_queryId = -1;
    ValidationReport m_report;
};

} // namespace quadphase
