// SPDX-License-Identifier: MIT
// What watches a quadphase b2BroadPhase: trace recording, validation, stock-tree mode. b2_broad_phase.cpp forwards
// each call to the core and tells the observers, once per call; each observer is a file of its own.
#pragma once

#include <utility>
#include <vector>

#include "box2d/b2_collision.h"
#include "broad_phase_interface.h"

namespace quadphase
{
namespace detail
{

/// Told of every call of a b2BroadPhase, with the core's proxy ids (-1, or an id the core does not know, where the
/// caller gave an unknown id: the core reports it, and each observer decides what such a call means to it). Called
/// after the core has carried the call out, except OnDestroy, called before, while the proxy can still be read.
class BroadPhaseObserver
{
public:
    BroadPhaseObserver() = default;
    BroadPhaseObserver(const BroadPhaseObserver&) = delete;
    BroadPhaseObserver& operator=(const BroadPhaseObserver&) = delete;
    virtual ~BroadPhaseObserver() = default;

    virtual void OnCreate(ProxyId id, const b2AABB& aabb, void* userData) = 0;
    virtual void OnDestroy(ProxyId id) = 0;
    virtual void OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement) = 0;
    virtual void OnTouch(ProxyId id) = 0;
    /// The pairs the core found, before they are handed to the caller's callback.
    virtual void OnUpdatePairs(const std::vector<Pair>& pairs) = 0;
    virtual void OnShiftOrigin(const b2Vec2& newOrigin) = 0;
};

/// The observers of one broadphase, told in the order they were listed:
///     state.observers.Tell(&BroadPhaseObserver::OnMove, id, aabb, displacement);
/// Empty in the common case, where a call costs one comparison for them (MoveProxy runs millions of times a second).
class ObserverList
{
public:
    void Assign(std::vector<BroadPhaseObserver*> observers)
    {
        m_observers = std::move(observers);
        m_empty = m_observers.empty();
    }

    /// No observer: the calls may take their fast paths, which tell no one (one load).
    bool Empty() const { return m_empty; }

    template <typename... Params, typename... Args>
    void Tell(void (BroadPhaseObserver::*call)(Params...), const Args&... args) const
    {
        for (BroadPhaseObserver* observer : m_observers)
        {
            (observer->*call)(args...);
        }
    }

private:
    std::vector<BroadPhaseObserver*> m_observers;
    bool m_empty = true;
};

} // namespace detail
} // namespace quadphase
