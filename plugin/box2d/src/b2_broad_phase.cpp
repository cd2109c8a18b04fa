// quadphase's b2BroadPhase: forwards Box2D's calls to the quadtree, keeps the stock-layout node array current and,
// in validation mode, feeds a shadow b2DynamicTree; with QUADPHASE_STOCK_TREE=1, keeps a real stock tree too.
#include "box2d/b2_broad_phase.h"

#include <atomic>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <type_traits>

#include "broad_phase_state.h"
#include "environment.h"
#include "quadphase/box2d.h"
#include "validation_log.h"

using quadphase::detail::BroadPhaseState;

namespace
{

bool RequestedByEnvironment(const char* name)
{
    return quadphase::detail::EnvironmentFlag(name);
}

quadphase::FatPolicy Box2DFatPolicy()
{
    quadphase::FatPolicy policy;
    policy.extension = b2_aabbExtension;
    policy.multiplier = b2_aabbMultiplier;
    return policy;
}

quadphase::Box ToBox(const b2AABB& a)
{
    return quadphase::Box{a.lowerBound.x, a.lowerBound.y, a.upperBound.x, a.upperBound.y};
}

// The core's query callback type is the adapter's: the thunks pass straight through.
static_assert(std::is_same<int32, quadphase::ProxyId>::value, "Box2D's int32 must be quadphase's ProxyId");
static_assert(sizeof(b2AABB) == sizeof(quadphase::Box) &&
                  offsetof(b2AABB, upperBound) == offsetof(quadphase::Box, maxX),
              "b2AABB and quadphase::Box must both be minX, minY, maxX, maxY");

// Process-wide validation totals (see AddValidationTotals).
std::atomic<int64_t> g_validatedChecks{0};
std::atomic<int64_t> g_validationMismatches{0};
std::once_flag g_summaryAtExit;

void PrintValidationSummary()
{
    std::fprintf(stderr, "quadphase: validation: %lld UpdatePairs checked, %lld mismatches\n",
                 static_cast<long long>(g_validatedChecks.load()),
                 static_cast<long long>(g_validationMismatches.load()));
    quadphase::detail::LogValidationTotals(g_validatedChecks.load(), g_validationMismatches.load(), true);
}

// m_state's block (broad_phase_state.h): the state pointer, then the int32 array m_state points at.
BroadPhaseState& State(const void* moves)
{
    BroadPhaseState* state;
    std::memcpy(&state, static_cast<const unsigned char*>(moves) - quadphase::detail::kStateHeader,
                sizeof state);
    return *state;
}

void* NewStateBlock(BroadPhaseState* state, int32 capacity)
{
    unsigned char* block = static_cast<unsigned char*>(
        b2Alloc(int32(quadphase::detail::kStateHeader) + capacity * int32(sizeof(int32))));
    std::memcpy(block, &state, sizeof state);
    return block + quadphase::detail::kStateHeader;
}

void FreeStateBlock(void* moves)
{
    b2Free(static_cast<unsigned char*>(moves) - quadphase::detail::kStateHeader);
}

// Stock-tree mode: the core id of a tree id, -1 (which the core reports as unknown) when there is none.
int32 CoreId(const BroadPhaseState& state, int32 treeId)
{
    return treeId >= 0 && size_t(treeId) < state.coreOfTree.size() ? state.coreOfTree[size_t(treeId)] : -1;
}

int32 TreeId(const BroadPhaseState& state, int32 coreId)
{
    return state.treeOfCore[size_t(coreId)];
}

void Map(std::vector<int32>& map, int32 from, int32 to)
{
    if (size_t(from) >= map.size())
    {
        map.resize(size_t(from) + 1, -1);
    }
    map[size_t(from)] = to;
}

// Adds what the validator found since the last call to the process-wide totals.
void SyncValidationTotals(BroadPhaseState& state)
{
    const quadphase::ValidationReport& report = state.shadow->Report();
    quadphase::ValidationReport delta;
    delta.checks = report.checks - state.totalsAdded.checks;
    delta.mismatches = report.mismatches - state.totalsAdded.mismatches;
    quadphase::detail::AddValidationTotals(delta);
    state.totalsAdded = report;
}

} // namespace

