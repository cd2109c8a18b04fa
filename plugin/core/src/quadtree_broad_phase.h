// SPDX-License-Identifier: MIT
// The static-quadtree broadphase: proxies in a Pyramid, pairs found by one independent query per buffered proxy.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "box_mirror.h"
#include "box_simd.h"
#include "broad_phase_interface.h"
#include "compiler.h"
#include "fat_policy.h"
#include "proxy_pool.h"
#include "pyramid.h"
#include "quadphase/config.h"
#include "quadphase/stats.h"
#include "thread_choice.h"

namespace quadphase
{
namespace detail
{
class WorkerPool; // worker_pool.h
}

/// Exact broadphase over a static quadtree (see Pyramid for the placement rule and why it misses nothing).
///
/// Cost model:
/// - QueueMove and QueueFatMove (what the Box2D adapter calls) are O(1) and only record the move; the moves recorded
///   since the last FindPairs are applied by the next FindPairs, in one batch (see QueueMove).
/// - MoveProxy is O(1): the fat-box test; when the box changed, the proxy is listed as stale. Its cell entry is
///   brought up to date by the next FindPairs, Query or RayCast, for all stale proxies at once, on one thread
///   (Pyramid::UpdateBatch): a query after a mass teleport then costs what it costs after a step, and the work is
///   the work the next FindPairs would have done.
/// - FindPairs is O(buffered proxies x their neighbourhoods): one query per buffered proxy, never a pass over
///   all proxies or all cells. Box2D calls it once per step and again after every time-of-impact event.
/// - The pyramid is rebuilt (O(proxies)) when the automatic rule re-tunes depth and bounds: when the proxy
///   count has doubled or fallen to a quarter since the last tuning, or when more than a quarter of the proxies
///   have moved outside the bounds since the last tuning; and on ShiftOrigin and a Configure that changes a layout
///   setting. See docs/design.md.
///
/// Determinism: the same sequence of calls gives the same ids, the same pairs and the same pair order, at any
/// thread count and schedule, on any executor.
/// Threading: no call may overlap another, except const calls with each other (a const call that finds queued
/// moves or stale entries applies them under a lock; see QueueMove). GetStats takes the same lock. Different
/// objects may be used from different threads at the same time (they share only the pool of Executor::Pool,
/// which is thread-safe).
/// Re-entrancy: the callbacks of Query and RayCast may call any method of this object (Box2D games create,
/// destroy and move bodies from b2World::QueryAABB and RayCast callbacks); see Query for what is then reported.
/// A rebuild (Configure, ShiftOrigin, an automatic re-tune) counts as moving every proxy.
/// Allocation failure: std::bad_alloc propagates out of the call that needed the memory, never from inside a
/// worker thread; FindPairs then leaves the queued moves or the move buffer as they were, so calling it again
/// reports every pair.
class QuadtreeBroadPhase final : public BroadPhaseInterface
{
public:
    explicit QuadtreeBroadPhase(const FatPolicy& policy = FatPolicy{}, const Config& config = Config{});

    ProxyId CreateProxy(const Box& tight, void* userData) override;
    void DestroyProxy(ProxyId id) override;
    bool MoveProxy(ProxyId id, const Box& tight, Vec2 displacement) override;

