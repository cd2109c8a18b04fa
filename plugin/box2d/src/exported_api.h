// SPDX-License-Identifier: MIT
// Which of quadphase's names libbox2d.so.2 exports. Box2D's sources are compiled with hidden visibility, as stock's
// CMake builds them, so the library exports what B2_API marks (stock's symbols) and, through this file, quadphase's
// public extras: what the installed headers declare (<quadphase/box2d.h> and the core headers it stands on:
// settings, statistics, the error hook, the task system). Included before anything else (-include) into quadphase's
// own sources of the shared library only: the functions below are then first declared, once and for all
// (#pragma once), with default visibility. Everything else of ours stays hidden: the core's classes and the
// adapter's internals (headers under plugin/*/src), quadphase::detail, the sources' own helpers. What the compiler
// exports regardless (libstdc++'s template instances, OpenMP's critical sections) the version script libbox2d.map
// drops. tests/abi/quadphase_exports.txt lists the result.
#pragma once

// Box2D's own headers first, outside the pragma: B2_API alone decides what of Box2D is exported.
#include "box2d/box2d.h"

#pragma GCC visibility push(default)
#include "quadphase/box.h"
#include "quadphase/box2d.h"
#include "quadphase/config.h"
#include "quadphase/error.h"
#include "quadphase/stats.h"
#include "quadphase/task_system.h"
#pragma GCC visibility pop
