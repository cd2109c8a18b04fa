// SPDX-License-Identifier: MIT
// quadphase's b2BroadPhase: the public API and the binary layout of Box2D 2.4.1's b2_broad_phase.h, implemented
// over a static quadtree (quadphase::QuadtreeBroadPhase, held behind an opaque pointer) instead of b2DynamicTree.
// This header replaces Box2D's own in the include tree that quadphase's Box2D is built with and installed with.
//
// Rules this header keeps (checked by tests/abi):
// - It includes only Box2D's own headers, compiles as C++11 with -Wall -Wextra -Wpedantic, and declares no name
//   outside the class b2BroadPhase and the struct b2Pair that stock declares: a game that defines macros such as
//   Config, Stats or Box before including <box2d/box2d.h> still compiles.
// - sizeof, alignof and the offset of every member that stock's inline functions read are stock's (80 bytes), so
//   b2ContactManager and b2World keep stock's layout, and a program compiled against stock headers runs on this
//   library (the binary swap through LD_LIBRARY_PATH).
// - What stock's inline functions read, compiled into such a program, stays valid: m_tree's node array holds, per
//   proxy id, the fat AABB and the user data, current at every moment (GetFatAABB, GetUserData and TestOverlap
//   read them exactly); m_proxyCount is the proxy count; the tree's root is b2_nullNode, so a height of 0, and
//   stock's inline Query, RayCast and UpdatePairs, if a program compiled its own copies, find nothing instead of
//   reading freed memory.
// - What stock's header has inline is inline here too, reading the same members: a program built against this
//   header that does not call the Query, RayCast or UpdatePairs templates runs on stock's libbox2d.so.2 as well.
// quadphase's extras (Configure, GetStats, SetValidation, ...) are in <quadphase/box2d.h>.

#ifndef B2_BROAD_PHASE_H
#define B2_BROAD_PHASE_H

#include "b2_api.h"
#include "b2_collision.h"
#include "b2_dynamic_tree.h"
#include "b2_settings.h"

struct B2_API b2Pair
{
    int32 proxyIdA;
    int32 proxyIdB;
};

/// The broad-phase is used for computing pairs and performing volume queries and ray casts.
/// This broad-phase does not persist pairs. Instead, this reports potentially new pairs.
/// It is up to the client to consume the new pairs and to track subsequent overlap.
///
/// quadphase: stores fat AABBs with b2DynamicTree's policy (b2_aabbExtension, b2_aabbMultiplier, the shrink rule),
/// bit for bit, so contacts are created and destroyed exactly as with the stock tree. UpdatePairs reports every
/// pair of proxies whose fat AABBs overlap and at least one of which was created, moved or touched since the
/// previous call, each pair once (the stock tree may repeat a pair; b2ContactManager::AddPair drops repeats), in an
/// order that depends only on the calls made. Not thread-safe, like the stock class.
class B2_API b2BroadPhase
{
public:
    enum
    {
        e_nullProxy = -1
    };

    b2BroadPhase();
    ~b2BroadPhase();

    /// Create a proxy with an initial AABB. Pairs are not reported until
    /// UpdatePairs is called.
    int32 CreateProxy(const b2AABB& aabb, void* userData);

    /// Destroy a proxy. It is up to the client to remove any pairs.
    void DestroyProxy(int32 proxyId);

