// SPDX-License-Identifier: MIT
// What quadphase's own tools (examples, tests, benchmarks) reach beyond <quadphase/box2d.h>: the quadtree behind a
// b2BroadPhase, and trace recording. Not installed, and not exported from libbox2d.so.2: these hand out the core's
// internal types, so only programs that link the static quadphase::box2d (through quadphase::box2d_internal) call
// them.
#pragma once

#include "box2d/b2_broad_phase.h"
#include "box2d/b2_world.h"
#include "quadphase/box2d.h"
#include "quadtree_broad_phase.h"
#include "trace.h"

namespace quadphase
{

/// The world's quadtree, for drawing and inspection. Valid while the world lives.
const QuadtreeBroadPhase& GetQuadtree(const b2World& world);

/// The broadphase's quadtree. Valid while the broadphase lives.
QuadtreeBroadPhase& GetQuadtree(b2BroadPhase& broadPhase);
const QuadtreeBroadPhase& GetQuadtree(const b2BroadPhase& broadPhase);

/// Records every later broadphase call of the world into `trace` (nullptr stops); see trace.h.
void SetTrace(b2World& world, Trace* trace);

/// Records every later call of the broadphase into `trace` (nullptr stops).
void SetTrace(b2BroadPhase& broadPhase, Trace* trace);

} // namespace quadphase
