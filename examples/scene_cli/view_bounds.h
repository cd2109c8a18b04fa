// SPDX-License-Identifier: MIT
// The world rectangle a frame shows when the user gives no --view.
#pragma once

#include "box2d/box2d.h"
#include "scene_cli_options.h"

namespace quadphase::scene_cli
{

/// Fixtures wider or taller than this (metres) are left out of the automatic view: a 20 km ground would
/// otherwise shrink everything else to a line.
constexpr float kAutoViewMaxFixture = 2000.0f;

/// The union of the AABBs of the world's fixtures (each no more than kAutoViewMaxFixture across), grown by 4%
/// on each side; all fixtures when every one is larger; [-10, 10]^2 for an empty world.
ViewRect AutoView(const b2World& world);

} // namespace quadphase::scene_cli
