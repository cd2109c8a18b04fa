// SPDX-License-Identifier: MIT
// Prints the binary layout of the Box2D classes a game's compiled code reads inline: sizeof and alignof of
// b2BroadPhase, b2ContactManager and b2World, and the offset of each of their data members. Built twice from this
// file, against stock Box2D 2.4.1's headers and against quadphase's (tests/abi/CMakeLists.txt); CompareLayouts.cmake
// requires the two outputs to be identical. quadphase's b2BroadPhase names some members differently (its m_tree is
// a view with stock's member order; m_state sits where stock keeps m_moveBuffer), so the lines use stock's names.
#include <cstddef>
#include <cstdio>

// Private members are part of the layout that inline functions compiled into a game read, so the dump needs them.
// Standard headers first: only Box2D's declarations are affected.
#include <cassert>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#define private public
#define protected public
#include <box2d/box2d.h>
#undef private
#undef protected

#define QP_OFFSET(type, member, name)                                                                        \
    std::printf("offsetof(%s, %s) %zu\n", #type, name, offsetof(type, member))
#define QP_SIZE(type)                                                                                        \
    std::printf("sizeof(%s) %zu\nalignof(%s) %zu\n", #type, sizeof(type), #type, alignof(type))

// The members whose names differ: quadphase's tree view drops stock's m_ prefixes.
#if defined(QUADPHASE_LAYOUT)
#define QP_TREE(field) m_tree.field
#define QP_TREE_TYPE b2BroadPhase::b2TreeView
#define QP_MOVE_BUFFER m_state
#else
#define QP_TREE(field) m_tree.m_##field
#define QP_TREE_TYPE b2DynamicTree
#define QP_MOVE_BUFFER m_moveBuffer
#endif

int main()
{
    QP_SIZE(b2BroadPhase);
    QP_SIZE(b2ContactManager);
    QP_SIZE(b2World);
    QP_SIZE(b2TreeNode);
    QP_SIZE(b2Pair);

    QP_OFFSET(b2BroadPhase, QP_TREE(root), "m_tree.m_root");
    QP_OFFSET(b2BroadPhase, QP_TREE(nodes), "m_tree.m_nodes");
    QP_OFFSET(b2BroadPhase, QP_TREE(nodeCount), "m_tree.m_nodeCount");
    QP_OFFSET(b2BroadPhase, QP_TREE(nodeCapacity), "m_tree.m_nodeCapacity");
    QP_OFFSET(b2BroadPhase, QP_TREE(freeList), "m_tree.m_freeList");
    QP_OFFSET(b2BroadPhase, QP_TREE(insertionCount), "m_tree.m_insertionCount");
    QP_OFFSET(b2BroadPhase, QP_MOVE_BUFFER, "m_moveBuffer");
    std::printf("sizeof(b2BroadPhase::m_tree) %zu\n", sizeof(QP_TREE_TYPE));
    QP_OFFSET(b2BroadPhase, m_proxyCount, "m_proxyCount");
    QP_OFFSET(b2BroadPhase, m_moveCapacity, "m_moveCapacity");
    QP_OFFSET(b2BroadPhase, m_moveCount, "m_moveCount");
    QP_OFFSET(b2BroadPhase, m_pairBuffer, "m_pairBuffer");
    QP_OFFSET(b2BroadPhase, m_pairCapacity, "m_pairCapacity");
    QP_OFFSET(b2BroadPhase, m_pairCount, "m_pairCount");
    QP_OFFSET(b2BroadPhase, m_queryProxyId, "m_queryProxyId");

    QP_OFFSET(b2TreeNode, aabb, "aabb");
    QP_OFFSET(b2TreeNode, userData, "userData");
    QP_OFFSET(b2TreeNode, child1, "child1");
    QP_OFFSET(b2TreeNode, height, "height");
    QP_OFFSET(b2TreeNode, moved, "moved");

    QP_OFFSET(b2ContactManager, m_broadPhase, "m_broadPhase");
    QP_OFFSET(b2ContactManager, m_contactList, "m_contactList");
    QP_OFFSET(b2ContactManager, m_contactCount, "m_contactCount");
    QP_OFFSET(b2ContactManager, m_contactFilter, "m_contactFilter");
    QP_OFFSET(b2ContactManager, m_contactListener, "m_contactListener");
    QP_OFFSET(b2ContactManager, m_allocator, "m_allocator");

    QP_OFFSET(b2World, m_blockAllocator, "m_blockAllocator");
    QP_OFFSET(b2World, m_stackAllocator, "m_stackAllocator");
    QP_OFFSET(b2World, m_contactManager, "m_contactManager");
    QP_OFFSET(b2World, m_bodyList, "m_bodyList");
    QP_OFFSET(b2World, m_jointList, "m_jointList");
    QP_OFFSET(b2World, m_bodyCount, "m_bodyCount");
    QP_OFFSET(b2World, m_jointCount, "m_jointCount");
    QP_OFFSET(b2World, m_gravity, "m_gravity");
    QP_OFFSET(b2World, m_allowSleep, "m_allowSleep");
    QP_OFFSET(b2World, m_destructionListener, "m_destructionListener");
    QP_OFFSET(b2World, m_debugDraw, "m_debugDraw");
    QP_OFFSET(b2World, m_inv_dt0, "m_inv_dt0");
    QP_OFFSET(b2World, m_newContacts, "m_newContacts");
    QP_OFFSET(b2World, m_locked, "m_locked");
    QP_OFFSET(b2World, m_clearForces, "m_clearForces");
    QP_OFFSET(b2World, m_warmStarting, "m_warmStarting");
    QP_OFFSET(b2World, m_continuousPhysics, "m_continuousPhysics");
    QP_OFFSET(b2World, m_subStepping, "m_subStepping");
    QP_OFFSET(b2World, m_stepComplete, "m_stepComplete");
    QP_OFFSET(b2World, m_profile, "m_profile");
    return 0;
}