namespace quadphase
{
namespace detail
{

BroadPhaseState& StateOf(b2BroadPhase& broadPhase)
{
    void* moves;
    std::memcpy(&moves, reinterpret_cast<unsigned char*>(&broadPhase) + kStateOffset, sizeof moves);
    return State(moves);
}

const BroadPhaseState& StateOf(const b2BroadPhase& broadPhase)
{
    void* moves;
    std::memcpy(&moves, reinterpret_cast<const unsigned char*>(&broadPhase) + kStateOffset, sizeof moves);
    return State(moves);
}

void AddValidationTotals(const ValidationReport& report)
{
    const int64_t checks = g_validatedChecks += report.checks;
    const int64_t mismatches = g_validationMismatches += report.mismatches;
    if (report.checks != 0 || report.mismatches != 0)
    {
        LogValidationTotals(checks, mismatches, false);
    }
}

} // namespace detail
} // namespace quadphase

b2BroadPhase::b2BroadPhase()
{
    // The layout promises of b2_broad_phase.h, checked where the private members can be named, against stock's
    // members in stock's order and types: 80 bytes, m_moveBuffer at 40, on 64-bit targets; 56 and 28 on
    // WebAssembly's 32-bit one.
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
    static_assert(sizeof(b2BroadPhase) == sizeof(StockLayout) &&
                      alignof(b2BroadPhase) == alignof(StockLayout),
                  "b2BroadPhase must keep stock's size");
    static_assert(offsetof(b2BroadPhase, m_tree) == offsetof(StockLayout, tree) &&
                      offsetof(b2BroadPhase, m_proxyCount) == offsetof(StockLayout, proxyCount) &&
                      offsetof(b2BroadPhase, m_state) == offsetof(StockLayout, moveBuffer) &&
                      offsetof(b2BroadPhase, m_state) == quadphase::detail::kStateOffset &&
                      offsetof(b2BroadPhase, m_moveCount) == offsetof(StockLayout, moveCount) &&
                      offsetof(b2BroadPhase, m_pairBuffer) == offsetof(StockLayout, pairBuffer) &&
                      offsetof(b2BroadPhase, m_queryProxyId) == offsetof(StockLayout, queryProxyId),
                  "b2BroadPhase must keep stock's member offsets");
    static_assert(sizeof(b2TreeView) == sizeof(b2DynamicTree) &&
                      alignof(b2TreeView) == alignof(b2DynamicTree),
                  "b2BroadPhase::m_tree must have b2DynamicTree's layout");
    m_tree.root = b2_nullNode;
    m_tree.nodes = nullptr;
    m_tree.nodeCount = 0;
    m_tree.nodeCapacity = 0;
    m_tree.freeList = b2_nullNode;
    m_tree.insertionCount = 0;
    m_proxyCount = 0;
    BroadPhaseState* state = new BroadPhaseState(Box2DFatPolicy());
    m_moveCapacity = 0;
    m_moveCount = 0;
    m_pairBuffer = nullptr;
    m_pairCapacity = 0;
    m_pairCount = 0;
    m_queryProxyId = e_nullProxy;
    if (RequestedByEnvironment("QUADPHASE_STOCK_TREE"))
    {
        // Stock's constructor, on storage of the same layout (checked above).
        state->stockTree = new (&m_tree) b2DynamicTree;
        m_moveCapacity = 16;
        m_pairCapacity = 16;
        m_pairBuffer = static_cast<b2Pair*>(b2Alloc(m_pairCapacity * int32(sizeof(b2Pair))));
    }
    m_state = NewStateBlock(state, m_moveCapacity);
    if (RequestedByEnvironment("QUADPHASE_VALIDATE"))
    {
        quadphase::SetValidation(*this, true);
    }
}

b2BroadPhase::~b2BroadPhase()
{
    BroadPhaseState& state = State(m_state);
    if (state.shadow)
    {
        quadphase::SetValidation(*this, false);
    }
    if (state.stockTree != nullptr)
    {
        state.stockTree->~b2DynamicTree();
        b2Free(m_pairBuffer);
    }
    else
    {
        b2Free(m_tree.nodes);
    }
    delete &state;
    FreeStateBlock(m_state);
}

