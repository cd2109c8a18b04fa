// b2BroadPhase of the paper-design Box2D build: forwards Box2D's calls to PaperQuadtreeBroadPhase.
#include "box2d/b2_broad_phase.h"

#include "quadphase_paper/paper_settings.h"

namespace quadphase::bench
{
namespace
{
PaperSettings& Settings()
{
    static PaperSettings settings;
    return settings;
}
} // namespace

void SetPaperSettings(const PaperSettings& settings)
{
    Settings() = settings;
}

const PaperSettings& GetPaperSettings()
{
    return Settings();
}
} // namespace quadphase::bench

namespace
{
quadphase::FatPolicy Box2DFatPolicy()
{
    quadphase::FatPolicy policy;
    policy.extension = b2_aabbExtension;
    policy.multiplier = b2_aabbMultiplier;
    return policy;
}
} // namespace

b2BroadPhase::b2BroadPhase()
    : m_core(quadphase::bench::GetPaperSettings().levels, quadphase::bench::GetPaperSettings().bounds,
             quadphase::bench::GetPaperSettings().threads, quadphase::bench::GetPaperSettings().schedule,
             quadphase::bench::PaperPairReport::All, Box2DFatPolicy())
{
}

b2BroadPhase::~b2BroadPhase() = default;

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

int32 b2BroadPhase::GetTreeHeight() const
{
    return m_core.GetLevels();
}

int32 b2BroadPhase::GetTreeBalance() const
{
    return 0;
}

float b2BroadPhase::GetTreeQuality() const
{
    return 0.0f;
}

void b2BroadPhase::ShiftOrigin(const b2Vec2& newOrigin)
{
    m_core.ShiftOrigin({newOrigin.x, newOrigin.y});
}