    /// Call MoveProxy as many times as you like, then when you are done
    /// call UpdatePairs to finalized the proxy pairs (for your time step).
    /// quadphase: O(1), a store: the move is queued, and its fat-AABB test runs (on one thread) in the next
    /// UpdatePairs, or earlier if something reads a fat AABB first. The outcome is the stock tree's.
    void MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement);

    /// Call to trigger a re-processing of it's pairs on the next call to UpdatePairs.
    void TouchProxy(int32 proxyId);

    /// Get the fat AABB for a proxy.
    /// quadphase: inline, as in stock's header, and exact at every moment (MoveProxy writes the record at once):
    /// the reference is into the node array, as with the stock tree: valid until the next call that creates a
    /// proxy (the array may grow) or moves or destroys this one. The id is checked by b2Assert only, as in stock.
    const b2AABB& GetFatAABB(int32 proxyId) const;

    /// Get user data from a proxy. Returns nullptr if the id is invalid.
    /// quadphase: nullptr too for a destroyed proxy, or an id outside the node array.
    void* GetUserData(int32 proxyId) const;

    /// Test overlap of fat AABBs.
    bool TestOverlap(int32 proxyIdA, int32 proxyIdB) const;

    /// Get the number of proxies.
    int32 GetProxyCount() const;

    /// Update the pairs. This results in pair callbacks. This can only add pairs.
    /// quadphase: costs in proportion to the proxies created, moved or touched since the previous call and their
    /// neighbourhoods, not to the number of proxies: Box2D calls it after every time-of-impact event too.
    /// quadphase: this template and Query and RayCast call functions only quadphase's library defines
    /// (UpdatePairsWith, QueryWith, RayCastWith): a program that calls them itself runs only on quadphase's
    /// libbox2d. To build one program for both libraries, compile it against stock's headers (installed in
    /// include/quadphase-box2d-stock): it then runs on either, its own copies of stock's templates finding
    /// nothing on quadphase's unless QUADPHASE_STOCK_TREE=1 keeps a stock tree (see docs/design.md, "Binary
    /// compatibility"). Everything else in this header but ShiftOrigin, and all of b2World's API, runs on either
    /// library.
    template <typename T>
    void UpdatePairs(T* callback);

    /// Query an AABB for overlapping proxies. The callback class
    /// is called for each proxy that overlaps the supplied AABB.
    /// quadphase: the callback may create, destroy and move proxies (b2World::QueryAABB callbacks that spawn,
    /// destroy, teleport, enable or wake bodies). A proxy that exists before the call and is neither destroyed nor
    /// moved during it is reported once; one destroyed during the call is never reported after its destruction;
    /// one created or moved during it may or may not be.
    template <typename T>
    void Query(T* callback, const b2AABB& aabb) const;

    /// Ray-cast against the proxies in the tree. This relies on the callback
    /// to perform a exact ray-cast in the case were the proxy contains a shape.
    /// The callback also performs the any collision filtering.
    /// @param input the ray-cast input data. The ray extends from p1 to p1 + maxFraction * (p2 - p1).
    /// @param callback a callback class that is called for each proxy that is hit by the ray.
    /// quadphase: walks only the cells the (clipped) ray can reach, so a long or diagonal ray costs the cells it
    /// crosses; the callback may change the broadphase as in Query, with the same guarantees.
    template <typename T>
    void RayCast(T* callback, const b2RayCastInput& input) const;

    /// Get the height of the embedded tree.
    /// quadphase: b2DynamicTree's statistics of m_tree, inline (stock's header calls m_tree's; written out here
    /// over the same members, so a program built against this header needs nothing stock's library lacks): 0 on
    /// quadphase's library, whose m_tree holds no tree, only the proxies' records, and stock's values with
    /// QUADPHASE_STOCK_TREE=1. The quadtree's own shape (depth, crowding) is in quadphase::GetStats.
    int32 GetTreeHeight() const;

    /// Get the balance of the embedded tree (quadphase: 0, see GetTreeHeight).
    int32 GetTreeBalance() const;

    /// Get the quality metric of the embedded tree (quadphase: 0, see GetTreeHeight).
    float GetTreeQuality() const;

    /// Shift the world origin. Useful for large worlds.
    /// The shift formula is: position -= newOrigin
    /// @param newOrigin the new origin with respect to the old origin
    /// quadphase: O(proxies); the quadtree's bounds move with the world. Out of line (inline in stock's header):
    /// a program built against this header that calls it needs quadphase's library.
    void ShiftOrigin(const b2Vec2& newOrigin);

