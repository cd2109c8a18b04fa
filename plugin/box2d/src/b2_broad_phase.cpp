// SPDX-License-Identifier: MIT
// quadphase's b2BroadPhase: forwards Box2D's calls to the quadtree (the core) and stock's node records, and tells
// the observers (broad_phase_observer.h). Its private functions that only stock-tree mode needs are in
// stock_tree_mode.cpp.
#include "box2d/b2_broad_phase.h"

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "box2d_types.h"
#include "compiler.h"
#include "broad_phase_state.h"

using quadphase::detail::BroadPhaseObserver;
using quadphase::detail::BroadPhaseState;
using quadphase::detail::DeleteState;
using quadphase::detail::NewState;
using quadphase::detail::StateAt;
using quadphase::detail::ToBox;

// The layout promises of b2_broad_phase.h, checked where the private members can be named, against stock's members
// in stock's order and types: 80 bytes, m_moveBuffer at 40, on 64-bit targets; 56 and 28 on WebAssembly's 32-bit one.
b2BroadPhase::b2BroadPhase()
{
    struct StockLayout
    {
        b2DynamicTree tree;
        int32 proxyCount;
        int32* moveBuffer;
        int32 moveCapacity;
        int32 moveCount;
        b2Pair* pairBuffer;
        int32 pairCapacity;
        int32 pairCount;
        int32 queryProxyId;
    };
    static_assert(sizeof(b2BroadPhase) == sizeof(StockLayout) && alignof(b2BroadPhase) == alignof(StockLayout),
                  "b2BroadPhase must keep stock's size");
    static_assert(offsetof(b2BroadPhase, m_tree) == offsetof(StockLayout, tree) &&
                      offsetof(b2BroadPhase, m_proxyCount) == offsetof(StockLayout, proxyCount) &&
                      offsetof(b2BroadPhase, m_state) == offsetof(StockLayout, moveBuffer) &&
                      offsetof(b2BroadPhase, m_state) == quadphase::detail::kStateOffset &&
                      offsetof(b2BroadPhase, m_moveCount) == offsetof(StockLayout, moveCount) &&
                      offsetof(b2BroadPhase, m_pairBuffer) == offsetof(StockLayout, pairBuffer) &&
                      offsetof(b2BroadPhase, m_queryProxyId) == offsetof(StockLayout, queryProxyId),
                  "b2BroadPhase must keep stock's member offsets");
    static_assert(sizeof(b2TreeView) == sizeof(b2DynamicTree) && alignof(b2TreeView) == alignof(b2DynamicTree),
                  "b2BroadPhase::m_tree must have b2DynamicTree's layout");
    m_tree = b2TreeView{b2_nullNode, nullptr, 0, 0, b2_nullNode, 0};
    m_proxyCount = 0;
    m_queryProxyId = e_nullProxy;
    NewState({&m_tree, &m_tree.nodes, &m_tree.nodeCount, &m_tree.nodeCapacity, &m_state, &m_moveCapacity,
              &m_moveCount, &m_pairBuffer, &m_pairCapacity, &m_pairCount});
}

b2BroadPhase::~b2BroadPhase()
{
    DeleteState(m_state);
}

int32 b2BroadPhase::CreateProxy(const b2AABB& aabb, void* userData)
{
    BroadPhaseState& state = StateAt(m_state);
    const int32 id = state.core.CreateProxy(ToBox(aabb), userData);
    state.records.Create(state.core, id, userData);
    state.observers.Tell(&BroadPhaseObserver::OnCreate, id, aabb, userData);
    m_proxyCount = state.core.GetProxyCount();
    return state.HandedOutId(id);
}

void b2BroadPhase::DestroyProxy(int32 proxyId)
{
    BroadPhaseState& state = StateAt(m_state);
    const int32 id = state.CoreId(proxyId);
    state.observers.Tell(&BroadPhaseObserver::OnDestroy, id);
    state.core.DestroyProxy(id); // reports an unknown id
    state.records.Destroy(state.core, id);
    m_proxyCount = state.core.GetProxyCount();
}

namespace
{

// MoveProxy's out-of-line path: stock-tree mode, observers, bad input, unknown ids, a move the core cannot queue
// on its fast path.
QUADPHASE_NOINLINE QUADPHASE_COLD void MoveProxySlow(BroadPhaseState& state, int32 proxyId, const b2AABB& aabb,
                                                   const b2Vec2& displacement)
{
    const int32 id = state.CoreId(proxyId);
    state.records.Move(state.core, id, ToBox(aabb), {displacement.x, displacement.y});
    state.observers.Tell(&BroadPhaseObserver::OnMove, id, aabb, displacement);
}

} // namespace

