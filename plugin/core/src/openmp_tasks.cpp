// OpenMP's side of pair generation: the team, and one parallel loop per task (see openmp_tasks.h).
#include "openmp_tasks.h"

#include <algorithm>
#include <atomic>

#include <omp.h>

namespace quadphase
{
namespace detail
{

int OpenMPMaxThreads()
{
    return omp_get_max_threads();
}

void StartOpenMPTeam(int threads)
{
    if (threads > 1)
    {
        // A region that only counts its threads: libgomp creates the team here and keeps it for the later
        // regions of the same size. (GCC drops a region with an empty body, threads and all.)
        std::atomic<int> started{0};
#pragma omp parallel num_threads(threads)
        started.fetch_add(1, std::memory_order_relaxed);
    }
}

TaskSystem OpenMPTasks::Get()
{
    TaskSystem tasks;
    tasks.enqueueTask = &Enqueue;
    tasks.finishTask = &Finish;
    tasks.workerCount = std::max(1, m_threads);
    tasks.userContext = this;
    return tasks;
}

void* OpenMPTasks::Enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                           void* userContext)
{
    const auto* self = static_cast<const OpenMPTasks*>(userContext);
    omp_sched_t previousKind;
    int previousChunk;
    omp_get_schedule(&previousKind, &previousChunk);
    static constexpr omp_sched_t kKinds[] = {omp_sched_static, omp_sched_dynamic, omp_sched_guided,
                                             omp_sched_auto};
    omp_set_schedule(kKinds[int(self->m_schedule)], self->m_chunk);
    const int rangeSize = std::max(1, minRange);
    const int ranges = itemCount > 0 ? (itemCount - 1) / rangeSize + 1 : 0;
#pragma omp parallel for schedule(runtime) num_threads(self->m_threads)
    for (int r = 0; r < ranges; ++r)
    {
        const int start = r * rangeSize;
        task(start, std::min(itemCount, start + rangeSize), unsigned(omp_get_thread_num()), taskContext);
    }
    omp_set_schedule(previousKind, previousChunk);
    return nullptr; // every range ran: finishTask is not called
}

void OpenMPTasks::Finish(void* /*userTask*/, void* /*userContext*/) {}

} // namespace detail
} // namespace quadphase