private:
    friend class b2DynamicTree;

    // Stock's private functions, kept so that this library exports every symbol stock's does: a program compiled
    // against stock headers that instantiates stock's inline UpdatePairs references QueryCallback. Nothing here
    // calls them (see b2_broad_phase.cpp and stock_tree_mode.cpp).
    void BufferMove(int32 proxyId);
    void UnBufferMove(int32 proxyId);
    bool QueryCallback(int32 proxyId);

    // Callbacks of the templates, passed to the library as plain functions.
    typedef bool (*b2QueryThunk)(void* callback, int32 proxyId);
    typedef float (*b2RayCastThunk)(void* callback, const b2RayCastInput& input, int32 proxyId);
    typedef void (*b2AddPairThunk)(void* callback, void* userDataA, void* userDataB);

    template <typename T>
    static bool QueryThunkOf(void* callback, int32 proxyId)
    {
        return static_cast<T*>(callback)->QueryCallback(proxyId);
    }

    template <typename T>
    static float RayCastThunkOf(void* callback, const b2RayCastInput& input, int32 proxyId)
    {
        return static_cast<T*>(callback)->RayCastCallback(input, proxyId);
    }

    template <typename T>
    static void AddPairThunkOf(void* callback, void* userDataA, void* userDataB)
    {
        static_cast<T*>(callback)->AddPair(userDataA, userDataB);
    }

    void QueryWith(b2QueryThunk thunk, void* callback, const b2AABB& aabb) const;
    void RayCastWith(b2RayCastThunk thunk, void* callback, const b2RayCastInput& input) const;
    void UpdatePairsWith(b2AddPairThunk thunk, void* callback);

    // Stock's b2DynamicTree m_tree, member for member (m_root, m_nodes, m_nodeCount, m_nodeCapacity, m_freeList,
    // m_insertionCount). nodes[id] is proxy id's record: fat AABB and user data, height 0 and child1 b2_nullNode
    // while the proxy lives, height -1 and user data nullptr after it is destroyed. root is always b2_nullNode.
    struct b2TreeView
    {
        int32 root;
        b2TreeNode* nodes;
        int32 nodeCount;
        int32 nodeCapacity;
        int32 freeList;
        int32 insertionCount;
    };

    b2TreeView m_tree;

    int32 m_proxyCount;

    // In stock's int32* m_moveBuffer: points into a block of the library's that starts with the quadtree's and the
    // adapter's state (the library's quadphase::detail::BroadPhaseState), opaque here. With QUADPHASE_STOCK_TREE=1
    // (a real b2DynamicTree in m_tree), stock's move buffer follows, and the six members below are stock's.
    void* m_state;
    int32 m_moveCapacity; // 0
    int32 m_moveCount;    // 0: stock's inline UpdatePairs, compiled into a program, finds no moved proxy

    b2Pair* m_pairBuffer; // nullptr
    int32 m_pairCapacity; // 0
    int32 m_pairCount;    // 0

    int32 m_queryProxyId; // e_nullProxy
};

inline void* b2BroadPhase::GetUserData(int32 proxyId) const
{
    return 0 <= proxyId && proxyId < m_tree.nodeCapacity ? m_tree.nodes[proxyId].userData : nullptr;
}

// Defined before TestOverlap, which calls it: MinGW-w64's GCC warns when a member of an imported class (B2_API with
// B2_SHARED: dllimport) is defined inline after a use.
inline const b2AABB& b2BroadPhase::GetFatAABB(int32 proxyId) const
{
    b2Assert(0 <= proxyId && proxyId < m_tree.nodeCapacity);
    return m_tree.nodes[proxyId].aabb;
}

inline bool b2BroadPhase::TestOverlap(int32 proxyIdA, int32 proxyIdB) const
{
    return b2TestOverlap(GetFatAABB(proxyIdA), GetFatAABB(proxyIdB));
}

inline int32 b2BroadPhase::GetProxyCount() const
{
    return m_proxyCount;
}

// The tree statistics: b2DynamicTree's GetHeight, GetMaxBalance and GetAreaRatio on m_tree, written out over its
// members (the same loops and float operations), since m_tree is not declared a b2DynamicTree here.
inline int32 b2BroadPhase::GetTreeHeight() const
{
    return m_tree.root == b2_nullNode ? 0 : m_tree.nodes[m_tree.root].height;
}

inline int32 b2BroadPhase::GetTreeBalance() const
{
    int32 maxBalance = 0;
    for (int32 i = 0; i < m_tree.nodeCapacity; ++i)
    {
        const b2TreeNode* node = m_tree.nodes + i;
        if (node->height <= 1)
        {
            continue;
        }
        const int32 balance = b2Abs(m_tree.nodes[node->child2].height - m_tree.nodes[node->child1].height);
        maxBalance = b2Max(maxBalance, balance);
    }
    return maxBalance;
}

inline float b2BroadPhase::GetTreeQuality() const
{
    if (m_tree.root == b2_nullNode)
    {
        return 0.0f;
    }
    const float rootArea = m_tree.nodes[m_tree.root].aabb.GetPerimeter();
    float totalArea = 0.0f;
    for (int32 i = 0; i < m_tree.nodeCapacity; ++i)
    {
        if (m_tree.nodes[i].height >= 0)
        {
            totalArea += m_tree.nodes[i].aabb.GetPerimeter();
        }
    }
    return totalArea / rootArea;
}

template <typename T>
void b2BroadPhase::UpdatePairs(T* callback)
{
    UpdatePairsWith(&b2BroadPhase::AddPairThunkOf<T>, callback);
}

template <typename T>
inline void b2BroadPhase::Query(T* callback, const b2AABB& aabb) const
{
    QueryWith(&b2BroadPhase::QueryThunkOf<T>, callback, aabb);
}

template <typename T>
inline void b2BroadPhase::RayCast(T* callback, const b2RayCastInput& input) const
{
    RayCastWith(&b2BroadPhase::RayCastThunkOf<T>, callback, input);
}

#endif
