// SPDX-License-Identifier: MIT
// The interface every broadphase of this project implements: the quadtree, and the brute-force reference that
// tests and benchmarks check it against (the pattern of Jolt Physics' BroadPhaseBruteForce).
#pragma once

#include <cstdint>
#include <vector>

#include "quadphase/box.h"
#include "ray.h"

namespace quadphase
{

using ProxyId = int32_t;
constexpr ProxyId kNullProxy = -1;

/// A candidate pair, a < b.
struct Pair
{
    ProxyId a;
    ProxyId b;

    friend bool operator==(const Pair& l, const Pair& r) { return l.a == r.a && l.b == r.b; }
    friend bool operator<(const Pair& l, const Pair& r) { return l.a < r.a || (l.a == r.a && l.b < r.b); }
};

/// Called for each proxy whose fat box overlaps a query box. Return false to stop the query.
using QueryFn = bool (*)(void* context, ProxyId id);

/// Called for each proxy whose fat box the searched part of a ray may cross. Return 0 to stop, a positive value
/// to clip the ray to that fraction, a negative value to leave the ray as it is (Box2D's convention).
using RayCastFn = float (*)(void* context, const RayInput& input, ProxyId id);

/// Semantics shared by every implementation (they are Box2D 2.4.1's b2BroadPhase semantics):
/// - Ids are small non-negative integers; a destroyed id is reused by a later CreateProxy (last freed, first used).
/// - Boxes are stored "fat" by the FatPolicy given at construction; GetFatBox returns the stored box.
/// - A proxy is "buffered" when it was created, moved to a new fat box, or touched since the last FindPairs.
/// - FindPairs reports every pair of live proxies whose fat boxes overlap and at least one of which is buffered,
///   each pair once, then clears the buffer. The order is deterministic: it depends only on the call sequence.
/// - Not thread-safe: calls must not overlap, except const calls with each other.
class BroadPhaseInterface
{
public:
    virtual ~BroadPhaseInterface() = default;

    /// Creates a proxy for a shape whose tight box is `tight`; it is buffered. Returns its id.
    virtual ProxyId CreateProxy(const Box& tight, void* userData) = 0;

    /// Destroys a proxy; its id may be reused.
    virtual void DestroyProxy(ProxyId id) = 0;

    /// Tells the broadphase that the shape now has tight box `tight` after moving by `displacement`.
    /// Returns true when the fat box was replaced (the proxy is then buffered).
    virtual bool MoveProxy(ProxyId id, const Box& tight, Vec2 displacement) = 0;

    /// Buffers a proxy so that its pairs are reported again by the next FindPairs.
    virtual void TouchProxy(ProxyId id) = 0;

    /// Appends the pairs (see above) to `out` and clears the buffer.
    virtual void FindPairs(std::vector<Pair>& out) = 0;

    /// Calls `fn` for each proxy whose fat box overlaps `box`, until it returns false.
    virtual void Query(const Box& box, QueryFn fn, void* context) const = 0;

    /// Calls `fn` for each proxy whose fat box the searched part of the ray may cross (see RayCastFn).
    virtual void RayCast(const RayInput& input, RayCastFn fn, void* context) const = 0;

    /// Moves every stored box by -newOrigin.
    virtual void ShiftOrigin(Vec2 newOrigin) = 0;

    virtual const Box& GetFatBox(ProxyId id) const = 0;
    virtual void* GetUserData(ProxyId id) const = 0;
    virtual int32_t GetProxyCount() const = 0;
};

} // namespace quadphase
