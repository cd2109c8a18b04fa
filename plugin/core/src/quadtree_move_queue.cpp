// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase's moves: MoveProxy, the move queue (QueueMove's slow path and its apply) and the stale entries
// that both leave for the next FindPairs or query.
#include "quadtree_broad_phase.h"

#include <algorithm>
#include <atomic>
#include <chrono>

#include "box_simd.h"
#include "quadtree_clock.h"

namespace quadphase
{
using detail::Clock;
using detail::SecondsSince;

namespace
{

// Grows a vector's capacity to at least n, geometrically (a plain reserve(n) reallocates to exactly n each time).
template <typename T>
void ReserveAtLeast(std::vector<T>& v, size_t n)
{
    if (v.capacity() < n)
    {
        v.reserve(std::max(n, 2 * v.capacity()));
    }
}

} // namespace

bool QuadtreeBroadPhase::MoveProxy(ProxyId id, const Box& tight, Vec2 displacement)
{
    if (!m_pool.CheckLive(id, "MoveProxy"))
    {
        return false;
    }
    ApplyQueuedIfAny(); // moves take effect in call order
    // Checked before Refatten: a bad box may lie inside the stored fat box, which is then kept, and must be
    // reported all the same.
    CheckBox(tight, "MoveProxy", id);
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    Box& fat = m_pool.Fat(id);
    if (!Refatten(m_policy, fat, tight, displacement))
    {
        return false;
    }
    m_mirror.Write(id, fat);
    ++m_mutations;
    if (m_pool.MarkStale(id))
    {
        m_stale.push_back(id);
        NoteStale();
    }
    m_pool.Buffer(id);
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
    return true;
}

void QuadtreeBroadPhase::SwitchQueueKind(bool fat)
{
    if (fat != m_queueHoldsFat)
    {
        // The other kind: the moves queued so far are applied first, in call order.
        ApplyQueued();
        m_queueHoldsFat = fat;
        UpdateFastRoom();
    }
}

void QuadtreeBroadPhase::QueueMoveSlow(const Box& tight, const QueuedMove& move)
{
    if (!m_pool.CheckLive(move.id, "MoveProxy"))
    {
        return;
    }
    CheckBox(tight, "MoveProxy", move.id);
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    SwitchQueueKind(false);
    if (!m_pool.MarkPending(move.id))
    {
        // Moved twice before the queue was applied: the second move must see the first one's fat box.
        ApplyQueued();
        m_pool.MarkPending(move.id);
    }
    if (m_queuedCount == m_queued.size())
    {
        // Full. Grows by doubling up to QueueLimit(), so a small world holds a small queue; at the limit, the
        // queue is applied and refilled.
        const size_t limit = QueueLimit();
        if (m_queued.size() < limit)
        {
            m_queued.resize(std::min(limit, std::max<size_t>(64, 2 * m_queued.size())));
            UpdateFastRoom();
        }
        else
        {
            ApplyQueued();
        }
    }
    m_queued[m_queuedCount++] = move;
    m_hasQueued.store(true, std::memory_order_release);
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
}

void QuadtreeBroadPhase::QueueFatMoveSlow(const Box& tight, ProxyId id, const Box& fat)
{
    if (!m_pool.CheckLive(id, "MoveProxy"))
    {
        return;
    }
    CheckBox(tight, "MoveProxy", id);
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    SwitchQueueKind(true);
    if (m_pool.IsPending(id))
    {
        // Moved twice before the queue was applied: the first move takes effect first (the stale list and the
        // move buffer keep call order).
        ApplyQueued();
    }
    if (m_queuedCount == m_queuedIds.size())
    {
        // Full: grows by doubling (std::bad_alloc here changes nothing). Never applied here: its cell upkeep is
        // FindPairs' work.
        m_queuedIds.resize(std::max<size_t>(64, 2 * m_queuedIds.size()));
    }
    UpdateFastRoom();
    EnqueueFat(id, fat);
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
}

void QuadtreeBroadPhase::ApplyQueuedLocked() const
{
    std::lock_guard<std::mutex> lock(m_queueMutex);
    if (m_hasQueued.load(std::memory_order_relaxed))
    {
        // Logically const: the fat boxes a caller observes are already defined by the calls made; applying the
        // queue only brings the stored ones up to date.
        const_cast<QuadtreeBroadPhase*>(this)->ApplyQueued();
    }
}

void QuadtreeBroadPhase::ApplyForReadLocked() const
{
    std::lock_guard<std::mutex> lock(m_queueMutex);
    // Logically const, as ApplyQueuedLocked: the entries only catch up with the calls already made. Safe beside
    // concurrent const calls: they cannot be reading the pyramid now, since every one of them saw the same flags
    // (only non-const calls set them) and waits on this lock before reading.
    QuadtreeBroadPhase* self = const_cast<QuadtreeBroadPhase*>(this);
    if (m_hasQueued.load(std::memory_order_relaxed))
    {
        self->ApplyQueued();
    }
    if (m_hasStale.load(std::memory_order_relaxed))
    {
        self->UpdateStaleEntries();
    }
}

void QuadtreeBroadPhase::ApplyQueued(Clock::time_point* now, int threads)
{
    const int64_t count = int64_t(m_queuedCount);
    if (count == 0)
    {
        return;
    }
    // A caller that already read the clock hands its reading over and gets this call's end back: on a step where
    // almost nothing moves, clock reads are a noticeable part of it.
    const Clock::time_point start = now != nullptr ? *now : Clock::now();
    // On the caller's thread unless FindPairs runs in parallel: the moves were queued on this thread, so the
    // queue, the pending flags and most fat boxes are in its cache (docs/design.md, "Grid maintenance"). In
    // FindPairs' parallel calls the blocks of moves run on the executor, since on many cores a serial apply
    // bounds the whole call.
    const int64_t blocks = (count + kApplyBlock - 1) / kApplyBlock;
    const bool parallel = threads > 1 && blocks >= 2 && count >= int64_t(m_config.parallelThreshold);
    // Everything this call allocates is reserved here, before any change: std::bad_alloc leaves the queue as it was.
    if (!m_queueHoldsFat)
    {
        ReserveAtLeast(m_refattened, size_t(count));
    }
    ReserveAtLeast(m_stale, m_stale.size() + size_t(count));
    m_pool.ReserveBuffer(size_t(count));
    if (parallel)
    {
        ReserveBlocks(blocks);
        m_applyCounts.resize(size_t(blocks));
    }
    ++m_mutations;
    // Within the capacities reserved above: no allocation. Each range lists its ids from its own start: the ids
    // with a new fat box in m_refattened (or the queue itself), the stale ids in m_stale's tail, which is cut back
    // to the ones listed below. Nothing reads m_stale until then.
    if (!m_queueHoldsFat)
    {
        m_refattened.resize(size_t(count));
    }
    m_staleTail = m_stale.size();
    m_stale.resize(m_staleTail + size_t(count));
    ProxyId* const buffered = m_queueHoldsFat ? m_queuedIds.data() : m_refattened.data();
    ProxyId* const stale = m_stale.data() + m_staleTail;
    size_t n = 0;
    size_t ns = 0;
    int32_t outsideDelta = 0;
    if (parallel)
    {
        // The pending flags are cleared here, on the caller's thread: the next step's MoveProxy calls, on this
        // thread, read and set them, and would otherwise fetch each flag's cache line from the core that cleared
        // it. The blocks then write flags only for the few proxies that leave their cell (MarkStale).
        uint8_t* const state = m_pool.MutableStateData();
        for (int64_t i = 0; i < count; ++i)
        {
            state[size_t(m_queueHoldsFat ? m_queuedIds[size_t(i)] : m_queued[size_t(i)].id)] &=
                ProxyPool::kClearPendingMask;
        }
        try
        {
            RunBlocks(blocks, threads, &QuadtreeBroadPhase::ApplyBlock, "FindPairs");
        }
        catch (...)
        {
            m_stale.resize(m_staleTail); // as before the call: the borrowed tail is not a list of stale ids
            throw;
        }
        // The blocks' lists, joined in block order: the lists of one range over the whole queue. Each moves to a
        // place before its own (std::copy: a forward copy never overwrites what it has yet to read). A queue of
        // QueueFatMove's lists every id already.
        for (int64_t b = 0; b < blocks; ++b)
        {
            const ApplyCounts& c = m_applyCounts[size_t(b)];
            const size_t from = size_t(b * kApplyBlock);
            if (!m_queueHoldsFat && n < from)
            {
                std::copy(buffered + from, buffered + from + c.changed, buffered + n);
            }
            if (ns < from)
            {
                std::copy(stale + from, stale + from + c.stale, stale + ns);
            }
            n += size_t(c.changed);
            ns += size_t(c.stale);
            outsideDelta += c.outsideDelta;
        }
    }
    else
    {
        const ApplyCounts c = ApplyRange(0, count, true);
        n = size_t(c.changed);
        ns = size_t(c.stale);
        outsideDelta = c.outsideDelta;
    }
    m_pyramid.AddOutsideDelta(outsideDelta);
    // In queue order, so the stale list and the move buffer are the ones MoveProxy calls would have built (less
    // the proxies already re-placed in their cell).
    m_stale.resize(m_staleTail + ns);
    m_pool.Buffer(buffered, n);
    m_refattened.clear();
    m_queuedCount = 0;
    m_hasQueued.store(false, std::memory_order_release);
    if (m_queued.size() > 2 * QueueLimit() ||
        m_queuedIds.size() > 2 * std::max<size_t>(64, size_t(m_pool.LiveCount())))
    {
        // The world shrank: so do the queues (and the lists sized from them).
        std::vector<QueuedMove>(std::min(m_queued.size(), QueueLimit())).swap(m_queued);
        std::vector<ProxyId>(std::min(m_queuedIds.size(), std::max<size_t>(64, size_t(m_pool.LiveCount()))))
            .swap(m_queuedIds);
        UpdateFastRoom();
        std::vector<ProxyId>().swap(m_refattened);
    }
    NoteStale();
    const Clock::time_point end = Clock::now();
    const double seconds = std::chrono::duration<double>(end - start).count();
    m_counters.updateSeconds += seconds;
    m_aftermathSeconds += seconds;
    if (now != nullptr)
    {
        *now = end;
    }
}

void QuadtreeBroadPhase::ApplyBlock(int64_t b)
{
    m_applyCounts[size_t(b)] =
        ApplyRange(b * kApplyBlock, std::min(int64_t(m_queuedCount), (b + 1) * kApplyBlock), false);
}

QuadtreeBroadPhase::ApplyCounts QuadtreeBroadPhase::ApplyRange(int64_t begin, int64_t end, bool clearPending)
{
    // Two passes over the range:
    // 1. the fat-box tests, without a branch on the outcome (RefattenSimd, and an append that always writes and
    //    advances by the outcome): whether a body keeps its fat box is close to random, and the mispredictions
    //    cost more than the test. A queue of QueueFatMove's holds the outcomes already: every box is new;
    // 2. each new fat box is written into the proxy's cell entry when it stays in its cell (most do: a fat box is
    //    smaller than a cell); the others are flagged and listed stale and wait for UpdateStaleEntries.
    // Everything the loops read in locals: through members (or the pool) the compiler reloads the policy, the
    // arrays and the constants built from them after every flag store, since a char store may alias anything.
    const QueuedMove* const moves = m_queued.data();
    Box* const boxes = m_pool.MutableFatData();
    uint8_t* const state = m_pool.MutableStateData();
    const FatPolicy policy = m_policy;
    // QueueFatMove's caller has its boxes already: only the boxes computed here are copied to the mirror.
    const BoxMirror mirror = m_queueHoldsFat ? BoxMirror{} : m_mirror;
    ProxyId* const stale = m_stale.data() + m_staleTail + begin;
    const ProxyId* changed = nullptr; // the ids with a new fat box, in queue order
    size_t n = 0;
    if (m_queueHoldsFat)
    {
        // The boxes are in the pool already (EnqueueFat), and every one is new: the queue lists them.
        changed = m_queuedIds.data() + begin;
        n = size_t(end - begin);
        if (clearPending)
        {
            for (size_t k = 0; k < n; ++k)
            {
                state[size_t(changed[k])] &= ProxyPool::kClearPendingMask;
            }
        }
    }
    else
    {
        int32_t* const out = m_refattened.data() + begin;
        changed = out;
        for (int64_t i = begin; i < end; ++i)
        {
            const QueuedMove& move = moves[i];
            if (clearPending)
            {
                state[size_t(move.id)] &= ProxyPool::kClearPendingMask;
            }
            out[n] = move.id;
            n += RefattenSimd(policy, boxes[move.id], move.box, move.displacement) ? 1 : 0;
        }
    }
    ApplyCounts counts;
    size_t ns = 0;
    for (size_t k = 0; k < n; ++k)
    {
        const ProxyId id = changed[k];
        if (mirror.Enabled())
        {
            mirror.Write(id, boxes[id]);
        }
        if (!m_pyramid.RewriteInPlace(id, boxes[id], counts.outsideDelta) && m_pool.MarkStale(id))
        {
            stale[ns++] = id;
        }
    }
    counts.changed = int32_t(n);
    counts.stale = int32_t(ns);
    return counts;
}

void QuadtreeBroadPhase::TouchProxy(ProxyId id)
{
    if (m_pool.CheckLive(id, "TouchProxy"))
    {
        ApplyQueuedIfAny(); // keeps the move buffer in call order
        m_pool.Buffer(id);
    }
}

void QuadtreeBroadPhase::UpdateStaleEntries(Clock::time_point* now)
{
    if (m_stale.empty())
    {
        return;
    }
    const Clock::time_point start = now != nullptr ? *now : Clock::now();
    ++m_mutations;
    // Filtered in place (no second array): the live ones are handed to the pyramid. They stay flagged until their
    // entries are written, so that std::bad_alloc inside UpdateBatch leaves every one listed and flagged (each
    // change is all or nothing, and the next call writes the rest).
    size_t kept = 0;
    for (ProxyId id : m_stale)
    {
        if (m_pool.IsLive(id))
        {
            m_stale[kept++] = id;
        }
        else
        {
            m_pool.ClearStale(id);
        }
    }
    m_stale.resize(kept);
    m_counters.reinserts += m_pyramid.UpdateBatch(m_stale, m_pool.FatData()); // one thread: see UpdateBatch
    for (ProxyId id : m_stale)
    {
        m_pool.ClearStale(id);
    }
    m_stale.clear();
    NoteStale();
    const Clock::time_point end = Clock::now();
    m_counters.updateSeconds += std::chrono::duration<double>(end - start).count();
    if (now != nullptr)
    {
        *now = end;
    }
}

} // namespace quadphase
