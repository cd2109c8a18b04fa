// SPDX-License-Identifier: MIT
// Box2D 2.4.1's own b2BroadPhase (over b2DynamicTree), compiled into the fuzz target under another name so
// that it runs beside quadphase's b2BroadPhase in one process: the oracle of box2d_fuzz.cpp.
//
// Both classes are called b2BroadPhase in their headers, and both headers use the include guard
// B2_BROAD_PHASE_H, so no translation unit can see both. stock_broad_phase.cpp and Box2D's own
// src/collision/b2_broad_phase.cpp are compiled with Box2D's pristine include directory and with
// -Db2BroadPhase=qp_fuzz_stock_b2BroadPhase -Db2Pair=qp_fuzz_stock_b2Pair (tests/fuzz/CMakeLists.txt); this
// header declares only a wrapper with plain callbacks. b2DynamicTree, b2Alloc and the rest are shared with
// quadphase's build of Box2D (the same source, the same flags).
#pragma once

#include <utility>
#include <vector>

#include "box2d/b2_collision.h"

namespace quadphase
{
namespace fuzz
{

class StockBroadPhase
{
public:
    using QueryFn = bool (*)(void* context, int32 proxyId);
    using RayCastFn = float (*)(void* context, const b2RayCastInput& input, int32 proxyId);

    StockBroadPhase();
    ~StockBroadPhase();
    StockBroadPhase(const StockBroadPhase&) = delete;
    StockBroadPhase& operator=(const StockBroadPhase&) = delete;

    int32 CreateProxy(const b2AABB& aabb, void* userData);
    void DestroyProxy(int32 proxyId);
    void MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement);
    void TouchProxy(int32 proxyId);
    const b2AABB& GetFatAABB(int32 proxyId) const;
    void* GetUserData(int32 proxyId) const;
    bool TestOverlap(int32 proxyIdA, int32 proxyIdB) const;
    int32 GetProxyCount() const;
    /// Appends the (userDataA, userDataB) of every AddPair call, repeats included, as b2ContactManager gets
    /// them.
    void UpdatePairs(std::vector<std::pair<void*, void*>>& out);
    void Query(const b2AABB& aabb, QueryFn fn, void* context) const;
    void RayCast(const b2RayCastInput& input, RayCastFn fn, void* context) const;
    void ShiftOrigin(const b2Vec2& newOrigin);

private:
    struct Impl;
    Impl* m_impl;
};

} // namespace fuzz
} // namespace quadphase
