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
//   proxy id, the fat AABB and the user data (GetFatAABB, GetUserData and TestOverlap read them exactly);
//   m_proxyCount is the proxy count; the tree's root is b2_nullNode, so a height of 0, and stock's inline Query,
//   RayCast and UpdatePairs, if a program compiled its own copies, find nothing instead of reading freed memory.
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
    /// quadphase: the reference is into the node array, as with the stock tree: valid until the next call that
    /// creates a proxy (the array may grow) or moves or destroys this one.
    const b2AABB& GetFatAABB(int32 proxyId) const;

    /// Get user data from a proxy. Returns nullptr if the id is invalid.
    void* GetUserData(int32 proxyId) const;

    /// Test overlap of fat AABBs.
    bool TestOverlap(int32 proxyIdA, int32 proxyIdB) const;

    /// Get the number of proxies.
    int32 GetProxyCount() const;

    /// Update the pairs. This results in pair callbacks. This can only add pairs.
    /// quadphase: costs in proportion to the proxies created, moved or touched since the previous call and their
    /// neighbourhoods, not to the number of proxies: Box2D calls it after every time-of-impact event too.
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

    /// quadphase: the depth of the static quadtree (its levels are 0..depth). O(1).
    int32 GetTreeHeight() const;

    /// quadphase: the number of proxies in the most crowded cell, the grid's counterpart of imbalance. O(cells).
    int32 GetTreeBalance() const;

    /// quadphase: the mean number of proxies per occupied cell (1 is ideal; large values mean crowded cells and
    /// more candidate tests per query). O(cells).
    float GetTreeQuality() const;

    /// Shift the world origin. Useful for large worlds.
    /// The shift formula is: position -= newOrigin
    /// @param newOrigin the new origin with respect to the old origin
    /// quadphase: O(proxies); the quadtree's bounds move with the world.
    void ShiftOrigin(const b2Vec2& newOrigin);

private:
    friend class b2DynamicTree;

    // Stock's private functions, kept so that this library exports every symbol stock's does: a program compiled
    // against stock headers that instantiates stock's inline UpdatePairs references QueryCallback. Nothing here
    // calls them (see b2_broad_phase.cpp).
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

    // In stock's int32* m_moveBuffer: the quadtree and the adapter's state (the library's
    // quadphase::detail::BroadPhaseState), opaque here.
    void* m_state;
    int32 m_moveCapacity; // 0
    int32 m_moveCount;    // 0: stock's inline UpdatePairs, compiled into a program, finds no moved proxy

    b2Pair* m_pairBuffer; // nullptr
    int32 m_pairCapacity; // 0
    int32 m_pairCount;    // 0

    int32 m_queryProxyId; // e_nullProxy
};

inline int32 b2BroadPhase::GetProxyCount() const
{
    return m_proxyCount;
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
