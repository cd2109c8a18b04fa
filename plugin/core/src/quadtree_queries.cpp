// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase's queries: Query (a box) and RayCast (a segment walked cell by cell along the ray), both safe
// against callbacks that change the broadphase.
#include "quadtree_broad_phase.h"

#include <algorithm>
#include <vector>

#include "box_simd.h"
#include "ray_walk.h"

namespace quadphase
{
namespace
{

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

} // namespace

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

// One RayCast call: the clipped segment, the batch being collected and the ids reported. See RayCast for the order
// of the walk and its re-entrancy guarantees. Candidates are collected a batch at a time (a cell, or a level) and
// reported after the batch is complete, so a callback may change the pyramid and the pool without the walk reading
// what it changed: cells are read again by index, after the callbacks, for the next batch.
class QuadtreeBroadPhase::RayCaster
{
public:
    RayCaster(const QuadtreeBroadPhase& owner, const RayInput& input, RayCastFn fn, void* context)
        : m_owner(owner), m_input(input), m_fn(fn), m_context(context), m_segment(input),
          m_startMutations(owner.m_mutations)
    {
    }

    // Walks the pyramid from the root; when a callback rebuilds it, walks the new one, up to 64 times.
    void Run()
    {
        for (int restarts = 0; restarts <= 64; ++restarts)
        {
            if (WalkPyramid() != Outcome::kRebuilt)
            {
                return;
            }
            // A callback rebuilt the pyramid: walk the new one from the root, with the clipped segment, skipping
            // the ids already reported.
            m_restarted = true;
        }
    }

private:
    enum class Outcome
    {
        kGoOn,    // this part of the walk is done; go on with the next
        kStopped, // a callback ended the ray cast (returned 0)
        kRebuilt, // a callback rebuilt the pyramid: start again from the root
    };

    Outcome WalkPyramid()
    {
        const Pyramid& pyramid = m_owner.m_pyramid;
        const uint64_t version = pyramid.Version();
        const detail::RayWalk walk(pyramid, m_input);
        for (int level = 0; level <= pyramid.Depth(); ++level)
        {
            if (pyramid.LevelCount(level) == 0)
            {
                continue;
            }
            const double t = double(m_segment.MaxFraction());
            // The walk reads a subset of the cells of the segment's bounding box, in the ray's order, so it is
            // chosen unless the level holds fewer proxies than the cells it would read (then the level's list,
            // through VisitLevel, reads less). Axis-aligned rays walk too: through the bounding box, a horizontal
            // closest-hit ray reads its whole row before the first clip.
            const Outcome outcome = walk.Valid() && walk.Cost(level, t) < int64_t(pyramid.LevelCount(level))
                                        ? WalkLevel(walk, level, version)
                                        : ScanLevel(level, version);
            if (outcome != Outcome::kGoOn)
            {
                return outcome;
            }
        }
        return Outcome::kGoOn;
    }

    // Row by row along the ray, from the first row to the last one the (clipped) segment reaches.
    Outcome WalkLevel(const detail::RayWalk& walk, int level, uint64_t version)
    {
        for (int32_t r = walk.First(level);; r += walk.Step())
        {
            const double tNow = double(m_segment.MaxFraction());
            const int32_t last = walk.Last(level, tNow);
            if (walk.Step() > 0 ? r > last : r < last)
            {
                return Outcome::kGoOn;
            }
            int32_t x0, x1;
            if (!walk.Columns(level, r, tNow, x0, x1))
            {
                continue;
            }
            const Outcome outcome = WalkRow(walk, level, r, tNow, x0, x1, version);
            if (outcome != Outcome::kGoOn)
            {
                return outcome;
            }
        }
    }

    // The columns [x0, x1] of row r in the ray's direction, a cell at a time, so that a clipped segment ends the
    // row at the cell where it now ends.
    Outcome WalkRow(const detail::RayWalk& walk, int level, int32_t r, double tNow, int32_t x0, int32_t x1,
                    uint64_t version)
    {
        const bool backward = walk.Backward();
        for (int32_t x = backward ? x1 : x0; backward ? x >= x0 : x <= x1; x += backward ? -1 : 1)
        {
            const Outcome outcome = VisitCell(level, x, r, version);
            if (outcome != Outcome::kGoOn)
            {
                return outcome;
            }
            const double tClipped = double(m_segment.MaxFraction());
            if (tClipped < tNow)
            {
                // The far end of the row moves toward the start; the columns behind stay visited.
                tNow = tClipped;
                int32_t nx0, nx1;
                if (!walk.Columns(level, r, tNow, nx0, nx1))
                {
                    return Outcome::kGoOn;
                }
                x0 = backward ? std::max(x0, nx0) : x0;
                x1 = backward ? x1 : std::min(x1, nx1);
            }
        }
        return Outcome::kGoOn;
    }

