// SPDX-License-Identifier: MIT
// Stock-tree mode (QUADPHASE_STOCK_TREE=1): a real b2DynamicTree in b2BroadPhase::m_tree's storage, with stock's
// move and pair buffers, kept beside the quadtree so that stock's inline templates compiled into a program give
// stock's answers (docs/design.md, "Binary compatibility", rule 5).
#pragma once

#include <cstddef>
#include <vector>

#include "box2d/b2_dynamic_tree.h"
#include "broad_phase_observer.h"
#include "stock_members.h"

namespace quadphase
{
namespace detail
{

/// Does to the tree and the buffers what stock's b2BroadPhase does on each call (stock's CreateProxy, MoveProxy,
/// BufferMove, UnBufferMove, and the end of UpdatePairs; b2BroadPhase::QueryCallback is stock's, in
/// stock_tree_mode.cpp). The ids b2BroadPhase hands out are then the tree's; the core's are mapped to and from
/// them. The move buffer is the int32 array after the state block's header, which m_state points at.
class StockTreeMode final : public BroadPhaseObserver
{
public:
    /// Constructs the tree in m_tree's storage and the buffers, as stock's constructor does; m_state's block is
    /// made afterwards with room for *members.moveCapacity moves.
    explicit StockTreeMode(const StockMembers& members);
    ~StockTreeMode() override;

    /// The core's id of a tree id, -1 (which the core reports as unknown) when there is none.
    int32 CoreId(int32 treeId) const
    {
        return treeId >= 0 && size_t(treeId) < m_coreOfTree.size() ? m_coreOfTree[size_t(treeId)] : -1;
    }

    /// The tree's id of a live proxy's core id.
    int32 TreeId(ProxyId coreId) const { return m_treeOfCore[size_t(coreId)]; }

    const b2DynamicTree& Tree() const { return *m_tree; }

    void OnCreate(ProxyId id, const b2AABB& aabb, void* userData) override;
    void OnDestroy(ProxyId id) override;
    void OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement) override;
    void OnTouch(ProxyId id) override;
    void OnUpdatePairs(const std::vector<Pair>& pairs) override;
    void OnShiftOrigin(const b2Vec2& newOrigin) override;

private:
    void BufferMove(int32 treeId);

    StockMembers m_members;
    b2DynamicTree* m_tree;
    std::vector<int32> m_coreOfTree; // tree id -> core id, -1 when none
    std::vector<int32> m_treeOfCore; // core id -> tree id, -1 when none
};

} // namespace detail
} // namespace quadphase
