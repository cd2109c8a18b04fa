// SPDX-License-Identifier: MIT
// b2BroadPhase of the paper-design Box2D build: its constructor, which reads the paper settings
// (the calls are forwarded to PaperQuadtreeBroadPhase inline, in the header).
#include "box2d/b2_broad_phase.h"

#include "quadphase_paper/paper_settings.h"

b2BroadPhase::b2BroadPhase()
    : m_core(quadphase::bench::g_paperSettings.levels, quadphase::bench::g_paperSettings.bounds,
             quadphase::bench::g_paperSettings.threads, quadphase::bench::g_paperSettings.schedule,
             quadphase::bench::PaperPairReport::All,
             quadphase::FatPolicy{b2_aabbExtension, b2_aabbMultiplier})
{
}
