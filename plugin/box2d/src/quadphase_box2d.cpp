#include "quadphase/box2d.h"

#include "box2d/b2_contact_manager.h"

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
    BroadPhaseOf(world).GetQuadtree().Configure(config);
}

Config GetConfig(const b2World& world)
{
    return BroadPhaseOf(world).GetQuadtree().GetConfig();
}

Stats GetStats(const b2World& world)
{
    return BroadPhaseOf(world).GetQuadtree().GetStats();
}

void ResetCounters(b2World& world)
{
    BroadPhaseOf(world).GetQuadtree().ResetCounters();
}

void SetTiming(b2World& world, bool enabled)
{
    BroadPhaseOf(world).GetQuadtree().SetTiming(enabled);
}

void SetValidation(b2World& world, bool enabled)
{
    BroadPhaseOf(world).SetValidation(enabled);
}

ValidationReport GetValidationReport(const b2World& world)
{
    const ShadowValidator* validator = BroadPhaseOf(world).GetValidator();
    return validator != nullptr ? validator->Report() : ValidationReport{};
}

void SetTrace(b2World& world, Trace* trace)
{
    BroadPhaseOf(world).SetTrace(trace);
}

const QuadtreeBroadPhase& GetQuadtree(const b2World& world)
{
    return BroadPhaseOf(world).GetQuadtree();
}

QuadtreeBroadPhase& GetQuadtree(b2BroadPhase& broadPhase)
{
    return broadPhase.GetQuadtree();
}

const QuadtreeBroadPhase& GetQuadtree(const b2BroadPhase& broadPhase)
{
    return broadPhase.GetQuadtree();
}

void SetValidation(b2BroadPhase& broadPhase, bool enabled)
{
    broadPhase.SetValidation(enabled);
}

bool IsValidating(const b2BroadPhase& broadPhase)
{
    return broadPhase.IsValidating();
}

ValidationReport GetValidationReport(const b2BroadPhase& broadPhase)
{
    const ShadowValidator* validator = broadPhase.GetValidator();
    return validator != nullptr ? validator->Report() : ValidationReport{};
}

void SetTrace(b2BroadPhase& broadPhase, Trace* trace)
{
    broadPhase.SetTrace(trace);
}

} // namespace quadphase