    /// MoveProxy for callers that do not need its answer (Box2D 2.4.1's b2BroadPhase::MoveProxy returns void):
    /// checks the id and the box (bad input is reported here, at the call) and records the move. Its effect, the
    /// same as MoveProxy's (new fat box when the policy says so, move buffer, cell entry), is applied in call order
    /// by the next FindPairs, or before anything that reads a fat box or changes the proxy set
    /// (MoveProxy, DestroyProxy, TouchProxy, GetFatBox, TestOverlap, Query, RayCast, ShiftOrigin, Configure,
    /// Validate). Why: Box2D moves its bodies one by one; queuing makes each call a store, and the fat-box tests run
    /// in one branch-free batch. A proxy queued twice before the queue is applied makes the second call apply the
    /// queue first (in order), so the outcome never depends on when it is applied. The queue holds at most
    /// QueueLimit() moves (an eighth of the proxies, up to kQueueChunk): a full queue is applied by the next
    /// QueueMove. The queue is applied on the calling thread (see ApplyQueued).
    void QueueMove(ProxyId id, const Box& tight, Vec2 displacement)
    {
        // Inline fast path (Box2D calls this once per moving fixture, on one thread); anything unusual (unknown
        // id, bad box, a second move of the proxy, timing on, a queue of QueueFatMove's) takes the out-of-line path.
        // int operands: & on bools is what is meant (no short-circuit branches), and clang warns otherwise.
        if (QUADPHASE_LIKELY(int(m_pool.IsLiveAndNotPending(id)) & int(IsSaneSimd(tight)) &
                             int(m_queuedCount < m_fastRoom)))
        {
            Enqueue(id, tight, displacement);
            return;
        }
        QueueMoveSlow(tight, QueuedMove{tight, displacement, id});
    }

    /// QueueMove for a caller that keeps every proxy's current fat box itself (the boxes of the moves it queued,
    /// and through the mirror the others) and has run the fat-box test on it (RefattenSimd with this object's
    /// policy): the Box2D adapter, whose node records stock's inline readers read between calls. Call it only for a
    /// move whose fat box changed, with `fat` the test's outcome; a move that keeps its fat box changes nothing
    /// (QueueMove it anyway when `tight` is bad, so that the box is reported). `tight` is checked as QueueMove
    /// checks it. Applied as QueueMove's move would be, with `fat` as its outcome: the test is not run again and
    /// the mirror is not written (the caller has the box already), so a changed fat box is computed once and
    /// written once. Unlike QueueMove's, this queue is never applied for being full: it grows (4 bytes per queued
    /// proxy, the pool holding the box), so that the cell upkeep of the moves runs in FindPairs, never in the
    /// caller's serial calls. The queue holds one kind of move at a time: a QueueFatMove after a QueueMove, or the
    /// reverse, applies the queue first (in call order, so the outcome is the same).
    void QueueFatMove(ProxyId id, const Box& tight, const Box& fat)
    {
        if (QUADPHASE_LIKELY(IsSaneSimd(tight) && TryQueueFatMove(id, fat))) // a bad box queues nothing
        {
            return;
        }
        QueueFatMoveSlow(tight, id, fat);
    }

    /// QueueFatMove's inline part, for a caller that has checked `tight` itself (IsSaneSimd): queues the move and
    /// returns true, or returns false having changed nothing when the move needs QueueFatMove's out-of-line path
    /// (unknown id, a second move of the proxy, a queue of QueueMove's, a full queue, timing on).
    bool TryQueueFatMove(ProxyId id, const Box& fat)
    {
        if (int(m_pool.IsLiveAndNotPending(id)) & int(m_queuedCount < m_fastFatRoom))
        {
            EnqueueFat(id, fat);
            return true;
        }
        return false;
    }

    /// Applies the queued moves now (see QueueMove). Calls that read fat boxes do it themselves; this is for
    /// readers of GetPool() and GetPyramid(). Takes the lock; safe to call concurrently with const calls.
    void ApplyQueuedMoves() const { ApplyQueuedIfAny(); }

    /// Moves recorded by QueueMove and not applied yet.
    int32_t QueuedMoveCount() const { return int32_t(m_queuedCount); }
    void TouchProxy(ProxyId id) override;
    void FindPairs(std::vector<Pair>& out) override;

    /// Calls fn for every proxy whose fat box overlaps `box`, until fn returns false. Applies queued moves and
    /// brings stale entries up to date first (see QueueMove), so its cost follows the proxies near `box`.
    /// Re-entrancy (stock b2DynamicTree's guarantees, or better): the candidates are collected before the first
    /// callback, so fn may create, destroy and move proxies. Then:
    /// - a proxy that existed before the call and is neither destroyed nor moved during it is reported, once;
    /// - a proxy destroyed during the call is never reported after its destruction (stock reports it);
    /// - a proxy created or moved during the call may or may not be reported (reported only if its box at that
    ///   moment overlaps `box`);
    /// - no id is reported twice in one call.
    void Query(const Box& box, QueryFn fn, void* context) const override;

