// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase::FindPairs: one query per buffered proxy, serial or in fixed blocks run by an executor (the
// library's pool, OpenMP or the game's task system, all through one TaskSystem interface), with the same pairs in
// the same order every way.
#include "quadtree_broad_phase.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "box_simd.h"
#include "openmp_tasks.h"
#include "quadtree_clock.h"
#include "report_error.h"
#include "worker_pool.h"

namespace quadphase
{
using detail::Clock;
using detail::SecondsSince;

void QuadtreeBroadPhase::QueryPairsOf(ProxyId q, std::vector<Pair>& out) const
{
    const Box qb = m_pool.Fat(q);
    const PreparedBox prepared = Prepare(qb);
    m_pyramid.Visit(qb, [&](const Entry& e) {
        if (OverlapsPrepared(e.box, prepared) && e.id != q)
        {
            // A pair of two buffered proxies is found from both sides; keep it from the smaller id only.
            if (!(e.id > q && m_pool.InWork(e.id)))
            {
                out.push_back(e.id < q ? Pair{e.id, q} : Pair{q, e.id});
            }
        }
        return true;
    });
}

void QuadtreeBroadPhase::FindPairs(std::vector<Pair>& out)
{
    const Clock::time_point start = Clock::now();
    const int64_t work = int64_t(m_queuedCount + m_stale.size()) + m_pool.BufferedCount();
    // Below the threshold no parallel call can happen (neither the queue's apply nor the search), so the executor
    // is not asked (omp_get_max_threads is a call into libgomp; most of Box2D's calls, after time-of-impact events
    // and on quiet scenes, are this small).
    int threads = work >= int64_t(m_config.parallelThreshold) && MayRunParallel() ? Threads() : 1;
    const bool eligible = m_config.threads == 0 && threads > 1 && work >= int64_t(m_config.parallelThreshold);
    // The queued moves applied since the last eligible call: the aftermath of that call's mode (see ThreadChoice).
    const double aftermath = m_aftermathSeconds;
    if (eligible)
    {
        // Which mode to run: the faster one, except on a probe of the other (see ThreadChoice).
        const bool parallel = m_choice.Next();
        if (!parallel)
        {
            threads = 1;
            m_counters.serialByChoice += m_choice.Parallel() ? 0 : 1;
        }
    }
    Clock::time_point now = start;
    ApplyQueued(&now, threads);
    // Entries first, then the re-tune test: the test reads the outside count, which is complete only once every
    // entry is up to date (ApplyQueued already updates the entries that stay in their cell). Queued and immediate
    // moves then re-tune at the same call. A re-tune rebuilds from the fat boxes, so the update work is wasted
    // then; re-tunes are rare.
    UpdateStaleEntries(&now);
    if (NeedsRetune())
    {
        Retune();
    }
    m_pool.LendBuffer(m_work);
    const size_t before = out.size();
    try
    {
        FindPairsOfWork(out, threads);
    }
    catch (...)
    {
        // std::bad_alloc (the only exception the search can throw): nothing reported, nothing lost. The proxies
        // are buffered again, so the next call searches their pairs.
        out.resize(before);
        m_pool.RestoreBuffer(m_work);
        throw;
    }
    const int64_t queried = int64_t(m_work.size());
    m_pool.ReturnBuffer(m_work);

    const int64_t found = int64_t(out.size() - before);
    m_counters.updatePairsCalls += 1;
    m_counters.pairsReported += found;
    m_counters.lastPairs = found;
    m_counters.proxiesQueried += queried;
    const double seconds = SecondsSince(start);
    m_counters.pairSeconds += seconds;
    if (eligible)
    {
        m_choice.Record(threads > 1, aftermath + seconds, double(work));
        m_aftermathSeconds = 0.0; // this call's own apply is in `seconds`
    }
}

void QuadtreeBroadPhase::FindPairsOfWork(std::vector<Pair>& out, int threads)
{
    if (threads > 1 && int64_t(m_work.size()) >= int64_t(m_config.parallelThreshold))
    {
        FindPairsParallel(out, threads);
        m_counters.parallelCalls += 1;
    }
    else
    {
        for (ProxyId q : m_work)
        {
            QueryPairsOf(q, out);
        }
    }
}

void QuadtreeBroadPhase::StartTeam()
{
    m_teamStarted = true;
    const bool pool = !UsesTaskSystem() && m_config.executor == Executor::Pool;
    if (!pool)
    {
        m_workerPool.reset(); // its threads end with the last broadphase that holds it
    }
    if (UsesTaskSystem())
    {
        return; // the game's workers exist already
    }
    const int threads = Threads();
    if (pool && threads > 1)
    {
        if (!m_workerPool)
        {
            m_workerPool = detail::WorkerPool::Shared();
        }
        m_workerPool->Reserve(threads - 1); // the caller is the team's first thread
    }
    else if (!pool)
    {
        detail::StartOpenMPTeam(threads);
    }
}

int QuadtreeBroadPhase::Threads() const
{
    if (UsesTaskSystem())
    {
        const int workers = m_config.taskSystem.workerCount;
        return m_config.threads > 0 ? std::min(m_config.threads, workers) : workers;
    }
    if (m_config.executor == Executor::OpenMP && !OpenMPAvailable())
    {
        return 1; // serial at any Config::threads (see its declaration); the pool needs no OpenMP
    }
    if (m_config.threads > 0)
    {
        return m_config.threads;
    }
    return m_config.executor == Executor::Pool ? detail::WorkerPool::DefaultThreads()
                                               : detail::OpenMPMaxThreads();
}

// The buffered proxies are cut into fixed blocks of kBlock queries, whatever the thread count and whoever runs them
// (the library's pool, OpenMP or the game's task system). Each block writes only its own vector, with no lock; the
// vectors are then joined in block order. The output is therefore the serial loop's output, pair for pair and in the
// same order, at any thread count, under any schedule and in any order the ranges run. During the search the pyramid
// and the pool are only read.
void QuadtreeBroadPhase::SearchBlock(int64_t b)
{
    const int64_t count = int64_t(m_work.size());
    std::vector<Pair>& pairs = m_blockPairs[size_t(b)];
    pairs.clear();
    const int64_t end = std::min(count, (b + 1) * kBlock);
    for (int64_t i = b * kBlock; i < end; ++i)
    {
        QueryPairsOf(m_work[size_t(i)], pairs);
    }
}

void QuadtreeBroadPhase::FindPairsParallel(std::vector<Pair>& out, int threads)
{
    const int64_t count = int64_t(m_work.size());
    const int64_t blocks = (count + kBlock - 1) / kBlock;
    if (int64_t(m_blockPairs.size()) < blocks)
    {
        m_blockPairs.resize(size_t(blocks));
    }
    ReserveBlocks(blocks);
    RunBlocks(blocks, threads, &QuadtreeBroadPhase::SearchBlock, "FindPairs");
    size_t total = out.size();
    for (int64_t b = 0; b < blocks; ++b)
    {
        total += m_blockPairs[size_t(b)].size();
    }
    out.reserve(total);
    for (int64_t b = 0; b < blocks; ++b)
    {
        const std::vector<Pair>& pairs = m_blockPairs[size_t(b)];
        out.insert(out.end(), pairs.begin(), pairs.end());
    }
}

void QuadtreeBroadPhase::ReserveBlocks(int64_t blocks)
{
    if (blocks > m_blockRoom)
    {
        const int64_t room = std::max(blocks, 2 * m_blockRoom);
        m_blockState.reset(new std::atomic<uint8_t>[size_t(room)]);
        m_blockRoom = room;
    }
}

// One RunBlocks call. A game's job system is not ours to trust blindly: each block is claimed before it runs, so a
// block handed out twice runs once, and an item outside the range is counted and ignored. An exception must not
// leave a worker (OpenMP ends the program; a game's job system may not expect one): the first one is kept and
// thrown again on the caller's thread.
struct QuadtreeBroadPhase::BlockRun
{
    static constexpr uint8_t kFree = 0, kClaimed = 1, kEnded = 2;

