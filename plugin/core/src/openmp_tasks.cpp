// SPDX-License-Identifier: MIT
// OpenMP's side of pair generation: the team, and one parallel loop per task (see openmp_tasks.h).
#include "openmp_tasks.h"

#include <algorithm>
#include <atomic>

// _OPENMP: the compiler's own mark of -fopenmp. Without it (a compiler or platform without OpenMP) the executor
// runs every range on the caller, in order: the same output, serially.
#ifdef _OPENMP
#include <omp.h>
#endif

namespace quadphase
{
namespace detail
{
namespace
{

unsigned ThreadNumber()
{
#ifdef _OPENMP
    return unsigned(omp_get_thread_num());
#else
    return 0;
#endif
}

} // namespace

int OpenMPMaxThreads()
{
#ifdef _OPENMP
    return omp_get_max_threads();
#else
    return 1;
#endif
}

void StartOpenMPTeam(int threads)
{
    if (threads > 1)
    {
        // A region that only counts its threads: libgomp creates the team here and keeps it for the later
        // regions of the same size. (GCC drops a region with an empty body, threads and all.)
        std::atomic<int> started{0};
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
        started.fetch_add(1, std::memory_order_relaxed);
    }
}

TaskSystem OpenMPTasks::Get()
{
    return TaskSystem{&Enqueue, &Finish, std::max(1, m_threads), this};
}

void* OpenMPTasks::Enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                           void* userContext)
{
    const auto* self = static_cast<const OpenMPTasks*>(userContext);
    const int rangeSize = std::max(1, minRange);
    const int ranges = itemCount > 0 ? (itemCount - 1) / rangeSize + 1 : 0;
#ifdef _OPENMP
    omp_sched_t previousKind;
    int previousChunk;
    omp_get_schedule(&previousKind, &previousChunk);
    static constexpr omp_sched_t kKinds[] = {omp_sched_static, omp_sched_dynamic, omp_sched_guided,
                                             omp_sched_auto};
    omp_set_schedule(kKinds[int(self->m_schedule)], self->m_chunk);
#pragma omp parallel for schedule(runtime) num_threads(self->m_threads)
#endif
    for (int r = 0; r < ranges; ++r)
    {
        const int start = r * rangeSize;
        task(start, std::min(itemCount, start + rangeSize), ThreadNumber(), taskContext);
    }
#ifdef _OPENMP
    omp_set_schedule(previousKind, previousChunk);
#else
    (void)self->m_schedule; // no schedule without OpenMP
    (void)self->m_chunk;
#endif
    return nullptr; // every range ran: finishTask is not called
}

void OpenMPTasks::Finish(void* /*userTask*/, void* /*userContext*/) {}

} // namespace detail

bool OpenMPAvailable()
{
#ifdef _OPENMP
    return true;
#else
    return false;
#endif
}

} // namespace quadphase
