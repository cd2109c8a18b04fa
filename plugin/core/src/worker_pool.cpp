// SPDX-License-Identifier: MIT
// WorkerPool: the library's sleeping workers (see worker_pool.h for the design and why the pool is shared).
#include "worker_pool.h"

#include <algorithm>
#include <cstdlib>
#include <system_error>

#include "environment.h"

#if defined(__linux__)
#include <sched.h>
#endif
#if defined(__GLIBC__)
#include <pthread.h>
#endif
#if defined(_WIN32)
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#ifndef NOMINMAX
#define NOMINMAX
#endif
#include <windows.h>
#endif

// emscripten without -pthread links stubs whose pthread_create fails: no worker is ever started there.
#if defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)
#define QUADPHASE_POOL_THREADS 0
#else
#define QUADPHASE_POOL_THREADS 1
#endif

namespace quadphase
{
namespace detail
{
namespace
{

int CountDefaultThreads()
{
#if QUADPHASE_POOL_THREADS
    if (const char* value = EnvironmentValue("OMP_NUM_THREADS"))
    {
        // "4" or "4,2" (a thread count per nesting level): the first level's, as OpenMP reads it.
        char* end = nullptr;
        const long threads = std::strtol(value, &end, 10);
        if (end != value && threads > 0)
        {
            return int(std::min(threads, 1024L));
        }
    }
#if defined(__linux__)
    // The CPUs this process may run on (taskset, cgroup cpusets), as libgomp counts them, rather than every online
    // one (std::thread::hardware_concurrency).
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0)
    {
        return CPU_COUNT(&set);
    }
#endif
    return std::max(1, int(std::thread::hardware_concurrency()));
#else
    return 1;
#endif
}

#if defined(_WIN32)
// Names the calling thread "quadphase" where Windows can (SetThreadDescription, Windows 10 1607 and later; Wine),
// for debuggers, profilers and Process Explorer, as pthread_setname_np does with glibc. Looked up at run time, so
// that box2d.dll still loads on an older Windows. Called by each worker as it starts: the handle behind
// std::thread::native_handle() differs between MinGW's winpthreads and MSVC.
void NameThisWorker()
{
    using SetThreadDescriptionFn = HRESULT(WINAPI*)(HANDLE, PCWSTR);
    const HMODULE kernel32 = GetModuleHandleW(L"kernel32.dll");
    const FARPROC proc = kernel32 != nullptr ? GetProcAddress(kernel32, "SetThreadDescription") : nullptr;
    if (proc != nullptr)
    {
        // Through void (*)(), the type GCC's -Wcast-function-type lets any function pointer become.
        const auto setDescription =
            reinterpret_cast<SetThreadDescriptionFn>(reinterpret_cast<void (*)()>(proc));
        setDescription(GetCurrentThread(), L"quadphase");
    }
}
#endif

// The process's pool while someone holds it. Allocated once and never destroyed: a broadphase destroyed during
// static destruction (a game's global b2World) may still release its pool after this file's statics are gone.
struct Registry
{
    std::mutex mutex;
    std::weak_ptr<WorkerPool> pool;
};

Registry& TheRegistry()
{
    static Registry* registry = new Registry;
    return *registry;
}

} // namespace

std::shared_ptr<WorkerPool> WorkerPool::Shared()
{
    Registry& registry = TheRegistry();
    std::lock_guard<std::mutex> lock(registry.mutex);
    std::shared_ptr<WorkerPool> pool = registry.pool.lock();
    if (!pool)
    {
        pool.reset(new WorkerPool);
        registry.pool = pool;
    }
    return pool;
}

int WorkerPool::DefaultThreads()
{
    static const int threads = CountDefaultThreads();
    return threads;
}

WorkerPool::~WorkerPool()
{
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        m_stopping = true;
    }
    m_wake.notify_all();
    for (std::thread& thread : m_threads)
    {
        thread.join();
    }
}