    /// Calls fn for every proxy whose fat box the segment may cross (b2DynamicTree::RayCast's test, with its
    /// arithmetic); fn returns 0 to stop, a fraction in (0, maxFraction] to clip the segment, or a negative value
    /// to go on unchanged. Walks, level by level from the root, only the cells whose proxies the (clipped) segment
    /// can reach, row by row in the ray's direction, so a long or diagonal ray costs the cells it crosses, and a
    /// closest-hit cast stops once the walk passes the clipped end. Falls back to the segment's bounding box where
    /// that reads less (short rays, sparse levels, degenerate or non-finite segments).
    /// Re-entrancy: as Query (same guarantees), with the clipped segment in place of the box. The cells of each
    /// batch are read afresh after the previous batch's callbacks. When a callback rebuilds the pyramid (an
    /// automatic re-tune, Configure, ShiftOrigin) the walk starts again from the root, skipping the ids already
    /// reported; after 64 rebuilds within one call (callbacks that rebuild at every report) it ends the ray cast.
    void RayCast(const RayInput& input, RayCastFn fn, void* context) const override;
    void ShiftOrigin(Vec2 newOrigin) override;

    /// The stored fat box. For an unknown id, reports ErrorCode::UnknownProxy and returns an empty box.
    const Box& GetFatBox(ProxyId id) const override;
    /// The user data, or nullptr for an unknown id (as b2BroadPhase::GetUserData documents).
    void* GetUserData(ProxyId id) const override;
    int32_t GetProxyCount() const override { return m_pool.LiveCount(); }

    /// Overlap of two proxies' fat boxes. Unknown ids report an error and answer false.
    bool TestOverlap(ProxyId a, ProxyId b) const;

    /// Applies new settings. When a layout setting differs from the current one (depth, maxDepth, autoBounds,
    /// bounds, cellToProxyRatio), it re-tunes for the current proxies and rebuilds the pyramid (O(proxies));
    /// settings of the executor alone (threads, schedule, chunk, the thresholds, taskSystem) change no layout,
    /// so the pairs and their order from then on are those the previous settings would have given. Pairs already
    /// reported are unaffected. All or nothing: std::bad_alloc or std::invalid_argument changes nothing.
    void Configure(const Config& config);
    const Config& GetConfig() const { return m_config; }

    /// Runs parallel pair generation on the game's job system from the next FindPairs on (an empty TaskSystem{} goes
    /// back to Config::executor); like Configure with only the task system changed, it rebuilds nothing. The measured
    /// serial/parallel choice starts afresh. Throws std::invalid_argument, changing nothing, for a half-set one (see
    /// TaskSystem).
    void SetTaskSystem(const TaskSystem& tasks);

    /// A snapshot of shape and work counters. O(cells) for the occupancy fields. Safe beside concurrent const
    /// calls: it takes the lock under which they apply queued moves.
    Stats GetStats() const;
    void ResetCounters();

    /// When true, MoveProxy, CreateProxy and DestroyProxy are timed into Stats::updateSeconds (two clock reads
    /// per call). FindPairs is always timed.
    void SetTiming(bool enabled)
    {
        m_timing = enabled;
        UpdateFastRoom();
    }

    /// Copies every fat box this object changes from now on into `mirror` (see BoxMirror), and writes the current
    /// fat box of every live proxy below its capacity now (after applying queued moves). A mirror with a null base
    /// stops the copies. O(proxies).
    void SetBoxMirror(const BoxMirror& mirror);
    const BoxMirror& GetBoxMirror() const { return m_mirror; }

