// SPDX-License-Identifier: MIT
// Where a b2BroadPhase keeps the members that stock Box2D's inline functions read.
#pragma once

#include "box2d/b2_broad_phase.h"

namespace quadphase
{
namespace detail
{

/// The addresses of b2BroadPhase's members that stock's inline functions, compiled into a program, read
/// (b2_broad_phase.h: m_tree and what follows m_state). They are private, and b2_broad_phase.h may declare no name
/// of ours, so only b2BroadPhase's own functions can name them: its constructor hands their addresses to the parts
/// of the state that keep them as stock's code expects (NodeRecords, StockTreeMode). Valid while it lives.
struct StockMembers
{
    void* tree;          ///< m_tree's storage, which has b2DynamicTree's layout
    b2TreeNode** nodes;  ///< m_tree.nodes
    int32* nodeCount;    ///< m_tree.nodeCount
    int32* nodeCapacity; ///< m_tree.nodeCapacity
    void** state;        ///< m_state (stock's m_moveBuffer)
    int32* moveCapacity; ///< m_moveCapacity
    int32* moveCount;    ///< m_moveCount
    b2Pair** pairBuffer; ///< m_pairBuffer
    int32* pairCapacity; ///< m_pairCapacity
    int32* pairCount;    ///< m_pairCount
};

} // namespace detail
} // namespace quadphase
