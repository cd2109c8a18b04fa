// SPDX-License-Identifier: MIT
// Compiled against Box2D 2.4.1's pristine headers with b2BroadPhase renamed (see stock_broad_phase.h).
#include "stock_broad_phase.h"

#include "box2d/b2_broad_phase.h"

namespace quadphase
{
namespace fuzz
{

namespace
{

struct PairRecorder
{
    std::vector<std::pair<void*, void*>>* out;
    void AddPair(void* userDataA, void* userDataB) { out->emplace_back(userDataA, userDataB); }
};

struct QueryAdapter
{
    StockBroadPhase::QueryFn fn;
    void* context;
    bool QueryCallback(int32 proxyId) { return fn(context, proxyId); }
};

struct RayCastAdapter
{
    StockBroadPhase::RayCastFn fn;
    void* context;
    float RayCastCallback(const b2RayCastInput& input, int32 proxyId) { return fn(context, input, proxyId); }
};

} // namespace

struct StockBroadPhase::Impl
{
    b2BroadPhase broadPhase; // qp_fuzz_stock_b2BroadPhase: Box2D's own
};

StockBroadPhase::StockBroadPhase() : m_impl(new Impl) {}

StockBroadPhase::~StockBroadPhase()
{
    delete m_impl;
}

int32 StockBroadPhase::CreateProxy(const b2AABB& aabb, void* userData)
{
    return m_impl->broadPhase.CreateProxy(aabb, userData);
}

void StockBroadPhase::DestroyProxy(int32 proxyId)
{
    m_impl->broadPhase.DestroyProxy(proxyId);
}

void StockBroadPhase::MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement)
{
    m_impl->broadPhase.MoveProxy(proxyId, aabb, displacement);
}

void StockBroadPhase::TouchProxy(int32 proxyId)
{
    m_impl->broadPhase.TouchProxy(proxyId);
}

const b2AABB& StockBroadPhase::GetFatAABB(int32 proxyId) const
{
    return m_impl->broadPhase.GetFatAABB(proxyId);
}

void* StockBroadPhase::GetUserData(int32 proxyId) const
{
    return m_impl->broadPhase.GetUserData(proxyId);
}

bool StockBroadPhase::TestOverlap(int32 proxyIdA, int32 proxyIdB) const
{
    return m_impl->broadPhase.TestOverlap(proxyIdA, proxyIdB);
}

int32 StockBroadPhase::GetProxyCount() const
{
    return m_impl->broadPhase.GetProxyCount();
}

void StockBroadPhase::UpdatePairs(std::vector<std::pair<void*, void*>>& out)
{
    PairRecorder recorder{&out};
    m_impl->broadPhase.UpdatePairs(&recorder);
}

void StockBroadPhase::Query(const b2AABB& aabb, QueryFn fn, void* context) const
{
    QueryAdapter adapter{fn, context};
    m_impl->broadPhase.Query(&adapter, aabb);
}

void StockBroadPhase::RayCast(const b2RayCastInput& input, RayCastFn fn, void* context) const
{
    RayCastAdapter adapter{fn, context};
    m_impl->broadPhase.RayCast(&adapter, input);
}

void StockBroadPhase::ShiftOrigin(const b2Vec2& newOrigin)
{
    m_impl->broadPhase.ShiftOrigin(newOrigin);
}

} // namespace fuzz
} // namespace quadphase
