// quadphase's b2BroadPhase: the public API of Box2D 2.4.1's b2_broad_phase.h, implemented over a static quadtree
// (quadphase::QuadtreeBroadPhase) instead of b2DynamicTree. This header replaces Box2D's own in the include tree
// that quadphase::box2d is compiled with and exports, so every translation unit sees this class layout.
#ifndef B2_BROAD_PHASE_H
#define B2_BROAD_PHASE_H

#include <memory>
#include <mutex>
#include <vector>

#include "b2_api.h"
#include "b2_collision.h"
#include "b2_dynamic_tree.h" // not used by the quadtree; kept because Box2D's header includes it
#include "b2_settings.h"

#include "quadphase/quadtree_broad_phase.h"
#include "quadphase/trace.h"

namespace quadphase
{
class ShadowValidator;
}

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
    b2BroadPhase(const b2BroadPhase&) = delete;
    b2BroadPhase& operator=(const b2BroadPhase&) = delete;

    /// Create a proxy with an initial AABB. Pairs are not reported until
    /// UpdatePairs is called.
    int32 CreateProxy(const b2AABB& aabb, void* userData);

    /// Destroy a proxy. It is up to the client to remove any pairs.
    void DestroyProxy(int32 proxyId);

    /// Call MoveProxy as many times as you like, then when you are done
    /// call UpdatePairs to finalized the proxy pairs (for your time step).
    /// quadphase: O(1), a store: the move is queued, and its fat-AABB test runs (on all threads) in the next
    /// UpdatePairs, or earlier if something reads a fat AABB first. The outcome is the stock tree's.
    void MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement);

    /// Call to trigger a re-processing of it's pairs on the next call to UpdatePairs.
    void TouchProxy(int32 proxyId);

    /// Get the fat AABB for a proxy.
    /// quadphase: the reference is to a copy kept for this proxy id (the quadtree stores boxes in its own type,
    /// and reading them through a b2AABB would break strict aliasing). It stays readable while the broadphase
    /// lives; its value is the fat AABB as of this call, refreshed by the next GetFatAABB of the same id.
    const b2AABB& GetFatAABB(int32 proxyId) const;

    /// Get user data from a proxy. Returns nullptr if the id is invalid.
    void* GetUserData(int32 proxyId) const;

    /// Test overlap of fat AABBs.
    bool TestOverlap(int32 proxyIdA, int32 proxyIdB) const;

    /// Get the number of proxies.
    int32 GetProxyCount() const;

    /// Update the pairs. This results in pair callbacks. This can only add pairs.
    /// Costs in proportion to the proxies created, moved or touched since the previous call and their
    /// neighbourhoods, not to the number of proxies: Box2D calls it after every time-of-impact event too.
    template <typename T>
    void UpdatePairs(T* callback);

    /// Query an AABB for overlapping proxies. The callback class
    /// is called for each proxy that overlaps the supplied AABB.
    /// quadphase: the callback may create, destroy and move proxies (b2World::QueryAABB callbacks that spawn,
    /// destroy, teleport, enable or wake bodies). A proxy that exists before the call and is neither destroyed nor
    /// moved during it is reported once; one destroyed during the call is never reported after its destruction;
    /// one created or moved during it may or may not be (QuadtreeBroadPhase::Query).
    template <typename T>
    void Query(T* callback, const b2AABB& aabb) const;

    /// Ray-cast against the proxies in the tree. This relies on the callback
    /// to perform a exact ray-cast in the case were the proxy contains a shape.
    /// The callback also performs the any collision filtering.
    /// @param input the ray-cast input data. The ray extends from p1 to p1 + maxFraction * (p2 - p1).
    /// @param callback a callback class that is called for each proxy that is hit by the ray.
    /// quadphase: walks only the cells the (clipped) ray can reach; the callback may change the broadphase as in
    /// Query, with the same guarantees (QuadtreeBroadPhase::RayCast).
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

    // ---- quadphase extensions (use them through <quadphase/box2d.h>) ----

    /// The quadtree, for settings, statistics and drawing.
    quadphase::QuadtreeBroadPhase& GetQuadtree() { return m_core; }
    const quadphase::QuadtreeBroadPhase& GetQuadtree() const { return m_core; }

    /// Validation mode: a shadow b2DynamicTree receives the same calls, and each UpdatePairs checks that both
    /// give the same set of pairs and the same fat AABBs. Also switched on at construction by the environment
    /// variable QUADPHASE_VALIDATE=1. Mismatches go to quadphase's error hook (ErrorCode::ValidationMismatch).
    void SetValidation(bool enabled);
    bool IsValidating() const { return m_shadow != nullptr; }
    const quadphase::ShadowValidator* GetValidator() const { return m_shadow; }

    /// Records every later call into `trace` (nullptr stops). The trace must outlive the recording.
    void SetTrace(quadphase::Trace* trace) { m_trace = trace; }

