// SPDX-License-Identifier: MIT
// User settings of the quadtree broadphase.
#pragma once

#include "quadphase/box.h"
#include "quadphase/export.h"
#include "quadphase/task_system.h"

namespace quadphase
{

/// Who runs parallel pair generation when no Config::taskSystem is set. Either way the pairs and their order are
/// those of the serial loop: the work is cut into the same blocks, written in the same order.
enum class Executor
{
    /// The library's own pool of threads, one per process (shared by every broadphase), whose threads sleep as
    /// soon as a step's pair search ends: no CPU is used between steps. The default.
    Pool,
    /// OpenMP (`omp parallel for` under Config::schedule). libgomp's threads keep spinning after each step
    /// (GOMP_SPINCOUNT) unless the process was started with OMP_WAIT_POLICY=passive: up to a core's worth of CPU
    /// while the game waits for its next frame. Serial in a build without OpenMP (see OpenMPAvailable).
    OpenMP,
};

/// OpenMP loop schedules for pair generation (the paper compared the first three).
enum class Schedule
{
    Static,
    Dynamic,
    Guided,
    Auto,
};

/// Settings of a quadtree broadphase. The defaults choose everything from the proxies.
struct Config
{
    /// Depth of the pyramid (levels 0..depth), or -1 to choose it automatically (see docs/design.md, "Automatic
    /// depth and bounds"). Fixed depths are clamped to [0, kMaxDepth].
    int depth = -1;

    /// Largest depth the automatic rule may pick; bounds memory (a pyramid of depth d has (4^(d+1)-1)/3 cells).
    int maxDepth = 12;

    /// When false, `bounds` is used as the square-ish region the pyramid covers; proxies outside it are clamped
    /// into border cells (found, but slower). When true, the bounds follow the proxies automatically.
    bool autoBounds = true;
    Box bounds{-100.0f, -100.0f, 100.0f, 100.0f};

    /// Target ratio of the finest cell's side to the median fat-box extent, used by the automatic depth
    /// (docs/design.md, "Automatic depth and bounds").
    float cellToProxyRatio = 2.0f;

    /// Threads for pair generation, the caller's included, run by `executor` (the library's pool by default).
    /// 0: up to OMP_NUM_THREADS's first number when it is set, else the cores the process may run on (for
    /// Executor::OpenMP: omp_get_max_threads()), but serial while serial calls are measured faster (a machine whose
    /// cores are busy with other work makes every parallel call wait; see QuadtreeBroadPhase::FindPairs). N > 0: up
    /// to N, always (Executor::Pool: fewer while another broadphase's call holds the pool; then this call runs on
    /// its own thread). 1: serial, with no thread started. The pairs and their order do not depend on it.
    /// The pool is plain std::thread and runs in every build. Executor::OpenMP in a build without OpenMP
    /// (OpenMPAvailable() false: QUADPHASE_OPENMP=OFF, as with Apple's clang or Emscripten) runs serially at every
    /// value: the fallback is documented here and not reported as an error, since a thread count asks for speed,
    /// never for other pairs. The value is kept as given (GetConfig returns it) and Stats::parallelCalls stays 0;
    /// use the pool or a taskSystem to run in parallel there.
    int threads = 0;

    /// Who runs the parallel calls: the library's sleeping pool (the default; see Executor) or OpenMP. Ignored
    /// while a taskSystem is set. The pairs and their order do not depend on it.
    Executor executor = Executor::Pool;

    /// Executor::OpenMP only: schedule of the loop over blocks of buffered proxies, and its chunk size in blocks
    /// (0: OpenMP's default for that schedule; the pool hands out one block at a time to whichever thread is
    /// free). The pairs and their order do not depend on them. Guided by default: it ties with static when the
    /// queries cost alike, and evens out scenes where they do not (rain), where static's contiguous halves leave a
    /// thread waiting; see docs/design.md.
    Schedule schedule = Schedule::Guided;
    int chunk = 0;

    /// FindPairs with fewer buffered proxies than this runs serially, with no parallel region at all: a parallel
    /// region costs a few microseconds, more than the queries of a small scene or of a time-of-impact update.
    /// Chosen from bench/ measurements; see docs/design.md, "Parallel pair generation".
    int parallelThreshold = 128;

    /// With threads == 0 (the default), pair generation goes parallel only while the broadphase holds at least
    /// this many proxies; below it every call is serial and no thread is started. In the last quiet full run
    /// (bench/RESULTS.md, b2Profile::broadphase, 1 against 2 threads) two threads paid from particles 20,000 and rain
    /// 32,000 on, and lost or tied below (particles 10,000, rain 16,000, pyramid 60, mixed 3,000, churn 8,000), while
    /// a small scene paid for starting the team and for probing the parallel path in its first steps (see
    /// docs/design.md, "Defaults"). Once a broadphase reaches it, the executor's threads are started at once, in
    /// CreateProxy or Configure (between steps in Box2D), so that no step pays for creating threads.
    /// Explicit thread counts (threads > 0) ignore it.
    int parallelMinProxies = 16384;

    /// The game's job system (see quadphase/task_system.h). When set, parallel pair generation runs on it and
    /// quadphase starts no thread of its own and makes no OpenMP call; `threads` then counts the game's workers
    /// (0: up to taskSystem.workerCount, chosen by measurement as for the executors; N > 0: min(N, workerCount)),
    /// and `executor`, `schedule` and `chunk` do not apply. Empty by default: `executor` runs the parallel calls.
    /// Configure rejects a half-set one (std::invalid_argument).
    TaskSystem taskSystem;
};

/// Whether this build of the library has OpenMP (built with QUADPHASE_OPENMP=ON), that is whether Executor::OpenMP
/// runs in parallel. When false, Executor::OpenMP runs serially (see Config::threads); the pool, the default, and a
/// Config::taskSystem run in parallel in every build.
QUADPHASE_API bool OpenMPAvailable();

/// Deepest pyramid allowed: 4^12 leaf cells already cost hundreds of MB.
constexpr int kMaxDepth = 12;

} // namespace quadphase
