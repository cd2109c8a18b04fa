// SPDX-License-Identifier: MIT
// quadphase's API for Box2D users (quadphase/box2d.h) and for its own tools (box2d_internal.h): reaches a b2World's
// broadphase and forwards to its quadtree.
#include "quadphase/box2d.h"

#include "box2d/b2_contact_manager.h"

#include "box2d_internal.h"
#include "broad_phase_state.h"
#include "validation_observer.h"

namespace quadphase
{
namespace
{

b2BroadPhase& BroadPhaseOf(b2World& world)
{
    // b2World exposes its contact manager only as const; the broadphase is a public member of it.
    return const_cast<b2ContactManager&>(world.GetContactManager()).m_broadPhase;
}

const b2BroadPhase& BroadPhaseOf(const b2World& world)
{
    return world.GetContactManager().m_broadPhase;
}

} // namespace

void Configure(b2World& world, const Config& config)
{
    GetQuadtree(BroadPhaseOf(world)).Configure(config);
}

void SetTaskSystem(b2World& world, const TaskSystem& tasks)
{
    GetQuadtree(BroadPhaseOf(world)).SetTaskSystem(tasks);
}

Config GetConfig(const b2World& world)
{
    return GetQuadtree(BroadPhaseOf(world)).GetConfig();
}

Stats GetStats(const b2World& world)
{
    return GetQuadtree(BroadPhaseOf(world)).GetStats();
}

void ResetCounters(b2World& world)
{
    GetQuadtree(BroadPhaseOf(world)).ResetCounters();
}

void SetTiming(b2World& world, bool enabled)
{
    GetQuadtree(BroadPhaseOf(world)).SetTiming(enabled);
}

void SetValidation(b2World& world, bool enabled)
{
    SetValidation(BroadPhaseOf(world), enabled);
}

ValidationReport GetValidationReport(const b2World& world)
{
    return GetValidationReport(BroadPhaseOf(world));
}

void SetTrace(b2World& world, Trace* trace)
{
    SetTrace(BroadPhaseOf(world), trace);
}

const QuadtreeBroadPhase& GetQuadtree(const b2World& world)
{
    return GetQuadtree(BroadPhaseOf(world));
}

QuadtreeBroadPhase& GetQuadtree(b2BroadPhase& broadPhase)
{
    return detail::StateOf(broadPhase).core;
}

const QuadtreeBroadPhase& GetQuadtree(const b2BroadPhase& broadPhase)
{
    return detail::StateOf(broadPhase).core;
}

void SetTrace(b2BroadPhase& broadPhase, Trace* trace)
{
    detail::StateOf(broadPhase).SetTrace(trace);
}

} // namespace quadphase