private:
    void CheckPairs();

    quadphase::QuadtreeBroadPhase m_core;
    std::vector<quadphase::Pair> m_pairs;
    quadphase::ShadowValidator* m_shadow = nullptr;
    quadphase::Trace* m_trace = nullptr;
    // GetFatAABB's copies, in chunks that never move (a reference handed out stays valid), allocated on first use:
    // Box2D itself reads fat AABBs only to draw them.
    static constexpr int32 kFatChunk = 256;
    mutable std::vector<std::unique_ptr<b2AABB[]>> m_fatCopies;
    mutable std::mutex m_fatCopiesMutex; // GetFatAABB is const: concurrent const calls may write the copies
};

namespace quadphase
{
namespace detail
{
inline Box ToBox(const b2AABB& a)
{
    return Box{a.lowerBound.x, a.lowerBound.y, a.upperBound.x, a.upperBound.y};
}

template <typename T>
bool QueryTrampoline(void* context, ProxyId id)
{
    return static_cast<T*>(context)->QueryCallback(id);
}

template <typename T>
float RayCastTrampoline(void* context, const RayInput& in, ProxyId id)
{
    b2RayCastInput sub;
    sub.p1.Set(in.p1.x, in.p1.y);
    sub.p2.Set(in.p2.x, in.p2.y);
    sub.maxFraction = in.maxFraction;
    return static_cast<T*>(context)->RayCastCallback(sub, id);
}
} // namespace detail
} // namespace quadphase

inline void* b2BroadPhase::GetUserData(int32 proxyId) const
{
    return m_core.GetUserData(proxyId);
}

inline bool b2BroadPhase::TestOverlap(int32 proxyIdA, int32 proxyIdB) const
{
    return m_core.TestOverlap(proxyIdA, proxyIdB);
}

inline int32 b2BroadPhase::GetProxyCount() const
{
    return m_core.GetProxyCount();
}

template <typename T>
void b2BroadPhase::UpdatePairs(T* callback)
{
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::UpdatePairs, -1, {}, {}});
    }
    m_pairs.clear();
    m_core.FindPairs(m_pairs);
    if (m_shadow != nullptr)
    {
        CheckPairs();
    }
    const quadphase::ProxyPool& pool = m_core.GetPool();
    for (const quadphase::Pair& pair : m_pairs)
    {
        callback->AddPair(pool.UserData(pair.a), pool.UserData(pair.b));
    }
}

template <typename T>
inline void b2BroadPhase::Query(T* callback, const b2AABB& aabb) const
{
    m_core.Query(quadphase::detail::ToBox(aabb), &quadphase::detail::QueryTrampoline<T>, callback);
}

template <typename T>
inline void b2BroadPhase::RayCast(T* callback, const b2RayCastInput& input) const
{
    const quadphase::RayInput in{{input.p1.x, input.p1.y}, {input.p2.x, input.p2.y}, input.maxFraction};
    m_core.RayCast(in, &quadphase::detail::RayCastTrampoline<T>, callback);
}

#endif
