// SPDX-License-Identifier: MIT
// The O(n^2) reference broadphase: obviously correct, used by tests and benchmarks to check the quadtree.
#pragma once

#include <vector>

#include "broad_phase_interface.h"
#include "fat_policy.h"
#include "proxy_pool.h"

namespace quadphase
{

/// Same semantics as QuadtreeBroadPhase (see BroadPhaseInterface) with the simplest possible search: every query
/// tests every live proxy. It shares ProxyPool, so for the same calls it hands out the same ids.
/// A derived class (the bench's baseline of the paper's design) may search pairs its own way: FindPairs and
/// ShiftOrigin can be overridden; the proxy calls, Query and RayCast (every live proxy in id order) are final.
class BruteForceBroadPhase : public BroadPhaseInterface
{
public:
    explicit BruteForceBroadPhase(const FatPolicy& policy = FatPolicy{});

    ProxyId CreateProxy(const Box& tight, void* userData) final;
    void DestroyProxy(ProxyId id) final;
    bool MoveProxy(ProxyId id, const Box& tight, Vec2 displacement) final;
    void TouchProxy(ProxyId id) final;
    void FindPairs(std::vector<Pair>& out) override;
    void Query(const Box& box, QueryFn fn, void* context) const final;
    void RayCast(const RayInput& input, RayCastFn fn, void* context) const final;
    void ShiftOrigin(Vec2 newOrigin) override;
    const Box& GetFatBox(ProxyId id) const final;
    void* GetUserData(ProxyId id) const final;
    int32_t GetProxyCount() const final { return m_pool.LiveCount(); }

protected:
    FatPolicy m_policy;
    ProxyPool m_pool;
    std::vector<ProxyId> m_work;
};

} // namespace quadphase
