// b2BroadPhase of the paper-design Box2D build: forwards Box2D's calls to PaperQuadtreeBroadPhase.
#include "box2d/b2_broad_phase.h"

#include "quadphase_paper/paper_settings.h"

b2BroadPhase::b2BroadPhase()
    : m_core(quadphase::bench::g_paperSettings.levels, quadphase::bench::g_paperSettings.bounds,
             quadphase::bench::g_paperSettings.threads, quadphase::bench::g_paperSettings.schedule,
             quadphase::bench::PaperPairReport::All,
             quadphase::FatPolicy{b2_aabbExtension, b2_aabbMultiplier})
{
}

int32 b2BroadPhase::CreateProxy(const b2AABB& aabb, void* userData)
{
    return m_core.CreateProxy(quadphase::bench::detail::ToBox(aabb), userData);
}

void b2BroadPhase::DestroyProxy(int32 proxyId)
{
    m_core.DestroyProxy(proxyId);
}

void b2BroadPhase::MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement)
{
    m_core.MoveProxy(proxyId, quadphase::bench::detail::ToBox(aabb), {displacement.x, displacement.y});
}

void b2BroadPhase::TouchProxy(int32 proxyId)
{
    m_core.TouchProxy(proxyId);
}
