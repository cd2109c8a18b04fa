// Which of quadphase's names libbox2d.so.2 exports. Box2D's sources are compiled with hidden visibility, as stock's
// CMake builds them, so the library exports what B2_API marks (stock's symbols) and, through this file, quadphase's
// extras: everything declared in the installed quadphase headers (<quadphase/box2d.h>, the objects it hands out,
// and the core they are made of). Included before anything else (-include) into quadphase's own sources of the
// shared library only: the classes and functions below are then first declared, once and for all (#pragma once),
// with default visibility. What is not declared here (quadphase::detail, the sources' own helpers) stays hidden;
// what the compiler exports regardless (libstdc++'s template instances, OpenMP's critical sections) the version
// script libbox2d.map drops.
#pragma once

// Box2D's own headers first, outside the pragma: B2_API alone decides what of Box2D is exported.
#include "box2d/box2d.h"

#pragma GCC visibility push(default)
#include "quadphase/box.h"
#include "quadphase/box2d.h"
#include "quadphase/box_mirror.h"
#include "quadphase/broad_phase_interface.h"
#include "quadphase/brute_force_broad_phase.h"
#include "quadphase/cell_store.h"
#include "quadphase/config.h"
#include "quadphase/error.h"
#include "quadphase/fat_policy.h"
#include "quadphase/proxy_pool.h"
#include "quadphase/pyramid.h"
#include "quadphase/quadtree_broad_phase.h"
#include "quadphase/ray.h"
#include "quadphase/shadow_validator.h"
#include "quadphase/stats.h"
#include "quadphase/thread_choice.h"
#include "quadphase/trace.h"
#pragma GCC visibility pop