    // Collects and reports the candidates of one cell.
    Outcome VisitCell(int level, int32_t x, int32_t r, uint64_t version)
    {
        const uint64_t collected = m_owner.m_mutations;
        int32_t count;
        const Entry* entries = m_owner.m_pyramid.CellEntries(level, x, r, count);
        for (int32_t i = 0; i < count; ++i)
        {
            Collect(entries[i]);
        }
        if (m_batch.size() == 0)
        {
            return Outcome::kGoOn;
        }
        return ReportBatch(collected, version);
    }

    // Collects and reports the candidates of a whole level, through the segment's bounding box.
    Outcome ScanLevel(int level, uint64_t version)
    {
        const uint64_t collected = m_owner.m_mutations;
        m_owner.m_pyramid.VisitLevel(level, m_segment.Bounds(),
                                     [this](const Entry& e) { return Collect(e); });
        return ReportBatch(collected, version);
    }

    bool Collect(const Entry& e)
    {
        if (m_segment.MayCross(e.box))
        {
            m_batch.push_back(e);
        }
        return true;
    }

    // Reports the batch in order and empties it. `collected` is the mutation count when the batch was collected.
    Outcome ReportBatch(uint64_t collected, uint64_t version)
    {
        for (size_t i = 0; i < m_batch.size(); ++i)
        {
            if (!ReportEntry(m_batch[i], collected))
            {
                return Outcome::kStopped;
            }
        }
        m_batch.clear();
        return m_owner.m_pyramid.Version() != version ? Outcome::kRebuilt : Outcome::kGoOn;
    }

    // Reports one collected entry unless a callback has made it stale, destroyed it or reported it already; false
    // when the callback ended the ray cast.
    bool ReportEntry(const Entry& e, uint64_t collected)
    {
        m_owner.ApplyQueuedIfAny(); // a callback's QueueMove: see Query
        if (!StillCrossed(e, collected) || (MayRepeat() && m_reported.contains(e.id)))
        {
            return true;
        }
        m_reported.push_back(e.id);
        const RayInput sub{m_input.p1, m_input.p2, m_segment.MaxFraction()};
        const float value = m_fn(m_context, sub, e.id);
        if (value == 0.0f)
        {
            return false;
        }
        if (value > 0.0f)
        {
            m_segment.Clip(value);
        }
        return true;
    }

    // Whether the segment, clipped so far, may still cross the proxy of a collected entry.
    bool StillCrossed(const Entry& e, uint64_t collected) const
    {
        const ProxyPool& pool = m_owner.m_pool;
        // A callback's move leaves the proxy's entry stale (old box) until the next FindPairs or query, and a batch
        // collected after that callback holds the stale box: test the pool's box then.
        if (m_owner.m_mutations == collected && !pool.IsStale(e.id))
        {
            return m_segment.MayCross(
                e.box); // the segment may have been clipped since the entry was collected
        }
        // destroyed (its id may have been reused) or moved away by a callback
        return pool.IsLive(e.id) && m_segment.MayCross(pool.Fat(e.id));
    }

    // Without a change since the call began, each entry is collected once: no id can come twice.
    bool MayRepeat() const { return m_restarted || m_owner.m_mutations != m_startMutations; }

    const QuadtreeBroadPhase& m_owner;
    const RayInput& m_input;
    const RayCastFn m_fn;
    void* const m_context;
    SegmentTest m_segment;
    SmallBuffer<Entry, 32> m_batch;
    SmallBuffer<ProxyId, 32> m_reported; // ids reported by this call, to report none twice after a change
    const uint64_t m_startMutations;
    bool m_restarted = false;
};

void QuadtreeBroadPhase::RayCast(const RayInput& input, RayCastFn fn, void* context) const
{
    ApplyForRead(); // no stale entry from here to the first callback
    RayCaster(*this, input, fn, context).Run();
}

} // namespace quadphase
