// SPDX-License-Identifier: MIT
// OpenMP as an executor of pair generation (Config::executor == Executor::OpenMP), handed to FindPairs as a
// TaskSystem like the library's pool and a game's job system, so that all three run the same split into items.
// Every OpenMP call of the library is in openmp_tasks.cpp.
#pragma once

#include "quadphase/config.h"
#include "quadphase/task_system.h"

namespace quadphase
{
namespace detail
{

/// OpenMP's team size for Config::threads == 0: omp_get_max_threads() (OMP_NUM_THREADS, else the cores).
int OpenMPMaxThreads();

/// Starts OpenMP's team of `threads` now (libgomp keeps it for later regions of that size), so that no step pays
/// for creating it. Does nothing for threads <= 1.
void StartOpenMPTeam(int threads);

/// OpenMP as a game's job system for one FindPairs call: enqueueTask runs every range of the task in one
/// `omp parallel for` of `threads` threads under `schedule` and `chunk` (set for the loop, then restored: the
/// schedule ICV belongs to the caller's thread) and returns nullptr, so finishTask is never called.
class OpenMPTasks
{
public:
    OpenMPTasks(int threads, Schedule schedule, int chunk)
        : m_threads(threads), m_schedule(schedule), m_chunk(chunk)
    {
    }
    TaskSystem Get();

private:
    static void* Enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                         void* userContext);
    static void Finish(void* userTask, void* userContext);

    int m_threads;
    Schedule m_schedule;
    int m_chunk;
};

} // namespace detail
} // namespace quadphase