    /// Read-only access for drawing and tests. The fat boxes are those of the last applied move: queued moves
    /// (QueueMove) are not in them until ApplyQueuedMoves, FindPairs or a reading call applies them.
    const Pyramid& GetPyramid() const { return m_pyramid; }
    const ProxyPool& GetPool() const { return m_pool; }
    /// The policy this object was made with (a caller of QueueFatMove runs its fat-box test with it).
    const FatPolicy& GetPolicy() const { return m_policy; }

    /// Checks every invariant of the pool and the pyramid, and that each stored box equals the pool's fat box.
    /// Empty string when all hold, otherwise the first violation. O(proxies + cells).
    std::string Validate() const;

private:
    struct QueuedMove
    {
        Box box; // the tight box (QueueMove), or the new fat box (QueueFatMove): the queue's kind says which
        Vec2 displacement;
        ProxyId id;
    };
    // The inline paths' store. Field by field into the slot: a temporary QueuedMove copied in as a whole was a
    // store-forwarding stall (two stores read back by one wider load), the largest cost of QueueMove.
    void Enqueue(ProxyId id, const Box& box, Vec2 displacement)
    {
        m_pool.MarkPending(id);
        QueuedMove& slot = m_queued[m_queuedCount];
        slot.box = box;
        slot.displacement = displacement;
        slot.id = id;
        m_hasQueued.store(true, std::memory_order_release);
        ++m_queuedCount; // when this fills the queue, the next move (QueueMoveSlow) applies or grows it
    }
    // QueueFatMove's store: the new fat box goes to the pool now (every reader of it applies the queue first), and
    // only the id to the queue.
    void EnqueueFat(ProxyId id, const Box& fat)
    {
        m_pool.MarkPending(id);
        m_pool.Fat(id) = fat;
        m_queuedIds[m_queuedCount] = id;
        m_hasQueued.store(true, std::memory_order_release);
        ++m_queuedCount; // when this fills the queue, the next move (QueueFatMoveSlow) grows it
    }
    // 8192 x 28 bytes (229 KB): a chunk still in the cache of the thread that queued it when it is applied, a
    // dozen applies per step for 100k moving proxies (each has a fixed cost of a few hundred ns), and a bound on
    // memory that does not grow with the world.
    static constexpr size_t kQueueChunk = 8192;
    // The queue's capacity: an eighth of the live proxies, as a power of two from 64 to kQueueChunk: at most 3.5
    // bytes per proxy (a queue sized to every moving proxy costs 28), and smaller chunks cost only their fixed
    // overhead (a few hundred ns each). See docs/design.md, "Memory".
    size_t QueueLimit() const
    {
        size_t limit = 64;
        while (limit < kQueueChunk && limit < size_t(m_pool.LiveCount()) / 8)
        {
            limit *= 2;
        }
        return limit;
    }

