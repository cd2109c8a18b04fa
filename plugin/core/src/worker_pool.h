// SPDX-License-Identifier: MIT
// The library's own threads for parallel pair generation (Config::executor == Executor::Pool): a pool of workers
// that sleep whenever they have nothing to do, handed to FindPairs as a TaskSystem like a game's job system.
//
// Why a pool of our own: libgomp's workers spin after every parallel region (GOMP_SPINCOUNT) unless the process
// was started with OMP_WAIT_POLICY=passive, which a library cannot set once libgomp is loaded; a game then loses a
// core's worth of CPU during the time it sleeps between frames (docs/design.md, "Parallel pair generation"). These
// workers block on a condition variable the moment their task's items run out, with no spin.
//
// One pool per process, shared by every broadphase that uses it, rather than one per broadphase:
// - threads: a game may hold many b2Worlds (levels, rooms, previews); the process then has as many workers as the
//   largest thread count asked for, less one, not that many per world;
// - worlds stepped at the same time from different threads: the pool runs one task at a time, and a second
//   caller that finds it busy runs its whole task on its own thread. That caller's thread is itself a core in use,
//   so it gets about what a share of the cores would give it, with no oversubscription; the pairs and their order
//   are the same either way (the task's items write only their own output);
// - lifetime: the pool lives while a broadphase holds it (std::shared_ptr) and its threads are joined when the
//   last one lets go: in the destructor of a broadphase, in the game's own code, never in a static destructor at
//   exit or while a shared library is unloaded (where joining can deadlock under a loader lock, and where a
//   broadphase leaked by the game could still want the pool). A leaked broadphase keeps its sleeping workers until
//   the process exits; std::thread objects that are never destroyed do not call std::terminate.
// Where the platform has no threads (emscripten without pthreads) the pool has no worker, and every task runs on
// its caller.
#pragma once

#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "quadphase/task_system.h"

namespace quadphase
{
namespace detail
{

class WorkerPool
{
public:
    /// The process's pool, created on the first call after the last holder released the previous one. Thread-safe.
    static std::shared_ptr<WorkerPool> Shared();

    /// The thread count Config::threads == 0 plans for: OMP_NUM_THREADS's first number when it is set (what users
    /// and scripts already set to choose this library's threads), else the cores this process may run on (its CPU
    /// affinity on Linux); 1 where the platform has no threads. Read once per process.
    static int DefaultThreads();

    ~WorkerPool();
    WorkerPool(const WorkerPool&) = delete;
    WorkerPool& operator=(const WorkerPool&) = delete;

    /// Makes sure at least `workers` threads exist, creating the missing ones now (never during a task: call it
    /// between steps). Where the system refuses a thread, the pool keeps the ones it has. Returns the worker count.
    int Reserve(int workers);

    /// Threads in the pool (the callers of tasks not counted).
    int Workers() const;

    /// One task: its items, claimed in ranges by an atomic counter; owned by the caller (see Tasks) for the
    /// task's lifetime. The fields below `next` are guarded by the pool's mutex.
    struct Job
    {
        TaskCallback* task = nullptr;
        void* context = nullptr;
        int itemCount = 0;
        int rangeSize = 1;
        std::atomic<int> next{0}; // first item not claimed yet
        int seatsLeft = 0;        // workers that may still join
        int seated = 0;           // workers that joined (their worker indices are 1..seated)
        int inside = 0;           // workers still running ranges
    };

    /// The pool as a game's job system for `participants` threads (the caller and up to participants - 1 workers),
    /// for one FindPairs call: hand Get() to the code that runs a task, and keep this object alive until its
    /// finishTask returned.
    class Tasks
    {
    public:
        /// `pool` may be null: every task then runs on its caller.
        Tasks(WorkerPool* pool, int participants) : m_pool(pool), m_participants(participants) {}
        TaskSystem Get();

    private:
        static void* Enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                             void* userContext);
        static void Finish(void* userTask, void* userContext);

        WorkerPool* m_pool;
        int m_participants;
        Job m_job;
    };

private:
    WorkerPool() = default;
    // Publishes `job` to up to `helpers` workers. False when another caller's task holds the pool or there is no
    // worker: the caller then runs every item itself.
    bool Start(Job& job, int helpers);
    // The caller's part: runs ranges until none is left, then waits for the workers that are still running one.
    void Finish(Job& job);
    void WorkerLoop();
    static void RunRanges(Job& job, unsigned worker);

    mutable std::mutex m_mutex;
    std::condition_variable m_wake; // workers: a job was published, or stop
    std::condition_variable m_done; // the caller in Finish: the last worker left its job
    Job* m_job = nullptr;           // the task being run, null while idle
    bool m_stopping = false;
    std::vector<std::thread> m_threads;
};

} // namespace detail
} // namespace quadphase
