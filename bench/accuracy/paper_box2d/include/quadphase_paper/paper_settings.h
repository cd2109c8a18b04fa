// SPDX-License-Identifier: MIT
// Settings of the paper-design b2BroadPhase (the third Box2D build of bench/accuracy, qp-accuracy-paper).
//
// b2World constructs its b2BroadPhase itself, with no arguments, so the paper's quadtree takes its levels,
// bounds and threads from these process-wide settings at construction time. Set them before creating a world;
// a world keeps the settings it was created with.
#pragma once

#include "quadphase/box.h"
#include "quadphase/config.h"

namespace quadphase::bench
{

struct PaperSettings
{
    int levels = 6;                               ///< the paper's "Lvl" (root = level 1), clamped to [1, 9]
    Box bounds{-100.0f, -100.0f, 100.0f, 100.0f}; ///< the fixed region (the paper's window)
    int threads = 1;                              ///< 1 = the paper's sequential tree; n >= 2 = a team of n
    Schedule schedule = Schedule::Static;         ///< the leaf loop's OpenMP schedule
};

/// Settings for b2BroadPhase objects constructed from now on. Not thread-safe (set before building a world).
inline PaperSettings g_paperSettings;

} // namespace quadphase::bench