    // Applies the queue when it is not empty; the common empty case is one atomic load.
    void ApplyQueuedIfAny() const
    {
        if (m_hasQueued.load(std::memory_order_acquire))
        {
            ApplyQueuedLocked();
        }
    }
    void ApplyQueuedLocked() const;
    // For Query and RayCast: applies the queue and brings the stale entries up to date (the work the next FindPairs
    // would do, done once instead of each query scanning the stale list). Two atomic loads when there is none.
    void ApplyForRead() const
    {
        if (m_hasQueued.load(std::memory_order_acquire) || m_hasStale.load(std::memory_order_acquire))
        {
            ApplyForReadLocked();
        }
    }
    void ApplyForReadLocked() const;
    void NoteStale() { m_hasStale.store(!m_stale.empty(), std::memory_order_release); }
    void CheckBox(const Box& b, const char* call, ProxyId id);
    void FindPairsOfWork(std::vector<Pair>& out, int threads);
    // The out-of-line paths of QueueMove and QueueFatMove; `tight` is the box to check.
    void QueueMoveSlow(const Box& tight, const QueuedMove& move);
    void QueueFatMoveSlow(const Box& tight, ProxyId id, const Box& fat);
    // Applies a queue of the other kind than `fat` says, then makes it that kind.
    void SwitchQueueKind(bool fat);
    // Applies the queue, in queue order: fat-box tests, in-cell rewrites, then the stale list and the move buffer.
    // Requires exclusive access. With `threads` > 1 (FindPairs' own parallel calls), the tests and rewrites run in
    // fixed blocks of kApplyBlock moves on the executor, and the blocks' lists are joined in block order: the same
    // lists as on one thread.
    // `now`, when given, is the caller's last clock reading (taken as this call's start) and receives its end.
    void ApplyQueued(std::chrono::steady_clock::time_point* now = nullptr, int threads = 1);
    // What ApplyRange found in one range of the queue.
    struct ApplyCounts
    {
        // Moves with a new fat box, and those of them that left their cell: each listed from the range's start
        // (in m_refattened, or m_queuedIds itself for a queue of QueueFatMove's, and in m_stale's tail).
        int32_t changed = 0;
        int32_t stale = 0;
        int32_t outsideDelta = 0; // the change of the pyramid's outside count
    };
    // Applies the queued moves [begin, end) (ApplyQueued's two loops): writes only those moves' proxies' flags,
    // boxes, mirror slots and cell entries, so ranges of distinct moves may run at the same time. Clears their
    // pending flags when `clearPending` says so (else the caller has).
    ApplyCounts ApplyRange(int64_t begin, int64_t end, bool clearPending);
    void ApplyBlock(int64_t b);                 // ApplyRange of block b, its counts to m_applyCounts[b]
    static constexpr int64_t kApplyBlock = 256; // queued moves per block of a parallel apply
    void WriteMirrorOfAll();
    void Retune();
    void Rebuild(float originX, float originY, float side, int depth);
    Pyramid BuildPyramid(float originX, float originY, float side, int depth, Vec2 shift) const;
    void CommitRebuild(Pyramid&& built);
    bool NeedsRetune() const;
    void QueryPairsOf(ProxyId q, std::vector<Pair>& out) const;
    void UpdateStaleEntries(std::chrono::steady_clock::time_point* now = nullptr); // `now` as in ApplyQueued
    int Threads() const;
    // Whether a FindPairs call may go parallel at all: an explicit thread count, or a scene of
    // Config::parallelMinProxies proxies.
    bool MayRunParallel() const
    {
        return m_config.threads > 1 ||
               (m_config.threads == 0 && m_pool.LiveCount() >= m_config.parallelMinProxies);
    }
    // Starts the executor's threads the first time MayRunParallel() holds, so that no FindPairs pays for creating
    // them.
    void StartTeamIfDue()
    {
        if (!m_teamStarted && MayRunParallel())
        {
            StartTeam();
        }
    }
    void StartTeam();
    bool UsesTaskSystem() const { return m_config.taskSystem.enqueueTask != nullptr; }
    void FindPairsParallel(std::vector<Pair>& out, int threads);
    class RayCaster;                      // one RayCast call (quadtree_queries.cpp)
    static constexpr int64_t kBlock = 64; // queries per block of a parallel search
    void SearchBlock(int64_t b);
    // Runs (this->*work)(b) for every block b in [0, blocks) on `threads` threads of this call's executor (the
    // library's pool, OpenMP or the game's task system), each block exactly once, whatever the executor does: a
    // block it skipped runs on the calling thread, one it hands out twice runs once, and the misuse is reported.
    // The first exception of a block is thrown again here, after every block has ended. `blocks` must not exceed
    // what ReserveBlocks made room for.
    void RunBlocks(int64_t blocks, int threads, void (QuadtreeBroadPhase::*work)(int64_t), const char* call);
    // Room for RunBlocks of `blocks` blocks (may throw std::bad_alloc; call it before changing anything).
    void ReserveBlocks(int64_t blocks);
    struct BlockRun;
    void RunOnTaskSystem(BlockRun& run, const TaskSystem& tasks);