    QuadtreeBroadPhase* self;
    int64_t blocks;
    void (QuadtreeBroadPhase::*work)(int64_t);
    std::atomic<uint8_t>* state;
    std::mutex errorMutex;
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    std::atomic<int64_t> outOfRange{0}; // items handed over outside [0, blocks)
    std::atomic<int64_t> repeated{0};   // items handed over again

    BlockRun(QuadtreeBroadPhase* owner, int64_t count, void (QuadtreeBroadPhase::*fn)(int64_t))
        : self(owner), blocks(count), work(fn), state(owner->m_blockState.get())
    {
        for (int64_t b = 0; b < blocks; ++b)
        {
            state[b].store(kFree, std::memory_order_relaxed);
        }
    }

    void Run(int64_t b)
    {
        if (b < 0 || b >= blocks)
        {
            outOfRange.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        uint8_t expected = kFree;
        if (!state[b].compare_exchange_strong(expected, kClaimed, std::memory_order_acquire))
        {
            repeated.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        if (!failed.load(std::memory_order_relaxed))
        {
            try
            {
                (self->*work)(b);
            }
            catch (...)
            {
                {
                    std::lock_guard<std::mutex> lock(errorMutex);
                    if (!error)
                    {
                        error = std::current_exception();
                    }
                }
                failed.store(true, std::memory_order_relaxed);
            }
        }
        state[b].store(kEnded, std::memory_order_release);
    }

    static void Task(int startIndex, int endIndex, unsigned /*workerIndex*/, void* context)
    {
        auto* run = static_cast<BlockRun*>(context);
        for (int64_t b = startIndex; b < int64_t(endIndex); ++b)
        {
            run->Run(b);
        }
    }
};

void QuadtreeBroadPhase::RunBlocks(int64_t blocks, int threads, void (QuadtreeBroadPhase::*work)(int64_t),
                                   const char* call)
{
    BlockRun run(this, blocks, work);
    // Each executor is a TaskSystem, so that the blocks are handed out, checked and joined in one way.
    if (UsesTaskSystem())
    {
        RunOnTaskSystem(run, m_config.taskSystem);
    }
    else if (m_config.executor == Executor::Pool)
    {
        detail::WorkerPool::Tasks pool(m_workerPool.get(), threads);
        RunOnTaskSystem(run, pool.Get());
    }
    else
    {
        detail::OpenMPTasks team(threads, m_config.schedule, m_config.chunk);
        RunOnTaskSystem(run, team.Get());
    }
    // Every block once, whatever the executor did: the ones it skipped run here; one it claimed and has not ended
    // (a finishTask that returned before the work) is waited for.
    int64_t missed = 0;
    for (int64_t b = 0; b < blocks; ++b)
    {
        uint8_t s = run.state[b].load(std::memory_order_acquire);
        if (s == BlockRun::kFree)
        {
            ++missed;
            run.Run(b);
            continue;
        }
        while (s != BlockRun::kEnded)
        {
            std::this_thread::yield();
            s = run.state[b].load(std::memory_order_acquire);
        }
    }
    const int64_t outside = run.outOfRange.load(std::memory_order_relaxed);
    const int64_t repeated = run.repeated.load(std::memory_order_relaxed);
    if (missed > 0 || outside > 0 || repeated > 0)
    {
        ReportError(
            ErrorCode::TaskSystemMisuse,
            "%s: the task system ran %lld of %lld items outside [0, %lld), handed out %lld again (run once) "
            "and skipped %lld (run on the calling thread)",
            call, (long long)outside, (long long)blocks, (long long)blocks, (long long)repeated,
            (long long)missed);
    }
    if (run.error)
    {
        std::rethrow_exception(run.error);
    }
}

void QuadtreeBroadPhase::RunOnTaskSystem(BlockRun& run, const TaskSystem& tasks)
{
    void* handle = tasks.enqueueTask(&BlockRun::Task, int(run.blocks), 1, &run, tasks.userContext);
    if (handle != nullptr)
    {
        tasks.finishTask(handle, tasks.userContext);
    }
}

} // namespace quadphase