// Box2D calls it for every fixture of every awake body, on one thread. The common case (records kept, no observer,
// a live proxy, a sane box) reads m_tree's members, m_state's header and the proxy's record: the fat-box test and
// the box's sanity as one mask, a return when the fat box is kept. When it changed, the record and a queue append
// (NodeRecords::TryMoveChanged); the cell upkeep waits for UpdatePairs. Everything else goes to MoveProxySlow.
void b2BroadPhase::MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement)
{
    using quadphase::detail::FastMovesAt;
    using quadphase::detail::NodeRecords;
    const quadphase::Vec2 d{displacement.x, displacement.y};
    // & rather than &&: both loads are independent, and one branch predicts better than two.
    if (QUADPHASE_LIKELY(FastMovesAt(m_state) & int32(uint32_t(proxyId) < uint32_t(m_tree.nodeCapacity))))
    {
        b2TreeNode& node = m_tree.nodes[proxyId];
        if (QUADPHASE_LIKELY(node.height == 0)) // a live proxy's record
        {
            quadphase::Box stored;
            std::memcpy(&stored, static_cast<const void*>(&node.aabb), sizeof stored);
            quadphase::Box fat;
            bool sane;
            // aabb is read corner by corner, as Box2D has just written it (KeptAndSaneSimd), and nowhere else here.
            if (QUADPHASE_LIKELY(quadphase::KeptAndSaneSimd(quadphase::detail::Box2DFatPolicy(), stored,
                                                             &aabb.lowerBound.x, &aabb.upperBound.x, d, fat, sane)) ||
                (sane && NodeRecords::TryMoveChanged(StateAt(m_state).core, node, proxyId, fat)))
            {
                return;
            }
        }
    }
    MoveProxySlow(StateAt(m_state), proxyId, aabb, displacement);
}

void b2BroadPhase::TouchProxy(int32 proxyId)
{
    BroadPhaseState& state = StateAt(m_state);
    const int32 id = state.CoreId(proxyId);
    state.core.TouchProxy(id);
    state.observers.Tell(&BroadPhaseObserver::OnTouch, id);
}

void b2BroadPhase::BufferMove(int32 proxyId)
{
    // Stock's, kept for its symbol: nothing calls it. Puts the proxy in the move buffer, as TouchProxy does.
    TouchProxy(proxyId);
}

void b2BroadPhase::UpdatePairsWith(b2AddPairThunk thunk, void* callback)
{
    BroadPhaseState& state = StateAt(m_state);
    state.pairs.clear();
    state.core.FindPairs(state.pairs);
    state.observers.Tell(&BroadPhaseObserver::OnUpdatePairs, state.pairs);
    const quadphase::ProxyPool& pool = state.core.GetPool();
    for (const quadphase::Pair& pair : state.pairs)
    {
        thunk(callback, pool.UserData(pair.a), pool.UserData(pair.b));
    }
}

namespace
{

// The callbacks get the ids b2BroadPhase hands out (the tree's in stock-tree mode), read at each call: a callback
// may create proxies.
struct QueryBridge
{
    bool (*thunk)(void*, int32);
    void* callback;
    const BroadPhaseState* state;

    static bool Call(void* context, quadphase::ProxyId id)
    {
        QueryBridge& self = *static_cast<QueryBridge*>(context);
        return self.thunk(self.callback, self.state->HandedOutId(id));
    }
};

struct RayCastBridge
{
    float (*thunk)(void*, const b2RayCastInput&, int32);
    void* callback;
    b2RayCastInput input;
    const BroadPhaseState* state;

    static float Call(void* context, const quadphase::RayInput& in, quadphase::ProxyId id)
    {
        RayCastBridge& self = *static_cast<RayCastBridge*>(context);
        self.input.maxFraction = in.maxFraction; // p1 and p2 never change; the core clips maxFraction
        return self.thunk(self.callback, self.input, self.state->HandedOutId(id));
    }
};

} // namespace

void b2BroadPhase::QueryWith(b2QueryThunk thunk, void* callback, const b2AABB& aabb) const
{
    const BroadPhaseState& state = StateAt(m_state);
    if (state.HandsOutCoreIds())
    {
        state.core.Query(ToBox(aabb), thunk, callback);
        return;
    }
    QueryBridge bridge{thunk, callback, &state};
    state.core.Query(ToBox(aabb), &QueryBridge::Call, &bridge);
}

void b2BroadPhase::RayCastWith(b2RayCastThunk thunk, void* callback, const b2RayCastInput& input) const
{
    const BroadPhaseState& state = StateAt(m_state);
    RayCastBridge bridge{thunk, callback, input, &state};
    const quadphase::RayInput in{{input.p1.x, input.p1.y}, {input.p2.x, input.p2.y}, input.maxFraction};
    state.core.RayCast(in, &RayCastBridge::Call, &bridge);
}

void b2BroadPhase::ShiftOrigin(const b2Vec2& newOrigin)
{
    BroadPhaseState& state = StateAt(m_state);
    state.core.ShiftOrigin({newOrigin.x, newOrigin.y}); // rewrites every record (the core's mirror)
    state.observers.Tell(&BroadPhaseObserver::OnShiftOrigin, newOrigin);
}
