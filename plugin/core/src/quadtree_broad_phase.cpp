#include "quadphase/quadtree_broad_phase.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <new>

#include "quadphase/box_simd.h"
#include "quadphase/error.h"

#include <omp.h>

namespace quadphase
{
namespace
{

using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// Reports non-finite and inverted boxes. The box is stored anyway: Pyramid places any box somewhere (NaN maps to
// cell 0), and Overlaps answers false for NaN, so a corrupted proxy gets no pairs and the others keep theirs.
__attribute__((noinline)) void ReportBadBox(const Box& b, const char* call, ProxyId id)
{
    if (!IsFinite(b))
    {
        ReportError(ErrorCode::NonFiniteBox, "%s: proxy %d got box (%g, %g)-(%g, %g)", call, int(id),
                    double(b.minX), double(b.minY), double(b.maxX), double(b.maxY));
    }
    else if (!IsOrdered(b))
    {
        ReportError(ErrorCode::InvertedBox, "%s: proxy %d got box (%g, %g)-(%g, %g) with min > max", call,
                    int(id), double(b.minX), double(b.minY), double(b.maxX), double(b.maxY));
    }
}

// Grows a vector's capacity to at least n, geometrically (a plain reserve(n) reallocates to exactly n each time).
template <typename T>
void ReserveAtLeast(std::vector<T>& v, size_t n)
{
    if (v.capacity() < n)
    {
        v.reserve(std::max(n, 2 * v.capacity()));
    }
}

// A vector whose first N elements live on the stack: Query and RayCast collect their candidates before calling
// back (re-entrancy), and a heap allocation per small query would cost as much as the query itself.
template <typename T, size_t N>
class SmallBuffer
{
public:
    size_t size() const { return m_size; }
    void clear()
    {
        m_size = 0;
        m_heap.clear();
    }
    void push_back(const T& value)
    {
        if (m_size < N)
        {
            m_local[m_size] = value;
        }
        else
        {
            m_heap.push_back(value);
        }
        ++m_size;
    }
    const T& operator[](size_t i) const { return i < N ? m_local[i] : m_heap[i - N]; }
    bool contains(const T& value) const
    {
        for (size_t i = 0; i < m_size; ++i)
        {
            if ((*this)[i] == value)
            {
                return true;
            }
        }
        return false;
    }

private:
    T m_local[N];
    size_t m_size = 0;
    std::vector<T> m_heap;
};

const Box kEmptyBox{0.0f, 0.0f, 0.0f, 0.0f};

// Percentile p (0..1) of values, reordering them.
float Percentile(std::vector<float>& values, double p)
{
    const size_t k = std::min(values.size() - 1, size_t(p * double(values.size() - 1) + 0.5));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

// The range of `values` without its far outliers: from the lo to the hi percentile, widened to the extreme values
// that lie within a tenth of that span beyond it. The percentiles keep a few bodies flung far away from stretching
// the grid; the widening keeps the dense edge of a distribution (bodies piled against a container's walls) inside,
// where the percentiles alone cut a strip of it off and clamp that strip into the border cells.
void RobustRange(std::vector<float>& values, double lo, double hi, float& low, float& high)
{
    const float a = Percentile(values, lo);
    const float b = Percentile(values, hi);
    const float margin = 0.1f * (b - a);
    low = a;
    high = b;
    for (float v : values)
    {
        if (v < low && v >= a - margin)
        {
            low = v;
        }
        if (v > high && v <= b + margin)
        {
            high = v;
        }
    }
}

} // namespace

void QuadtreeBroadPhase::CheckBox(const Box& b, const char* call, ProxyId id)
{
    // Once per proxy: a runaway body gets a bad box at every step, and one line says all there is to say.
    if (!IsSane(b) && m_pool.MarkBadReported(id))
    {
        ReportBadBox(b, call, id);
    }
}

QuadtreeBroadPhase::QuadtreeBroadPhase(const FatPolicy& policy, const Config& config)
    : m_policy(policy), m_config(config)
{
    Retune();
}

ProxyId QuadtreeBroadPhase::CreateProxy(const Box& tight, void* userData)
{
    ApplyQueuedIfAny(); // a re-tune below reads every fat box
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    const Box fat = FattenNew(m_policy, tight);
    ++m_mutations;
    // std::bad_alloc leaves no trace: the pool, the pyramid and the move buffer each reserve before they change,
    // and what succeeded is undone (without allocating) when a later step throws.
    m_pool.ReserveFree();
    const ProxyId id = m_pool.Allocate(fat, userData);
    try
    {
        m_pyramid.Insert(id, fat);
        try
        {
            m_pool.Buffer(id);
        }
        catch (...)
        {
            m_pyramid.Remove(id);
            throw;
        }
    }
    catch (...)
    {
        m_pool.Free(id);
        throw;
    }
    CheckBox(tight, "CreateProxy", id);
    if (m_pool.LiveCount() >= 2 * m_tunedCount && (m_config.depth < 0 || m_config.autoBounds))
    {
        // Re-tune while a scene is being built, so queries made before the first step are not all in one cell.
        // Doubling keeps the total rebuild work linear in the number of creations. The proxy exists from here:
        // a re-tune that runs out of memory is skipped (it is an optimisation; the next creation tries again).
        try
        {
            Retune();
        }
        catch (const std::bad_alloc&)
        {
        }
    }
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
    return id;
}

void QuadtreeBroadPhase::DestroyProxy(ProxyId id)
{
    if (!m_pool.CheckLive(id, "DestroyProxy"))
    {
        return;
    }
    ApplyQueuedIfAny(); // the id may be reused by the next CreateProxy: no queued move may outlive its proxy
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    ++m_mutations;
    m_pool.ReserveFree(); // the only allocation, before any change
    m_pyramid.Remove(id);
    m_pool.Free(id);
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
}

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

void QuadtreeBroadPhase::QueueMoveSlow(ProxyId id, const Box& tight, Vec2 displacement)
{
    if (!m_pool.CheckLive(id, "MoveProxy"))
    {
        return;
    }
    CheckBox(tight, "MoveProxy", id);
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    if (!m_pool.MarkPending(id))
    {
        // Moved twice before the queue was applied: the second move must see the first one's fat box.
        ApplyQueued();
        m_pool.MarkPending(id);
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
    m_queued[m_queuedCount++] = QueuedMove{tight, displacement, id};
    m_hasQueued.store(true, std::memory_order_release);
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

void QuadtreeBroadPhase::ApplyQueued(Clock::time_point* now)
{
    const int64_t count = int64_t(m_queuedCount);
    if (count == 0)
    {
        return;
    }
    // A caller that already read the clock hands its reading over and gets this call's end back: clock reads
    // (about 25 ns each) were a tenth of a step where almost nothing moves (tiles).
    const Clock::time_point start = now != nullptr ? *now : Clock::now();
    // One thread, the caller's: see docs/design.md ("Grid maintenance"). The moves were queued on this thread, so
    // the queue, the pending flags and (through the last queries) most fat boxes are in its cache; applying half of
    // them on a second core made that core fetch them and the next QueueMove calls fetch them back, which cost more
    // than the work saved (rain 64k, 2 threads: 0.4 ms more per step outside FindPairs).
    // Everything this call allocates is reserved here, before any change: std::bad_alloc leaves the queue as it was.
    ReserveAtLeast(m_applyLists.stale, size_t(count));
    ReserveAtLeast(m_applyLists.buffered, size_t(count));
    ReserveAtLeast(m_stale, m_stale.size() + size_t(count));
    m_pool.ReserveBuffer(size_t(count));
    ++m_mutations;
    // Two passes over the queue:
    // 1. the fat-box tests, without a branch on the outcome (RefattenSimd, and an append that always writes and
    //    advances by the outcome): whether a body keeps its fat box is close to random, and the mispredictions
    //    cost more than the test;
    // 2. each new fat box is written into the proxy's cell entry when it stays in its cell (most do: a fat box is
    //    smaller than a cell); the others are flagged and listed stale and wait for UpdateStaleEntries. Every
    //    proxy with a new fat box is flagged and listed for the move buffer.
    // Everything the loops read in locals: through members (or the pool) the compiler reloaded the policy, the
    // arrays and the constants built from them after every flag store, since a char store may alias anything
    // (tiles: 70 instructions per move, half of them such reloads).
    const QueuedMove* const moves = m_queued.data();
    Box* const boxes = m_pool.MutableFatData();
    uint8_t* const state = m_pool.MutableStateData();
    const FatPolicy policy = m_policy;
    const BoxMirror mirror = m_mirror;
    std::vector<ProxyId>& buffered = m_applyLists.buffered;
    std::vector<ProxyId>& stale = m_applyLists.stale;
    buffered.resize(size_t(count)); // within the capacity reserved above: no allocation here
    int32_t* const out = buffered.data();
    size_t n = 0;
    for (int64_t i = 0; i < count; ++i)
    {
        const QueuedMove& move = moves[i];
        state[size_t(move.id)] &= ProxyPool::kClearPendingMask;
        out[n] = int32_t(i);
        n += RefattenSimd(policy, boxes[move.id], move.tight, move.displacement) ? 1 : 0;
    }
    stale.resize(n);
    int32_t outsideDelta = 0;
    size_t nb = 0;
    size_t ns = 0;
    for (size_t k = 0; k < n; ++k)
    {
        const ProxyId id = moves[out[k]].id; // read before out[nb] (nb <= k) is written
        if (mirror.Enabled())
        {
            mirror.Write(id, boxes[id]);
        }
        if (!m_pyramid.RewriteInPlace(id, boxes[id], outsideDelta) && m_pool.MarkStale(id))
        {
            stale[ns++] = id;
        }
        out[nb] = id;
        nb += m_pool.MarkBuffered(id) ? 1 : 0;
    }
    buffered.resize(nb);
    stale.resize(ns);
    m_pyramid.AddOutsideDelta(outsideDelta);
    // In queue order, so the stale list and the move buffer are the ones MoveProxy calls would have built (less
    // the proxies already re-placed in their cell).
    m_stale.insert(m_stale.end(), stale.begin(), stale.end());
    m_pool.AppendBuffered(buffered);
    stale.clear();
    buffered.clear();
    m_queuedCount = 0;
    m_hasQueued.store(false, std::memory_order_release);
    if (m_queued.size() > 2 * QueueLimit())
    {
        // The world shrank: so does the queue (and the lists sized from it).
        std::vector<QueuedMove>(QueueLimit()).swap(m_queued);
        UpdateFastRoom();
        m_applyLists = ApplyLists{};
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

void QuadtreeBroadPhase::TouchProxy(ProxyId id)
{
    if (m_pool.CheckLive(id, "TouchProxy"))
    {
        ApplyQueuedIfAny(); // keeps the move buffer in call order
        m_pool.Buffer(id);
    }
}

const Box& QuadtreeBroadPhase::GetFatBox(ProxyId id) const
{
    ApplyQueuedIfAny();
    return m_pool.CheckLive(id, "GetFatAABB") ? m_pool.Fat(id) : kEmptyBox;
}

void* QuadtreeBroadPhase::GetUserData(ProxyId id) const
{
    return m_pool.IsLive(id) ? m_pool.UserData(id) : nullptr;
}

bool QuadtreeBroadPhase::TestOverlap(ProxyId a, ProxyId b) const
{
    if (!m_pool.CheckLive(a, "TestOverlap") || !m_pool.CheckLive(b, "TestOverlap"))
    {
        return false;
    }
    ApplyQueuedIfAny();
    return Overlaps(m_pool.Fat(a), m_pool.Fat(b));
}

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
    // Below the threshold no parallel region can open (neither the queue's apply nor the search), so OpenMP is
    // not asked (omp_get_max_threads is a call into libgomp; most of Box2D's calls, after time-of-impact events
    // and on quiet scenes, are this small).
    int threads = work >= int64_t(m_config.parallelThreshold) ? Threads() : 1;
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
    ApplyQueued(&now);
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
        m_pool.UnlendWork(m_work);
        throw;
    }
    const int64_t queried = int64_t(m_work.size());
    m_pool.ReturnWork(m_work);

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

int QuadtreeBroadPhase::Threads() const
{
    return m_config.threads > 0 ? m_config.threads : omp_get_max_threads();
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

// The buffered proxies are cut into fixed blocks of kBlock queries, whatever the thread count. Each block writes
// only its own vector, with no lock; the vectors are then joined in block order. The output is therefore the
// serial loop's output, pair for pair and in the same order, at any thread count and under any schedule. During
// the parallel loop the pyramid and the pool are only read.
void QuadtreeBroadPhase::FindPairsParallel(std::vector<Pair>& out, int threads)
{
    constexpr int64_t kBlock = 64;
    const int64_t count = int64_t(m_work.size());
    const int64_t blocks = (count + kBlock - 1) / kBlock;
    if (int64_t(m_blockPairs.size()) < blocks)
    {
        m_blockPairs.resize(size_t(blocks));
    }

    omp_sched_t previousKind;
    int previousChunk;
    omp_get_schedule(&previousKind, &previousChunk);
    static constexpr omp_sched_t kKinds[] = {omp_sched_static, omp_sched_dynamic, omp_sched_guided,
                                             omp_sched_auto};
    omp_set_schedule(kKinds[int(m_config.schedule)], m_config.chunk);

    // A block's pair list may grow, and an exception must not leave the region (that ends the program): the first
    // one is kept and thrown again after the region, on the caller's thread.
    std::exception_ptr error;
    std::atomic<bool> failed{false};
#pragma omp parallel for schedule(runtime) num_threads(threads)
    for (int64_t b = 0; b < blocks; ++b)
    {
        if (failed.load(std::memory_order_relaxed))
        {
            continue;
        }
        try
        {
            std::vector<Pair>& pairs = m_blockPairs[size_t(b)];
            pairs.clear();
            const int64_t end = std::min(count, (b + 1) * kBlock);
            for (int64_t i = b * kBlock; i < end; ++i)
            {
                QueryPairsOf(m_work[size_t(i)], pairs);
            }
        }
        catch (...)
        {
#pragma omp critical(quadphase_find_pairs_error)
            {
                if (!error)
                {
                    error = std::current_exception();
                }
            }
            failed.store(true, std::memory_order_relaxed);
        }
    }

    omp_set_schedule(previousKind, previousChunk); // the schedule ICV belongs to the caller's thread
    if (error)
    {
        std::rethrow_exception(error);
    }
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

void QuadtreeBroadPhase::Query(const Box& box, QueryFn fn, void* context) const
{
    ApplyForRead(); // no stale entry from here to the first callback
    // Every candidate is collected before the first callback, so a callback may change the pyramid and the pool
    // (create, destroy, move, even rebuild) without this loop reading what it changed.
    SmallBuffer<ProxyId, 64> hits;
    const PreparedBox prepared = Prepare(box);
    m_pyramid.Visit(box, [&](const Entry& e) {
        if (OverlapsPrepared(e.box, prepared))
        {
            hits.push_back(e.id);
        }
        return true;
    });
    const uint64_t collected = m_mutations;
    for (size_t i = 0; i < hits.size(); ++i)
    {
        const ProxyId id = hits[i];
        // A callback's QueueMove (b2BroadPhase::MoveProxy) changes no fat box until the queue is applied: apply it
        // now, so that the test below sees where a moved proxy is (one atomic load when nothing is queued).
        ApplyQueuedIfAny();
        // After a callback changed something, a candidate is reported only while it is live and its current box
        // still overlaps: a destroyed proxy is never reported after its destruction (its id may even have been
        // reused), and a moved one is reported only where it now is.
        if (m_mutations != collected && !(m_pool.IsLive(id) && Overlaps(m_pool.Fat(id), box)))
        {
            continue;
        }
        if (!fn(context, id))
        {
            return;
        }
    }
}

namespace
{

// The cells a segment's proxies can live in, level by level: see QuadtreeBroadPhase::RayCast and docs/design.md
// ("Ray casts"). Works in deepest-level cell units ("leaf units"), in double.
class RayWalk
{
public:
    RayWalk(const Pyramid& pyramid, const RayInput& input)
    {
        const double invLeaf = double(pyramid.InvLeaf());
        const double ox = double(pyramid.OriginX());
        const double oy = double(pyramid.OriginY());
        m_u0 = (double(input.p1.x) - ox) * invLeaf;
        m_v0 = (double(input.p1.y) - oy) * invLeaf;
        m_du = (double(input.p2.x) - double(input.p1.x)) * invLeaf;
        m_dv = (double(input.p2.y) - double(input.p1.y)) * invLeaf;
        m_invDv = m_dv != 0.0 ? 1.0 / m_dv : 0.0;
        m_max = double(pyramid.MaxCoord());
        m_depth = pyramid.Depth();
        // Slack for float rounding, in leaf units. The proxies' cells come from float coordinates and the segment
        // test (SegmentTest::MayCross) runs in float, so a box the exact segment misses by a few ulps may still
        // pass it; such a box must lie in a walked cell. Errors there are a few ulps (2^-23 relative) of the
        // magnitudes involved; 2^-19 of their sum, plus a thousandth of a cell, is a wide margin.
        const double magnitude = std::fabs(ox) + std::fabs(oy) +
                                 2.0 * double(pyramid.Bounds().maxX - pyramid.Bounds().minX) +
                                 std::fabs(double(input.p1.x)) + std::fabs(double(input.p1.y)) +
                                 std::fabs(double(input.p2.x)) + std::fabs(double(input.p2.y));
        m_eps = 1e-3 + magnitude * invLeaf * (1.0 / 524288.0);
        // Beyond 1e18 the float arithmetic of SegmentTest overflows (the segment's squared length is infinite, its
        // normal becomes zero, and every box its bounding box touches passes MayCross, as in stock's tree): only
        // the bounding box then finds every candidate.
        const float kMaxCoord = 1e18f;
        const bool moderate = std::fabs(input.p1.x) <= kMaxCoord && std::fabs(input.p1.y) <= kMaxCoord &&
                              std::fabs(input.p2.x) <= kMaxCoord && std::fabs(input.p2.y) <= kMaxCoord;
        m_valid = moderate && std::isfinite(m_u0) && std::isfinite(m_v0) && std::isfinite(m_du) &&
                  std::isfinite(m_dv) && std::isfinite(m_eps) && (m_du != 0.0 || m_dv != 0.0);
    }

    /// False for segments the walk cannot follow (non-finite, zero length, coordinates beyond 1e18): use the
    /// bounding box instead.
    bool Valid() const { return m_valid; }

    /// Cells the walk of `level` reads, about, up to fraction t.
    int64_t Cost(int level, double t) const
    {
        const double cs = CellSize(level);
        const double w = std::fabs(Clamp(m_u0 + t * m_du) - Clamp(m_u0)) / cs;
        const double z = std::fabs(Clamp(m_v0 + t * m_dv) - Clamp(m_v0)) / cs;
        return int64_t(std::min(2.0 * w + 3.0 * z + 9.0, 4e18));
    }

    /// Stored rows of `level` in the ray's direction: from First(level) to Last(level, t) (inclusive), stepping by
    /// Step(). Last moves toward First as the segment is clipped.
    int32_t First(int level) const
    {
        const double z = Clamp(m_v0) / CellSize(level);
        const double e = Slack(level);
        return ClampRow(level, m_dv >= 0.0 ? Floor(z - e) - 1 : Floor(z + e));
    }
    int32_t Last(int level, double t) const
    {
        const double z = Clamp(m_v0 + t * m_dv) / CellSize(level);
        const double e = Slack(level);
        return ClampRow(level, m_dv >= 0.0 ? Floor(z + e) : Floor(z - e) - 1);
    }
    int32_t Step() const { return m_dv >= 0.0 ? 1 : -1; }

    /// The columns [x0, x1] of stored row r of `level` whose proxies the segment up to fraction t may reach; false
    /// when there are none. A proxy stored in cell (cx, cy) lies, in clamped coordinates, within cells cx..cx+1 and
    /// cy..cy+1 (Pyramid's placement rule), so row r's proxies are reached only by points of the segment whose
    /// clamped row is r or r + 1; their columns, less one, bound the stored columns.
    bool Columns(int level, int32_t r, double t, int32_t& x0, int32_t& x1) const
    {
        const double cs = CellSize(level);
        const double invCs = 1.0 / cs; // exact: a power of two
        const double e = Slack(level) * cs;
        const double inf = std::numeric_limits<double>::infinity();
        // The band of unclamped v whose clamped value lies in rows [r, r + 2), widened by the slack.
        const double vLo = double(r) * cs - e <= 0.0 ? -inf : double(r) * cs - e;
        const double vHi = double(r + 2) * cs + e >= m_max ? inf : double(r + 2) * cs + e;
        double ta = 0.0;
        double tb = t;
        if (m_dv != 0.0)
        {
            // By the inverse, not a division per row: a few ulps of t, far inside the slack.
            double t1 = (vLo - m_v0) * m_invDv;
            double t2 = (vHi - m_v0) * m_invDv;
            if (t1 > t2)
            {
                std::swap(t1, t2);
            }
            ta = std::max(ta, t1);
            tb = std::min(tb, t2);
        }
        else if (!(vLo <= m_v0 && m_v0 <= vHi))
        {
            return false;
        }
        if (!(ta <= tb))
        {
            return false;
        }
        const double ua = m_u0 + ta * m_du;
        const double ub = m_u0 + tb * m_du;
        const int32_t side = LevelSide(level);
        x0 = std::max(0, Floor(Clamp(std::min(ua, ub) - e) * invCs) - 1);
        x1 = std::min(side - 1, Floor(Clamp(std::max(ua, ub) + e) * invCs));
        return x0 <= x1;
    }

    /// True when the ray runs toward smaller x (columns are then walked from x1 down to x0).
    bool Backward() const { return m_du < 0.0; }

private:
    double CellSize(int level) const { return double(int64_t(1) << (m_depth - level)); }
    // Slack in cells of `level`: the leaf-unit slack, plus 2^-16 of a cell for the division by the cell size.
    double Slack(int level) const { return m_eps / CellSize(level) + (1.0 / 65536.0); }
    double Clamp(double u) const { return u < 0.0 ? 0.0 : (u > m_max ? m_max : u); }
    // floor() clamped to +-1e9, without libm's floor (a call on baseline x86-64, which has no roundsd; it was a
    // tenth of a long ray's walk): truncation, minus one for negative non-integers.
    static int32_t Floor(double x)
    {
        if (!(x > -1e9))
        {
            return -1000000000;
        }
        if (!(x < 1e9))
        {
            return 1000000000;
        }
        const int32_t i = int32_t(x);
        return double(i) > x ? i - 1 : i;
    }
    static int32_t ClampRow(int level, int32_t r) { return std::max(0, std::min(LevelSide(level) - 1, r)); }

    double m_u0 = 0.0, m_v0 = 0.0, m_du = 0.0, m_dv = 0.0, m_invDv = 0.0, m_max = 0.0, m_eps = 0.0;
    int m_depth = 0;
    bool m_valid = false;
};

} // namespace

void QuadtreeBroadPhase::RayCast(const RayInput& input, RayCastFn fn, void* context) const
{
    ApplyForRead(); // no stale entry from here to the first callback
    SegmentTest segment(input);
    // Candidates are collected a batch at a time (a row of cells, or a level) and reported after the batch is
    // complete, so a callback may change the pyramid and the pool without the walk reading what it changed: cells
    // are read again by index, after the callbacks, for the next batch.
    SmallBuffer<Entry, 32> batch;
    SmallBuffer<ProxyId, 32> reported; // ids reported by this call, to report none twice after a change
    const uint64_t startMutations = m_mutations;
    bool restarted = false;
    // Reports the batch in order; false when the caller ended the ray cast.
    auto reportBatch = [&](uint64_t collected) {
        for (size_t i = 0; i < batch.size(); ++i)
        {
            const Entry& e = batch[i];
            ApplyQueuedIfAny(); // a callback's QueueMove: see Query
            // A callback's move leaves the proxy's entry stale (old box) until the next FindPairs or query, and a
            // batch collected after that callback holds the stale box: test the pool's box then.
            if (m_mutations == collected && !m_pool.IsStale(e.id))
            {
                // the segment may have been clipped since the entry was collected
                if (!segment.MayCross(e.box))
                {
                    continue;
                }
            }
            else if (!(m_pool.IsLive(e.id) && segment.MayCross(m_pool.Fat(e.id))))
            {
                continue; // destroyed (its id may have been reused) or moved away by a callback
            }
            // Without a change since the call began, each entry is collected once: no id can come twice.
            if (restarted || m_mutations != startMutations)
            {
                if (reported.contains(e.id))
                {
                    continue;
                }
            }
            reported.push_back(e.id);
            const RayInput sub{input.p1, input.p2, segment.MaxFraction()};
            const float value = fn(context, sub, e.id);
            if (value == 0.0f)
            {
                return false;
            }
            if (value > 0.0f)
            {
                segment.Clip(value);
            }
        }
        batch.clear();
        return true;
    };
    auto collect = [&](const Entry& e) {
        if (segment.MayCross(e.box))
        {
            batch.push_back(e);
        }
        return true;
    };
    for (int restarts = 0; restarts <= 64; ++restarts)
    {
        const uint64_t version = m_pyramid.Version();
        const RayWalk walk(m_pyramid, input);
        bool changed = false;
        for (int level = 0; level <= m_pyramid.Depth() && !changed; ++level)
        {
            if (m_pyramid.LevelCount(level) == 0)
            {
                continue;
            }
            const double t = double(segment.MaxFraction());
            // The walk reads a subset of the cells of the segment's bounding box, in the ray's order, so it is
            // chosen unless the level holds fewer proxies than the cells it would read (then the level's list,
            // through VisitLevel, reads less). Axis-aligned rays walk too: through the bounding box, a horizontal
            // closest-hit ray read its whole row before the first clip (0.73x stock on 200 rays over 1 km).
            if (walk.Valid() && walk.Cost(level, t) < int64_t(m_pyramid.LevelCount(level)))
            {
                // Row by row along the ray; each row's cells in the ray's direction, a cell at a time, so that a
                // clipped segment ends the row (and the level) at the cell where it now ends.
                const bool backward = walk.Backward();
                for (int32_t r = walk.First(level);; r += walk.Step())
                {
                    double tNow = double(segment.MaxFraction());
                    const int32_t last = walk.Last(level, tNow);
                    if (walk.Step() > 0 ? r > last : r < last)
                    {
                        break;
                    }
                    int32_t x0, x1;
                    if (!walk.Columns(level, r, tNow, x0, x1))
                    {
                        continue;
                    }
                    for (int32_t x = backward ? x1 : x0; backward ? x >= x0 : x <= x1; x += backward ? -1 : 1)
                    {
                        const uint64_t collected = m_mutations;
                        int32_t count;
                        const Entry* entries = m_pyramid.CellEntries(level, x, r, count);
                        for (int32_t i = 0; i < count; ++i)
                        {
                            collect(entries[i]);
                        }
                        if (batch.size() == 0)
                        {
                            continue;
                        }
                        if (!reportBatch(collected))
                        {
                            return;
                        }
                        if (m_pyramid.Version() != version)
                        {
                            changed = true;
                            break;
                        }
                        const double tClipped = double(segment.MaxFraction());
                        if (tClipped < tNow)
                        {
                            // The far end of the row moves toward the start; the columns behind stay visited.
                            tNow = tClipped;
                            int32_t nx0, nx1;
                            if (!walk.Columns(level, r, tNow, nx0, nx1))
                            {
                                break;
                            }
                            x0 = backward ? std::max(x0, nx0) : x0;
                            x1 = backward ? x1 : std::min(x1, nx1);
                        }
                    }
                    if (changed)
                    {
                        break;
                    }
                }
            }
            else
            {
                const uint64_t collected = m_mutations;
                m_pyramid.VisitLevel(level, segment.Bounds(), collect);
                if (!reportBatch(collected))
                {
                    return;
                }
                changed = m_pyramid.Version() != version;
            }
        }
        if (!changed)
        {
            return;
        }
        // A callback rebuilt the pyramid: walk the new one from the root, with the clipped segment, skipping the
        // ids already reported.
        restarted = true;
    }
}

void QuadtreeBroadPhase::ShiftOrigin(Vec2 newOrigin)
{
    ApplyQueuedIfAny(); // queued boxes are in the old frame
    // The world moved, so the region it lives in moves with it. The shifted pyramid is built first (the only
    // step that allocates), then everything is shifted: std::bad_alloc leaves the old frame intact.
    const Box bounds = m_pyramid.Bounds();
    Pyramid built = BuildPyramid(bounds.minX - newOrigin.x, bounds.minY - newOrigin.y,
                                 bounds.maxX - bounds.minX, m_pyramid.Depth(), newOrigin);
    // the same subtraction as BuildPyramid's, so entries and pool agree bit for bit
    m_pool.ShiftOrigin(newOrigin);
    WriteMirrorOfAll();
    m_config.bounds.minX -= newOrigin.x;
    m_config.bounds.minY -= newOrigin.y;
    m_config.bounds.maxX -= newOrigin.x;
    m_config.bounds.maxY -= newOrigin.y;
    CommitRebuild(std::move(built));
}

void QuadtreeBroadPhase::SetBoxMirror(const BoxMirror& mirror)
{
    ApplyQueuedIfAny(); // the records must hold the fat boxes the calls made so far define
    m_mirror = mirror;
    WriteMirrorOfAll();
}

void QuadtreeBroadPhase::WriteMirrorOfAll()
{
    if (!m_mirror.Enabled())
    {
        return;
    }
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsLive(id))
        {
            m_mirror.Write(id, m_pool.Fat(id));
        }
    }
}

void QuadtreeBroadPhase::Configure(const Config& config)
{
    ApplyQueuedIfAny();
    const Config previous = m_config;
    m_config = config;
    try
    {
        Retune();
    }
    catch (...)
    {
        m_config = previous; // all or nothing
        throw;
    }
}

bool QuadtreeBroadPhase::NeedsRetune() const
{
    if (m_config.depth >= 0 && !m_config.autoBounds)
    {
        return false;
    }
    const int32_t n = m_pool.LiveCount();
    if ((n > 0 && n >= 2 * m_tunedCount) || (m_tunedCount > 64 && 4 * n < m_tunedCount))
    {
        return true;
    }
    // Counted from the last tuning: when retuning cannot bring proxies inside (boxes larger than the region the
    // centres span), the same retune would otherwise run again on every FindPairs.
    return m_config.autoBounds && n > 32 && m_pyramid.OutsideCount() - m_tunedOutside > n / 4;
}

// The automatic rule (docs/design.md, "Automatic depth and bounds"):
// - bounds: the box holding the centres of the proxies' fat boxes, from the 1st to the 99th percentile on each
//   axis when there are at least 200 proxies (so a few far-away bodies do not stretch the grid) widened to the
//   centres within a tenth of that span beyond it (RobustRange), grown on every side by the median fat-box extent,
//   made square around its centre;
// - depth: the smallest depth whose leaf side is at most cellToProxyRatio x the median fat-box extent, capped so
//   that the deepest level has at most 2 cells per proxy (4^depth <= 2 n) and by maxDepth.
void QuadtreeBroadPhase::Retune()
{
    const int32_t n = m_pool.LiveCount();
    std::vector<float> cx, cy, extent;
    cx.reserve(size_t(n));
    cy.reserve(size_t(n));
    extent.reserve(size_t(n));
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (!m_pool.IsLive(id))
        {
            continue;
        }
        const Box& b = m_pool.Fat(id);
        if (!IsFinite(b) || !IsOrdered(b))
        {
            continue;
        }
        cx.push_back(0.5f * b.minX + 0.5f * b.maxX);
        cy.push_back(0.5f * b.minY + 0.5f * b.maxY);
        extent.push_back(std::max(b.maxX - b.minX, b.maxY - b.minY));
    }

    float originX, originY, side;
    float medianExtent = extent.empty() ? 1.0f : Percentile(extent, 0.5);
    if (!(medianExtent > 0.0f) || !std::isfinite(medianExtent))
    {
        medianExtent = 1.0f;
    }
    if (m_config.autoBounds)
    {
        if (cx.empty())
        {
            originX = m_config.bounds.minX;
            originY = m_config.bounds.minY;
            side = std::max(m_config.bounds.maxX - m_config.bounds.minX,
                            m_config.bounds.maxY - m_config.bounds.minY);
        }
        else
        {
            const double lo = cx.size() >= 200 ? 0.01 : 0.0;
            const double hi = cx.size() >= 200 ? 0.99 : 1.0;
            float x0, x1, y0, y1;
            RobustRange(cx, lo, hi, x0, x1);
            RobustRange(cy, lo, hi, y0, y1);
            // Made square around the centre of the percentile box, not from its lower corner: the extra room goes
            // to both sides of the shorter axis, where bodies are as likely to go (rain: the container below the
            // spawn rows was outside bounds that grew upward only, and the bodies piling in it crowded the border).
            side = std::max(x1 - x0, y1 - y0) + 2.0f * medianExtent;
            originX = 0.5f * x0 + 0.5f * x1 - 0.5f * side;
            originY = 0.5f * y0 + 0.5f * y1 - 0.5f * side;
        }
    }
    else
    {
        originX = m_config.bounds.minX;
        originY = m_config.bounds.minY;
        side = std::max(m_config.bounds.maxX - m_config.bounds.minX,
                        m_config.bounds.maxY - m_config.bounds.minY);
    }
    if (!(side > 0.0f) || !std::isfinite(side))
    {
        side = 1.0f;
    }

    int depth;
    if (m_config.depth >= 0)
    {
        depth = std::min(m_config.depth, kMaxDepth);
    }
    else
    {
        const float target = m_config.cellToProxyRatio * medianExtent;
        // Clamped before the conversion: a ratio <= 0 gives +inf (finest allowed) or NaN (0), and converting
        // either to int is undefined.
        const double want = std::ceil(std::log2(double(side) / double(target)));
        depth = want > 0.0 ? (want < double(kMaxDepth) ? int(want) : kMaxDepth) : 0;
        // 4^depth <= 2n  <=>  depth <= log2(2n) / 2
        const int memoryCap = int(std::floor(std::log2(2.0 * std::max(n, 1)) / 2.0));
        depth = std::max(0, std::min({depth, memoryCap, std::min(m_config.maxDepth, kMaxDepth)}));
    }
    m_tunedCount = n;
    Rebuild(originX, originY, side, depth);
    m_tunedOutside = m_pyramid.OutsideCount();
}

Pyramid QuadtreeBroadPhase::BuildPyramid(float originX, float originY, float side, int depth,
                                         Vec2 shift) const
{
    // Built beside the current pyramid and swapped in by CommitRebuild: std::bad_alloc half way leaves the current
    // one intact (the price is both in memory at once, for the length of a rebuild).
    Pyramid built;
    built.Reset(originX, originY, side, depth);
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsLive(id))
        {
            const Box& b = m_pool.Fat(id);
            built.Insert(id, Box{b.minX - shift.x, b.minY - shift.y, b.maxX - shift.x, b.maxY - shift.y});
        }
    }
    built.Compact(); // cells in row-major order in memory: neighbouring cells are read together
    return built;
}

void QuadtreeBroadPhase::Rebuild(float originX, float originY, float side, int depth)
{
    CommitRebuild(BuildPyramid(originX, originY, side, depth, Vec2{0.0f, 0.0f}));
}

void QuadtreeBroadPhase::CommitRebuild(Pyramid&& built)
{
    m_pyramid.ReplaceWith(std::move(built));
    // Every entry was just written from the current boxes.
    for (ProxyId id : m_stale)
    {
        m_pool.ClearStale(id);
    }
    m_stale.clear();
    NoteStale();
    ++m_mutations;
    m_counters.rebuilds += 1;
}

Stats QuadtreeBroadPhase::GetStats() const
{
    // Const calls on other threads may be applying queued moves (under this lock), which writes the counters,
    // the per-thread lists and the pyramid.
    std::lock_guard<std::mutex> lock(m_queueMutex);
    Stats s = m_counters;
    s.depth = m_pyramid.Depth();
    s.bounds = m_pyramid.Bounds();
    s.leafSize = m_pyramid.LeafSize();
    s.proxyCount = m_pool.LiveCount();
    s.outsideCount = m_pyramid.OutsideCount();
    m_pyramid.CountOccupancy(s.occupiedCells, s.largestCell);
    s.proxiesPerLevel.resize(size_t(s.depth + 1));
    for (int level = 0; level <= s.depth; ++level)
    {
        s.proxiesPerLevel[size_t(level)] = m_pyramid.LevelCount(level);
    }
    // Every heap byte held, working buffers included (their capacity, not their size).
    s.memoryBytes =
        m_pool.MemoryBytes() + m_pyramid.MemoryBytes() +
        int64_t((m_work.capacity() + m_stale.capacity()) * sizeof(ProxyId)) +
        int64_t(m_queued.capacity() * sizeof(QueuedMove)) +
        int64_t(m_blockPairs.capacity() * sizeof(std::vector<Pair>)) +
        int64_t((m_applyLists.stale.capacity() + m_applyLists.buffered.capacity()) * sizeof(ProxyId));
    for (const std::vector<Pair>& pairs : m_blockPairs)
    {
        s.memoryBytes += int64_t(pairs.capacity() * sizeof(Pair));
    }
    return s;
}

void QuadtreeBroadPhase::ResetCounters()
{
    const int64_t rebuilds = m_counters.rebuilds;
    m_counters = Stats{};
    m_counters.rebuilds = rebuilds;
}

std::string QuadtreeBroadPhase::Validate() const
{
    ApplyQueuedIfAny();
    std::string problem = m_pool.Validate();
    if (!problem.empty())
    {
        return "pool: " + problem;
    }
    // Applied above: no move is queued, and no proxy is flagged as having one.
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsPending(id))
        {
            return "proxy " + std::to_string(id) +
                   " is flagged with a queued move after the queue was applied";
        }
    }
    problem = m_pyramid.Validate();
    if (!problem.empty())
    {
        return "pyramid: " + problem;
    }
    int32_t stored = 0;
    for (int level = 0; level <= m_pyramid.Depth(); ++level)
    {
        stored += m_pyramid.LevelCount(level);
    }
    if (stored != m_pool.LiveCount())
    {
        return "pyramid stores " + std::to_string(stored) + " proxies but " +
               std::to_string(m_pool.LiveCount()) + " are live";
    }
    // A proxy is flagged stale exactly when it is in the stale list, once.
    std::vector<uint8_t> listed(size_t(m_pool.IdBound()), 0);
    for (ProxyId id : m_stale)
    {
        if (id < 0 || id >= m_pool.IdBound() || listed[size_t(id)]++ != 0 || !m_pool.IsStale(id))
        {
            return "stale list entry " + std::to_string(id) +
                   " is out of range, repeated or not flagged stale";
        }
    }
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsStale(id) && listed[size_t(id)] == 0)
        {
            return "proxy " + std::to_string(id) + " is flagged stale but not in the stale list";
        }
    }
    // With a mirror, every live proxy below its capacity has its fat box in its record, bit for bit.
    if (m_mirror.Enabled())
    {
        for (ProxyId id = 0; id < std::min(m_pool.IdBound(), m_mirror.capacity); ++id)
        {
            const Box copy = m_mirror.Read(id);
            if (m_pool.IsLive(id) && std::memcmp(&copy, &m_pool.Fat(id), sizeof copy) != 0) // NaN included
            {
                return "proxy " + std::to_string(id) + "'s mirror record differs from its fat box";
            }
        }
    }
    // Every live proxy that is not stale is stored with its fat box: found through a query of its own box.
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (!m_pool.IsLive(id) || m_pool.IsStale(id))
        {
            continue;
        }
        bool found = false;
        const Box& fat = m_pool.Fat(id);
        // An inverted box (bad input, reported) is stored in the cell of its min corner, but a query of the box
        // itself may cover no cell at all: query that corner instead. The same holds for boxes holding NaN.
        const Box probe = IsOrdered(fat) ? fat : Box{fat.minX, fat.minY, fat.minX, fat.minY};
        m_pyramid.Visit(probe, [&](const Entry& e) {
            if (e.id == id)
            {
                found = SameBits(e.box, fat) || !IsFinite(fat);
                return false;
            }
            return true;
        });
        if (!found)
        {
            return "proxy " + std::to_string(id) + " is not found by a query of its own fat box";
        }
    }
    return {};
}

} // namespace quadphase