int32 b2BroadPhase::CreateProxy(const b2AABB& aabb, void* userData)
{
    BroadPhaseState& state = State(m_state);
    const int32 proxyId = state.core.CreateProxy(ToBox(aabb), userData);
    int32 handedOut = proxyId;
    if (state.stockTree != nullptr)
    {
        // Stock's CreateProxy on the tree, whose id is the one handed out.
        handedOut = state.stockTree->CreateProxy(aabb, userData);
        Map(state.coreOfTree, handedOut, proxyId);
        Map(state.treeOfCore, proxyId, handedOut);
        BufferMove(handedOut);
    }
    else
    {
        // The record of the new proxy in m_tree's node array, as stock's inline readers expect it.
        if (proxyId >= m_tree.nodeCapacity)
        {
            // Grows the records by doubling (amortised O(1)), then hands the new array to the core, which copies every
            // live fat box into it.
            const int32 capacity = b2Max(b2Max(16, 2 * m_tree.nodeCapacity), proxyId + 1);
            b2TreeNode* nodes = static_cast<b2TreeNode*>(b2Alloc(capacity * int32(sizeof(b2TreeNode))));
            if (m_tree.nodes != nullptr)
            {
                std::memcpy(nodes, m_tree.nodes, size_t(m_tree.nodeCapacity) * sizeof(b2TreeNode));
            }
            for (int32 i = m_tree.nodeCapacity; i < capacity; ++i)
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
            b2Free(m_tree.nodes);
            m_tree.nodes = nodes;
            m_tree.nodeCapacity = capacity;
            quadphase::BoxMirror mirror;
            mirror.base = reinterpret_cast<unsigned char*>(nodes) + offsetof(b2TreeNode, aabb);
            mirror.stride = sizeof(b2TreeNode);
            mirror.capacity = capacity;
            state.core.SetBoxMirror(mirror);
        }
        // The core writes the records of the fat boxes it changes, but a new proxy's is the adapter's to write.
        const quadphase::Box& fat = state.core.GetPool().Fat(proxyId);
        b2TreeNode& node = m_tree.nodes[proxyId];
        node.aabb.lowerBound.Set(fat.minX, fat.minY);
        node.aabb.upperBound.Set(fat.maxX, fat.maxY);
        node.userData = userData;
        node.height = 0;
        m_tree.nodeCount = state.core.GetProxyCount();
    }
    m_proxyCount = state.core.GetProxyCount();
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::Create, proxyId, ToBox(aabb), {}});
    }
    if (state.shadow)
    {
        state.shadow->OnCreate(proxyId, aabb);
        SyncValidationTotals(state);
    }
    return handedOut;
}

void b2BroadPhase::DestroyProxy(int32 id)
{
    BroadPhaseState& state = State(m_state);
    const int32 proxyId = state.stockTree != nullptr ? CoreId(state, id) : id;
    if (state.stockTree != nullptr && proxyId >= 0)
    {
        UnBufferMove(id);
        state.stockTree->DestroyProxy(id);
        state.coreOfTree[size_t(id)] = -1;
        state.treeOfCore[size_t(proxyId)] = -1;
    }
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::Destroy, proxyId, {}, {}});
    }
    const bool live = state.core.GetPool().IsLive(proxyId);
    if (state.shadow && live)
    {
        state.shadow->OnDestroy(proxyId);
    }
    state.core.DestroyProxy(proxyId); // reports an unknown id
    if (state.stockTree == nullptr)
    {
        if (live)
        {
            b2TreeNode& node = m_tree.nodes[proxyId];
            node.userData = nullptr;
            node.height = -1;
        }
        m_tree.nodeCount = state.core.GetProxyCount();
    }
    m_proxyCount = state.core.GetProxyCount();
}