int WorkerPool::Reserve(int workers)
{
    std::lock_guard<std::mutex> lock(m_mutex);
#if QUADPHASE_POOL_THREADS
    while (int(m_threads.size()) < workers)
    {
        try
        {
            m_threads.emplace_back([this] { WorkerLoop(); });
#if defined(__GLIBC__)
            // How the threads show in top, perf and debuggers (set here, so it shows as soon as Reserve returns).
            pthread_setname_np(m_threads.back().native_handle(), "quadphase");
#endif
        }
        catch (const std::system_error&)
        {
            break; // a thread limit reached: the tasks are shared among the workers there are
        }
    }
#else
    (void)workers;
#endif
    return int(m_threads.size());
}

int WorkerPool::Workers() const
{
    std::lock_guard<std::mutex> lock(m_mutex);
    return int(m_threads.size());
}

bool WorkerPool::Start(Job& job, int helpers)
{
    int seats = 0;
    int workers = 0;
    {
        std::lock_guard<std::mutex> lock(m_mutex);
        workers = int(m_threads.size());
        if (m_job != nullptr || workers == 0)
        {
            return false;
        }
        seats = std::min(helpers, workers);
        job.next.store(0, std::memory_order_relaxed);
        job.seatsLeft = seats;
        job.seated = 0;
        job.inside = 0;
        m_job = &job;
    }
    // Wake only as many workers as may join: the others stay asleep and cost nothing.
    if (seats == workers)
    {
        m_wake.notify_all();
    }
    else
    {
        for (int i = 0; i < seats; ++i)
        {
            m_wake.notify_one();
        }
    }
    return true;
}

void WorkerPool::Finish(Job& job)
{
    RunRanges(job, 0);
    std::unique_lock<std::mutex> lock(m_mutex);
    job.seatsLeft = 0; // the items are all claimed: a worker that has not joined yet need not
    m_done.wait(lock, [&job] { return job.inside == 0; });
    m_job = nullptr;
}

void WorkerPool::RunRanges(Job& job, unsigned worker)
{
    for (;;)
    {
        const int start = job.next.fetch_add(job.rangeSize, std::memory_order_relaxed);
        if (start >= job.itemCount)
        {
            return;
        }
        job.task(start, std::min(job.itemCount, start + job.rangeSize), worker, job.context);
    }
}

void WorkerPool::WorkerLoop()
{
#if defined(_WIN32)
    NameThisWorker();
#endif
    std::unique_lock<std::mutex> lock(m_mutex);
    for (;;)
    {
        // Asleep until a job has a seat for this worker: no spinning, whatever the game does meanwhile.
        m_wake.wait(lock, [this] { return m_stopping || (m_job != nullptr && m_job->seatsLeft > 0); });
        if (m_stopping)
        {
            return;
        }
        Job& job = *m_job;
        --job.seatsLeft;
        ++job.inside;
        const unsigned worker = unsigned(++job.seated);
        lock.unlock();
        RunRanges(job, worker);
        lock.lock();
        job.seatsLeft = 0;
        if (--job.inside == 0)
        {
            m_done.notify_one(); // the caller, if it already waits in Finish
        }
    }
}

TaskSystem WorkerPool::Tasks::Get()
{
    return TaskSystem{&Enqueue, &Finish, std::max(1, m_participants), this};
}

void* WorkerPool::Tasks::Enqueue(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                                 void* userContext)
{
    auto* self = static_cast<Tasks*>(userContext);
    if (itemCount <= 0)
    {
        return nullptr;
    }
    Job& job = self->m_job;
    job.task = task;
    job.context = taskContext;
    job.itemCount = itemCount;
    job.rangeSize = std::max(1, minRange);
    const int ranges = (itemCount - 1) / job.rangeSize + 1;
    const int helpers = std::min(self->m_participants - 1, ranges - 1);
    if (helpers > 0 && self->m_pool != nullptr && self->m_pool->Start(job, helpers))
    {
        return &job;
    }
    // One range, one participant, or the pool busy with another caller's task: all of it here, now.
    job.next.store(0, std::memory_order_relaxed);
    RunRanges(job, 0);
    return nullptr;
}

void WorkerPool::Tasks::Finish(void* userTask, void* userContext)
{
    auto* self = static_cast<Tasks*>(userContext);
    self->m_pool->Finish(*static_cast<Job*>(userTask));
}

} // namespace detail
} // namespace quadphase
