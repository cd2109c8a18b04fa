// SPDX-License-Identifier: MIT
// Stock's node records: see node_records.h.
#include "node_records.h"

#include <cstddef>

namespace quadphase
{
namespace detail
{

NodeRecords::NodeRecords(const StockMembers* members)
{
    if (members != nullptr)
    {
        m_members = *members;
        m_kept = true;
    }
}

NodeRecords::~NodeRecords()
{
    b2Free(m_nodes);
}

void NodeRecords::Create(QuadtreeBroadPhase& core, ProxyId id, void* userData)
{
    if (!m_kept)
    {
        return;
    }
    if (id >= m_capacity)
    {
        Grow(core, b2Max(b2Max(16, 2 * m_capacity), id + 1)); // by doubling: amortised O(1)
    }
    // The core fattened the new box (and does not copy a new proxy's box into the mirror).
    const Box& fat = core.GetPool().Fat(id);
    b2TreeNode& node = m_nodes[id];
    node.aabb.lowerBound.Set(fat.minX, fat.minY);
    node.aabb.upperBound.Set(fat.maxX, fat.maxY);
    node.userData = userData;
    node.height = 0;
    *m_members.nodeCount = core.GetProxyCount();
}

void NodeRecords::Destroy(const QuadtreeBroadPhase& core, ProxyId id)
{
    if (!HasRecord(id))
    {
        return;
    }
    b2TreeNode& node = m_nodes[id];
    node.userData = nullptr;
    node.height = -1;
    *m_members.nodeCount = core.GetProxyCount();
}

void NodeRecords::Grow(QuadtreeBroadPhase& core, int32 capacity)
{
    b2TreeNode* nodes = static_cast<b2TreeNode*>(b2Alloc(capacity * int32(sizeof(b2TreeNode))));
    if (m_nodes != nullptr)
    {
        std::memcpy(nodes, m_nodes, size_t(m_capacity) * sizeof(b2TreeNode));
    }
    for (int32 i = m_capacity; i < capacity; ++i)
    {
        b2TreeNode& node = nodes[i];
        node.aabb.lowerBound.SetZero();
        node.aabb.upperBound.SetZero();
        node.userData = nullptr;
        node.next = b2_nullNode;
        node.child1 = b2_nullNode;
        node.child2 = b2_nullNode;
        node.height = -1;
        node.moved = false;
    }
    b2Free(m_nodes);
    m_nodes = nodes;
    m_capacity = capacity;
    *m_members.nodes = nodes;
    *m_members.nodeCapacity = capacity;
    BoxMirror mirror;
    mirror.base = reinterpret_cast<unsigned char*>(nodes) + offsetof(b2TreeNode, aabb);
    mirror.stride = sizeof(b2TreeNode);
    mirror.capacity = capacity;
    core.SetBoxMirror(mirror);
}

} // namespace detail
} // namespace quadphase
