// The O(n^2) reference broadphase: obviously correct, used by tests and benchmarks to check the quadtree.
#pragma once

#include <vector>

#include "quadphase/broad_phase_interface.h"
#include "quadphase/fat_policy.h"
#include "quadphase/proxy_pool.h"

namespace quadphase
{

/// Query and RayCast by testing every live proxy of `pool`, in id order (BroadPhaseInterface's semantics).
void ScanQuery(const ProxyPool& pool, const Box& box, QueryFn fn, void* context);
void ScanRayCast(const ProxyPool& pool, const RayInput& input, RayCastFn fn, void* context);

/// Same semantics as QuadtreeBroadPhase (see BroadPhaseInterface) with the simplest possible search: every query
/// tests every live proxy. It shares ProxyPool, so for the same calls it hands out the same ids.
class BruteForceBroadPhase final : public BroadPhaseInterface
{
public:
    explicit BruteForceBroadPhase(const FatPolicy& policy = FatPolicy{});

    ProxyId CreateProxy(const Box& tight, void* userData) override;
    void DestroyProxy(ProxyId id) override;
    bool MoveProxy(ProxyId id, const Box& tight, Vec2 displacement) override;
    void TouchProxy(ProxyId id) override;
    void FindPairs(std::vector<Pair>& out) override;
    void Query(const Box& box, QueryFn fn, void* context) const override;
    void RayCast(const RayInput& input, RayCastFn fn, void* context) const override;
    void ShiftOrigin(Vec2 newOrigin) override;
    const Box& GetFatBox(ProxyId id) const override;
    void* GetUserData(ProxyId id) const override;
    int32_t GetProxyCount() const override { return m_pool.LiveCount(); }

private:
    FatPolicy m_policy;
    ProxyPool m_pool;
    std::vector<ProxyId> m_work;
};

} // namespace quadphase
