// SPDX-License-Identifier: MIT
// b2BroadPhase over the paper's static quadtree (bench/baselines' PaperQuadtreeBroadPhase): the public API of
// Box2D 2.4.1's b2_broad_phase.h, for the third Box2D build that bench/accuracy measures. APPROXIMATE by
// design: each UpdatePairs reports the pairs the paper's algorithm finds among ALL proxies
// (PaperPairReport::All, its output: it has no move buffer), so it misses some overlapping pairs (leaf
// corners, boxes larger than a leaf) and repeats some (b2ContactManager::AddPair drops repeats and pairs that
// already have a contact). Levels, bounds and threads come from quadphase_paper/paper_settings.h at
// construction.
#ifndef B2_BROAD_PHASE_H
#define B2_BROAD_PHASE_H

#include <vector>

#include "b2_api.h"
#include "b2_collision.h"
#include "b2_dynamic_tree.h" // not used; kept because Box2D's header includes it
#include "b2_settings.h"

#include "paper_quadtree.h"

struct B2_API b2Pair
{
    int32 proxyIdA;
    int32 proxyIdB;
};

namespace quadphase::bench::detail
{
static_assert(sizeof(b2AABB) == sizeof(Box), "b2AABB and quadphase::Box must have the same layout");

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
} // namespace quadphase::bench::detail

class B2_API b2BroadPhase
{
public:
    enum
    {
        e_nullProxy = -1
    };

    /// Reads quadphase::bench::g_paperSettings.
    b2BroadPhase();
    b2BroadPhase(const b2BroadPhase&) = delete;
    b2BroadPhase& operator=(const b2BroadPhase&) = delete;

    int32 CreateProxy(const b2AABB& aabb, void* userData)
    {
        return m_core.CreateProxy(quadphase::bench::detail::ToBox(aabb), userData);
    }
    void DestroyProxy(int32 proxyId) { m_core.DestroyProxy(proxyId); }
    void MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement)
    {
        m_core.MoveProxy(proxyId, quadphase::bench::detail::ToBox(aabb), {displacement.x, displacement.y});
    }
    void TouchProxy(int32 proxyId) { m_core.TouchProxy(proxyId); }
    const b2AABB& GetFatAABB(int32 proxyId) const
    {
        return reinterpret_cast<const b2AABB&>(m_core.GetFatBox(proxyId));
    }
    void* GetUserData(int32 proxyId) const { return m_core.GetUserData(proxyId); }
    bool TestOverlap(int32 proxyIdA, int32 proxyIdB) const
    {
        return quadphase::Overlaps(m_core.GetFatBox(proxyIdA), m_core.GetFatBox(proxyIdB));
    }
    int32 GetProxyCount() const { return m_core.GetProxyCount(); }

    /// The paper's frame: every live proxy inserted, every leaf searched, every found pair reported (a pair
    /// may come twice; some overlapping pairs are missed). O(proxies + leaves + tests) on every call,
    /// including the calls Box2D makes after time-of-impact events.
    template <typename T>
    void UpdatePairs(T* callback)
    {
        m_pairs.clear();
        m_core.FindPairs(m_pairs);
        for (const quadphase::Pair& pair : m_pairs)
        {
            callback->AddPair(m_core.GetUserData(pair.a), m_core.GetUserData(pair.b));
        }
    }

    /// Brute force over the proxies (the paper has no queries): exact.
    template <typename T>
    void Query(T* callback, const b2AABB& aabb) const
    {
        m_core.Query(quadphase::bench::detail::ToBox(aabb), &quadphase::bench::detail::QueryTrampoline<T>,
                     callback);
    }
    template <typename T>
    void RayCast(T* callback, const b2RayCastInput& input) const
    {
        const quadphase::RayInput in{{input.p1.x, input.p1.y}, {input.p2.x, input.p2.y}, input.maxFraction};
        m_core.RayCast(in, &quadphase::bench::detail::RayCastTrampoline<T>, callback);
    }

    /// The paper's level count.
    int32 GetTreeHeight() const { return m_core.GetLevels(); }
    /// Not meaningful for this tree: 0.
    int32 GetTreeBalance() const { return 0; }
    /// Not meaningful for this tree: 0.
    float GetTreeQuality() const { return 0.0f; }

    void ShiftOrigin(const b2Vec2& newOrigin) { m_core.ShiftOrigin({newOrigin.x, newOrigin.y}); }

private:
    quadphase::bench::PaperQuadtreeBroadPhase m_core;
    std::vector<quadphase::Pair> m_pairs;
};

#endif
