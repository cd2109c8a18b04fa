// SPDX-License-Identifier: MIT
// A small job system of the kind games already run: a fixed pool of std::threads fed from one queue. It hands
// itself to quadphase as a quadphase::TaskSystem, so that pair generation runs on these threads instead of OpenMP's.
// The example and the tests use it; a game would hand over its own.
#pragma once

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "quadphase/task_system.h"

namespace qpjobs
{

class JobSystem
{
public:
    /// Who runs a task's ranges. Helps: the caller of finishTask takes ranges too, as a game's main thread does
    /// (fastest; which thread runs which range is then a race). Waits: the caller only waits, so every range of a
    /// task that was split runs on the pool (tests use it to prove that the pool's threads searched).
    enum class Caller
    {
        Helps,
        Waits
    };

    /// `workers` threads take part in a task: the caller of finishTask (worker 0, unless it Waits) and workers - 1
    /// pool threads, all started here. workers >= 1.
    explicit JobSystem(int workers, Caller caller = Caller::Helps)
        : m_workers(std::max(1, workers)), m_callerHelps(caller == Caller::Helps)
    {
        for (int i = 1; i < m_workers; ++i)
        {
            m_threads.emplace_back([this, i] { WorkerLoop(unsigned(i)); });
        }
    }

    ~JobSystem()
    {
        {
            std::lock_guard<std::mutex> lock(m_mutex);
            m_stopping = true;
        }
        m_wake.notify_all();
        for (std::thread& t : m_threads)
        {
            t.join();
        }
    }

    JobSystem(const JobSystem&) = delete;
    JobSystem& operator=(const JobSystem&) = delete;

    /// The callbacks quadphase calls; valid while this object lives.
    quadphase::TaskSystem Tasks()
    {
        quadphase::TaskSystem tasks;
        tasks.enqueueTask = &Enqueue;
        tasks.finishTask = &Finish;
        tasks.workerCount = m_workers;
        tasks.userContext = this;
        return tasks;
    }

    int Workers() const { return m_workers; }
    /// Ranges run so far by the pool's threads (not the caller's): > 0 once a task really ran in parallel.
    int64_t RangesOnPool() const { return m_rangesOnPool.load(); }

private:
    struct Task
    {
        std::atomic<int> remaining{0}; // ranges not finished yet
    };
    struct Range
    {
        quadphase::TaskCallback* fn = nullptr;
        int start = 0;
        int end = 0;
        void* context = nullptr;
        Task* task = nullptr;
    };

    // One range per worker (at least minRange items each), queued; the caller's thread takes its share in Finish.
    static void* Enqueue(quadphase::TaskCallback* fn, int itemCount, int minRange, void* context, void* user)
    {
        auto* self = static_cast<JobSystem*>(user);
        if (itemCount <= 0)
        {
            return nullptr;
        }
        const int ranges = std::max(1, std::min(self->m_workers, itemCount / std::max(1, minRange)));
        if (ranges == 1)
        {
            fn(0, itemCount, 0, context); // not worth a hand-off
            return nullptr;
        }
        auto* task = new Task;
        task->remaining.store(ranges);
        {
            std::lock_guard<std::mutex> lock(self->m_mutex);
            for (int r = 0; r < ranges; ++r)
            {
                const int start = int(int64_t(itemCount) * r / ranges);
                const int end = int(int64_t(itemCount) * (r + 1) / ranges);
                self->m_queue.push_back(Range{fn, start, end, context, task});
            }
        }
        self->m_wake.notify_all();
        return task;
    }

    // The caller helps (unless it Waits) until the queue is empty, then waits for the ranges still running on the
    // pool.
    static void Finish(void* handle, void* user)
    {
        auto* self = static_cast<JobSystem*>(user);
        auto* task = static_cast<Task*>(handle);
        Range range;
        while (self->m_callerHelps && self->Pop(range))
        {
            self->RunRange(range, 0);
        }
        std::unique_lock<std::mutex> lock(self->m_mutex);
        self->m_done.wait(lock, [task] { return task->remaining.load() == 0; });
        lock.unlock();
        delete task;
    }

    bool Pop(Range& range)
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        if (m_queue.empty())
        {
            return false;
        }
        range = m_queue.front();
        m_queue.pop_front();
        return true;
    }

    void RunRange(const Range& range, unsigned worker)
    {
        range.fn(range.start, range.end, worker, range.context);
        if (worker != 0)
        {
            m_rangesOnPool.fetch_add(1);
        }
        if (range.task->remaining.fetch_sub(1) == 1)
        {
            std::lock_guard<std::mutex> lock(m_mutex); // pairs with Finish's wait: no lost wake-up
            m_done.notify_all();
        }
    }

    // Pool threads sleep on the condition variable between tasks: they never spin on a core the game needs.
    void WorkerLoop(unsigned worker)
    {
        for (;;)
        {
            Range range;
            {
                std::unique_lock<std::mutex> lock(m_mutex);
                m_wake.wait(lock, [this] { return m_stopping || !m_queue.empty(); });
                if (m_queue.empty())
                {
                    return; // stopping
                }
                range = m_queue.front();
                m_queue.pop_front();
            }
            RunRange(range, worker);
        }
    }

    const int m_workers;
    const bool m_callerHelps;
    std::vector<std::thread> m_threads;
    std::mutex m_mutex;
    std::condition_variable m_wake; // pool threads: a range was queued, or stop
    std::condition_variable m_done; // Finish: a task's last range finished
    std::deque<Range> m_queue;
    bool m_stopping = false;
    std::atomic<int64_t> m_rangesOnPool{0};
};

} // namespace qpjobs
