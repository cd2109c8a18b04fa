// SPDX-License-Identifier: MIT
// Stock-tree mode: see stock_tree_mode.h. Also b2BroadPhase's private functions that stock's header declares,
// which do stock's work on the move and pair buffers.
#include "stock_tree_mode.h"

#include <cstring>
#include <new>

#include "broad_phase_state.h"

namespace quadphase
{
namespace detail
{
namespace
{

void Map(std::vector<int32>& map, int32 from, int32 to)
{
    if (size_t(from) >= map.size())
    {
        map.resize(size_t(from) + 1, -1);
    }
    map[size_t(from)] = to;
}

// Stock's UnBufferMove: nulls the proxy out of the move buffer.
void NullOut(int32* moves, int32 count, int32 treeId)
{
    for (int32 i = 0; i < count; ++i)
    {
        if (moves[i] == treeId)
        {
            moves[i] = b2BroadPhase::e_nullProxy;
        }
    }
}

} // namespace

StockTreeMode::StockTreeMode(const StockMembers& members)
    : m_members(members), m_tree(new (members.tree) b2DynamicTree) // stock's constructor on the same layout
{
    *m_members.moveCapacity = 16;
    *m_members.pairCapacity = 16;
    *m_members.pairBuffer = static_cast<b2Pair*>(b2Alloc(16 * int32(sizeof(b2Pair))));
}

StockTreeMode::~StockTreeMode()
{
    m_tree->~b2DynamicTree();
    b2Free(*m_members.pairBuffer);
}

void StockTreeMode::OnCreate(ProxyId id, const b2AABB& aabb, void* userData)
{
    const int32 treeId = m_tree->CreateProxy(aabb, userData);
    Map(m_coreOfTree, treeId, id);
    Map(m_treeOfCore, id, treeId);
    BufferMove(treeId);
}

void StockTreeMode::OnDestroy(ProxyId id)
{
    if (id < 0)
    {
        return; // an unknown tree id
    }
    const int32 treeId = TreeId(id);
    NullOut(static_cast<int32*>(*m_members.state), *m_members.moveCount, treeId);
    m_tree->DestroyProxy(treeId);
    m_coreOfTree[size_t(treeId)] = -1;
    m_treeOfCore[size_t(id)] = -1;
}

void StockTreeMode::OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement)
{
    if (id >= 0 && m_tree->MoveProxy(TreeId(id), aabb, displacement))
    {
        BufferMove(TreeId(id));
    }
}

void StockTreeMode::OnTouch(ProxyId id)
{
    if (id >= 0)
    {
        BufferMove(TreeId(id));
    }
}

void StockTreeMode::OnUpdatePairs(const std::vector<Pair>&)
{
    // As stock's UpdatePairs ends: the move buffer is consumed.
    const int32* moves = static_cast<const int32*>(*m_members.state);
    for (int32 i = 0; i < *m_members.moveCount; ++i)
    {
        if (moves[i] != b2BroadPhase::e_nullProxy)
        {
            m_tree->ClearMoved(moves[i]);
        }
    }
    *m_members.moveCount = 0;
}

void StockTreeMode::OnShiftOrigin(const b2Vec2& newOrigin)
{
    m_tree->ShiftOrigin(newOrigin);
}

void StockTreeMode::BufferMove(int32 treeId)
{
    int32& count = *m_members.moveCount;
    int32& capacity = *m_members.moveCapacity;
    if (count == capacity)
    {
        capacity *= 2;
        *m_members.state = GrowStateBlock(*m_members.state, count, capacity);
    }
    static_cast<int32*>(*m_members.state)[count] = treeId;
    ++count;
}

} // namespace detail
} // namespace quadphase

void b2BroadPhase::UnBufferMove(int32 proxyId)
{
    // Stock's, kept for its symbol: nothing calls it (StockTreeMode nulls the ids it destroys). Outside stock-tree
    // mode, m_moveCount is 0.
    quadphase::detail::NullOut(static_cast<int32*>(m_state), m_moveCount, proxyId);
}

bool b2BroadPhase::QueryCallback(int32 proxyId)
{
    // Stock's, for stock's inline UpdatePairs compiled into a program: collects a pair for the proxy being
    // queried. Reached only in stock-tree mode: otherwise m_tree's root is b2_nullNode and m_moveCount is 0.
    if (proxyId == m_queryProxyId)
    {
        return true;
    }
    const bool moved = quadphase::detail::StateAt(m_state).stockTree->Tree().WasMoved(proxyId);
    if (moved && proxyId > m_queryProxyId)
    {
        return true; // both proxies are moving: avoids duplicate pairs
    }
    if (m_pairCount == m_pairCapacity)
    {
        b2Pair* oldBuffer = m_pairBuffer;
        m_pairCapacity = m_pairCapacity + (m_pairCapacity >> 1);
        m_pairBuffer = static_cast<b2Pair*>(b2Alloc(m_pairCapacity * int32(sizeof(b2Pair))));
        std::memcpy(m_pairBuffer, oldBuffer, size_t(m_pairCount) * sizeof(b2Pair));
        b2Free(oldBuffer);
    }
    m_pairBuffer[m_pairCount].proxyIdA = b2Min(proxyId, m_queryProxyId);
    m_pairBuffer[m_pairCount].proxyIdB = b2Max(proxyId, m_queryProxyId);
    ++m_pairCount;
    return true;
}