    FatPolicy m_policy;
    Config m_config;
    ProxyPool m_pool;
    Pyramid m_pyramid;
    // QueueMove calls not applied yet, in call order, one per proxy at most: the first m_queuedCount slots. The
    // vector's size is the queue's capacity (grown by QueueMoveSlow, up to QueueLimit()), so the fast path never
    // allocates.
    std::vector<QueuedMove> m_queued;
    // QueueFatMove calls not applied yet, the same way (their boxes are in the pool already); grown by
    // QueueFatMoveSlow without a limit other than the proxies (each is queued at most once).
    std::vector<ProxyId> m_queuedIds;
    size_t m_queuedCount = 0; // of m_queued or m_queuedIds, the kind m_queueHoldsFat says
    // True while the queue holds QueueFatMove's moves (the kind of the last move queued): one kind at a time keeps
    // ApplyQueued's loops free of a branch per move.
    bool m_queueHoldsFat = false;
    // Slots QueueMove's and QueueFatMove's inline paths may fill: the queue's capacity for the kind it holds, 0 for
    // the other kind and while timing is on (those calls take the out-of-line path). One comparison on the hot path.
    size_t m_fastRoom = 0;
    size_t m_fastFatRoom = 0;
    void UpdateFastRoom()
    {
        m_fastRoom = m_queueHoldsFat || m_timing ? 0 : m_queued.size();
        m_fastFatRoom = m_queueHoldsFat && !m_timing ? m_queuedIds.size() : 0;
    }
    // ApplyQueued's scratch for a queue of QueueMove's, in queue order: the ids whose fat box changed (for the move
    // buffer). A queue of QueueFatMove's needs none: each of its boxes is new, so its ids are that list. The stale
    // ids need none either: ApplyQueued lends ApplyRange the tail of m_stale, from m_staleTail.
    std::vector<ProxyId> m_refattened;
    size_t m_staleTail = 0; // m_stale's size before the ApplyQueued call that is running
    mutable std::atomic<bool> m_hasQueued{false}; // m_queuedCount > 0, readable without the lock
    mutable std::atomic<bool> m_hasStale{false};  // !m_stale.empty(), readable without the lock
    mutable std::mutex m_queueMutex;              // serialises const calls that apply the queue
    // proxies whose pairs the current FindPairs searches (the pool's move buffer)
    std::vector<ProxyId> m_work;
    // proxies whose fat box changed since their cell entry was written (see MoveProxy)
    std::vector<ProxyId> m_stale;
    std::vector<std::vector<Pair>> m_blockPairs; // parallel FindPairs: the pairs of each block of m_work
    // RunBlocks: each block's state (0 free, 1 claimed by a thread, 2 ended), m_blockRoom of them
    std::unique_ptr<std::atomic<uint8_t>[]> m_blockState;
    int64_t m_blockRoom = 0;
    std::vector<ApplyCounts> m_applyCounts; // parallel ApplyQueued: what each block found
    int32_t m_tunedCount = 0;               // live proxies at the last automatic tuning
    int32_t m_tunedOutside = 0; // proxies outside the bounds right after the last automatic tuning
    ThreadChoice m_choice;      // Config::threads == 0: serial or parallel FindPairs calls
    // Seconds spent applying queued moves since the last FindPairs that consulted m_choice: the part of a mode's
    // window (see ThreadChoice) that lies outside the calls.
    double m_aftermathSeconds = 0.0;
    bool m_teamStarted = false; // StartTeam ran (or a task system made it unnecessary)
    // Executor::Pool: the process's detail::WorkerPool, held from the first StartTeam on (see worker_pool.h); null
    // otherwise.
    std::shared_ptr<detail::WorkerPool> m_workerPool;
    // Counts calls that changed proxies or entries (create, destroy, move, queue applied, rebuild). Query and
    // RayCast compare it before and after their callbacks: unchanged means every collected candidate is still
    // what it was, so the re-entrancy checks cost nothing in the common case.
    uint64_t m_mutations = 0;
    BoxMirror m_mirror; // see SetBoxMirror; disabled by default
    bool m_timing = false;
    mutable Stats m_counters; // work counters only; shape fields are filled by GetStats
};

} // namespace quadphase