void b2BroadPhase::MoveProxy(int32 id, const b2AABB& aabb, const b2Vec2& displacement)
{
    BroadPhaseState& state = State(m_state);
    const int32 proxyId = state.stockTree != nullptr ? CoreId(state, id) : id;
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::Move, proxyId, ToBox(aabb), {displacement.x, displacement.y}});
    }
    const quadphase::Box tight = ToBox(aabb);
    const quadphase::Vec2 move{displacement.x, displacement.y};
    if (state.stockTree != nullptr)
    {
        state.core.QueueMove(proxyId, tight, move);
        // Stock's MoveProxy on the tree, which updates its own node.
        if (proxyId >= 0 && state.stockTree->MoveProxy(id, aabb, displacement))
        {
            BufferMove(id);
        }
    }
    else if (proxyId >= 0 && proxyId < m_tree.nodeCapacity && m_tree.nodes[proxyId].height == 0)
    {
        // The record gets the move's outcome now, as stock's tree does inside MoveProxy, so that stock's inline
        // GetFatAABB and TestOverlap, compiled into a program, never read a box the core has not applied yet. The
        // record is the fat box after every earlier move (the core applies its queue before a proxy's second
        // move), so the core's own test on it (branch-free, SSE where available) gives, bit for bit, the box the
        // core computes when it applies this move. A move that keeps its fat box therefore changes nothing in the
        // core either, and is not queued: most moves, so the queue and its batch see only the fat boxes that
        // changed. A box the core must report (non-finite, inverted) is queued whatever the test says.
        b2AABB& record = m_tree.nodes[proxyId].aabb;
        quadphase::Box stored;
        std::memcpy(&stored, static_cast<const void*>(&record), sizeof stored);
        const bool changed = quadphase::RefattenSimd(Box2DFatPolicy(), stored, tight, move);
        if (changed || !quadphase::IsSaneSimd(tight))
        {
            // Queued before the record is written: a second move applies the queue, which rewrites the record
            // with the first move's box.
            state.core.QueueMove(proxyId, tight, move);
        }
        std::memcpy(static_cast<void*>(&record), &stored, sizeof stored);
    }
    else
    {
        state.core.QueueMove(proxyId, tight, move); // an unknown id: the core reports it
    }
    if (state.shadow && state.core.GetPool().IsLive(proxyId))
    {
        state.shadow->OnMove(proxyId, aabb, displacement);
    }
}

void b2BroadPhase::TouchProxy(int32 id)
{
    BroadPhaseState& state = State(m_state);
    const int32 proxyId = state.stockTree != nullptr ? CoreId(state, id) : id;
    if (state.stockTree != nullptr && proxyId >= 0)
    {
        BufferMove(id);
    }
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::Touch, proxyId, {}, {}});
    }
    state.core.TouchProxy(proxyId);
    if (state.shadow && state.core.GetPool().IsLive(proxyId))
    {
        state.shadow->OnTouch(proxyId);
    }
}

void b2BroadPhase::BufferMove(int32 proxyId)
{
    BroadPhaseState& state = State(m_state);
    if (state.stockTree == nullptr)
    {
        // Stock: puts the proxy in the move buffer, which is what TouchProxy does here.
        state.core.TouchProxy(proxyId);
        return;
    }
    // Stock-tree mode: stock's move buffer, in m_state's block.
    if (m_moveCount == m_moveCapacity)
    {
        void* old = m_state;
        m_moveCapacity *= 2;
        m_state = NewStateBlock(&state, m_moveCapacity);
        std::memcpy(m_state, old, size_t(m_moveCount) * sizeof(int32));
        FreeStateBlock(old);
    }
    static_cast<int32*>(m_state)[m_moveCount] = proxyId;
    ++m_moveCount;
}

void b2BroadPhase::UnBufferMove(int32 proxyId)
{
    // Stock: nulls the proxy out of the move buffer when it is destroyed (stock-tree mode); otherwise the core's
    // DestroyProxy does that itself, and m_moveCount is 0.
    int32* moves = static_cast<int32*>(m_state);
    for (int32 i = 0; i < m_moveCount; ++i)
    {
        if (moves[i] == proxyId)
        {
            moves[i] = e_nullProxy;
        }
    }
}

bool b2BroadPhase::QueryCallback(int32 proxyId)
{
    // Stock's, for stock's inline UpdatePairs compiled into a program: collects a pair for the proxy being
    // queried. Reached only in stock-tree mode: otherwise m_tree's root is b2_nullNode and m_moveCount is 0.
    if (proxyId == m_queryProxyId)
    {
        return true;
    }
    const bool moved = State(m_state).stockTree->WasMoved(proxyId);
    if (moved && proxyId > m_queryProxyId)
    {
        return true; // both proxies are moving: avoids duplicate pairs
    }
    if (m_pairCount == m_pairCapacity)
    {
        b2Pair* oldBuffer = m_pairBuffer;
        m_pairCapacity = m_pairCapacity + (m_pairCapacity >> 1);
        m_pairBuffer = static_cast<b2Pair*>(b2Alloc(m_pairCapacity * int32(sizeof(b2Pair))));
        std::memcpy(m_pairBuffer, oldBuffer, size_t(m_pairCount) * sizeof(b2Pair));
        b2Free(oldBuffer);
    }
    m_pairBuffer[m_pairCount].proxyIdA = b2Min(proxyId, m_queryProxyId);
    m_pairBuffer[m_pairCount].proxyIdB = b2Max(proxyId, m_queryProxyId);
    ++m_pairCount;
    return true;
}

void b2BroadPhase::UpdatePairsWith(b2AddPairThunk thunk, void* callback)
{
    BroadPhaseState& state = State(m_state);
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::UpdatePairs, -1, {}, {}});
    }
    state.pairs.clear();
    state.core.FindPairs(state.pairs);
    if (state.shadow)
    {
        state.shadow->OnUpdatePairs(state.pairs);
        SyncValidationTotals(state);
    }
    const quadphase::ProxyPool& pool = state.core.GetPool();
    for (const quadphase::Pair& pair : state.pairs)
    {
        thunk(callback, pool.UserData(pair.a), pool.UserData(pair.b));
    }
    if (state.stockTree != nullptr)
    {
        // As stock's UpdatePairs ends: the move buffer is consumed.
        const int32* moves = static_cast<const int32*>(m_state);
        for (int32 i = 0; i < m_moveCount; ++i)
        {
            if (moves[i] != e_nullProxy)
            {
                state.stockTree->ClearMoved(moves[i]);
            }
        }
        m_moveCount = 0;
    }
}

namespace
{

// Stock-tree mode: the callbacks get the tree's ids. The map is read at each call (a callback may create proxies).
struct QueryBridge
{
    bool (*thunk)(void*, int32);
    void* callback;
    const BroadPhaseState* state;

    static bool Call(void* context, quadphase::ProxyId id)
    {
        QueryBridge& self = *static_cast<QueryBridge*>(context);
        return self.thunk(self.callback, TreeId(*self.state, id));
    }
};

} // namespace

void b2BroadPhase::QueryWith(b2QueryThunk thunk, void* callback, const b2AABB& aabb) const
{
    const BroadPhaseState& state = State(m_state);
    if (state.stockTree != nullptr)
    {
        QueryBridge bridge{thunk, callback, &state};
        state.core.Query(ToBox(aabb), &QueryBridge::Call, &bridge);
        return;
    }
    state.core.Query(ToBox(aabb), thunk, callback);
}

namespace
{

struct RayCastBridge
{
    float (*thunk)(void*, const b2RayCastInput&, int32);
    void* callback;
    b2RayCastInput input;
    const BroadPhaseState* stockTreeMap; // stock-tree mode: the callbacks get the tree's ids

    static float Call(void* context, const quadphase::RayInput& in, quadphase::ProxyId id)
    {
        RayCastBridge& self = *static_cast<RayCastBridge*>(context);
        self.input.maxFraction = in.maxFraction; // p1 and p2 never change; the core clips maxFraction
        return self.thunk(self.callback, self.input,
                          self.stockTreeMap != nullptr ? TreeId(*self.stockTreeMap, id) : id);
    }
};

} // namespace

void b2BroadPhase::RayCastWith(b2RayCastThunk thunk, void* callback, const b2RayCastInput& input) const
{
    const BroadPhaseState& state = State(m_state);
    RayCastBridge bridge{thunk, callback, input, state.stockTree != nullptr ? &state : nullptr};
    const quadphase::RayInput in{{input.p1.x, input.p1.y}, {input.p2.x, input.p2.y}, input.maxFraction};
    state.core.RayCast(in, &RayCastBridge::Call, &bridge);
}

void b2BroadPhase::ShiftOrigin(const b2Vec2& newOrigin)
{
    BroadPhaseState& state = State(m_state);
    if (state.trace != nullptr)
    {
        state.trace->Add({quadphase::TraceOp::ShiftOrigin, -1, {}, {newOrigin.x, newOrigin.y}});
    }
    state.core.ShiftOrigin({newOrigin.x, newOrigin.y}); // rewrites every record
    if (state.stockTree != nullptr)
    {
        state.stockTree->ShiftOrigin(newOrigin);
    }
    if (state.shadow)
    {
        state.shadow->OnShiftOrigin(newOrigin);
    }
}

namespace quadphase
{

void SetValidation(b2BroadPhase& broadPhase, bool enabled)
{
    detail::BroadPhaseState& state = detail::StateOf(broadPhase);
    if (enabled && !state.shadow)
    {
        state.shadow.reset(new ShadowValidator(state.core));
        std::call_once(g_summaryAtExit, [] { std::atexit(&PrintValidationSummary); });
    }
    else if (!enabled && state.shadow)
    {
        state.shadow.reset();
        state.totalsAdded = ValidationReport{};
    }
}

} // namespace quadphase
