// SPDX-License-Identifier: MIT
#include "paper_quadtree.h"

#include <omp.h>

#include <algorithm>

#include "report_error.h"
#include "row_major.h"

namespace quadphase
{
namespace bench
{
namespace
{
Box CheckedBounds(const Box& bounds)
{
    const bool finite = IsFinite(bounds);
    if (finite && bounds.minX < bounds.maxX && bounds.minY < bounds.maxY)
    {
        return bounds;
    }
    ReportError(finite ? ErrorCode::InvertedBox : ErrorCode::NonFiniteBox,
                "PaperQuadtreeBroadPhase: %s bounds (%g, %g, %g, %g)",
                finite ? "empty or inverted" : "non-finite", double(bounds.minX), double(bounds.minY),
                double(bounds.maxX), double(bounds.maxY));
    return Config{}.bounds;
}

omp_sched_t OmpKind(Schedule schedule)
{
    switch (schedule) // no default: -Wswitch names a Schedule added later and not mapped here
    {
    case Schedule::Static:
        return omp_sched_static;
    case Schedule::Dynamic:
        return omp_sched_dynamic;
    case Schedule::Guided:
        return omp_sched_guided;
    case Schedule::Auto:
        return omp_sched_auto;
    }
    return omp_sched_static; // a value outside the enumerators
}

Pair Ordered(ProxyId a, ProxyId b)
{
    return a < b ? Pair{a, b} : Pair{b, a};
}
} // namespace

struct PaperQuadtreeBroadPhase::Locks
{
    std::vector<omp_lock_t> leaf; // one per leaf, row-major: the paper's Box::writelock
    omp_lock_t pairs;             // the paper's single global lock on the shared pair vector

    explicit Locks(size_t leafCount) : leaf(leafCount)
    {
        for (omp_lock_t& l : leaf)
        {
            omp_init_lock(&l);
        }
        omp_init_lock(&pairs);
    }
    ~Locks()
    {
        for (omp_lock_t& l : leaf)
        {
            omp_destroy_lock(&l);
        }
        omp_destroy_lock(&pairs);
    }
    Locks(const Locks&) = delete;
    Locks& operator=(const Locks&) = delete;
};

PaperQuadtreeBroadPhase::PaperQuadtreeBroadPhase(int levels, const Box& bounds, int threads,
                                                 Schedule schedule, PaperPairReport report,
                                                 const FatPolicy& policy)
    : BruteForceBroadPhase(policy), m_report(report), m_levels(std::clamp(levels, kMinLevels, kMaxLevels)),
      m_leafSide(int32_t(1) << (m_levels - 1)), m_bounds(CheckedBounds(bounds)),
      m_threads(threads < 0 ? 0 : threads), m_schedule(schedule)
{
    BuildTree();
    m_locks = std::make_unique<Locks>(m_leaves.size());
}

PaperQuadtreeBroadPhase::~PaperQuadtreeBroadPhase() = default;

// ---------------------------------------------------------------------------------------------------------------
// The tree: built once (again only on ShiftOrigin), never restructured.

void PaperQuadtreeBroadPhase::BuildTree()
{
    m_nodes.clear();
    m_leaves.clear();
    // (4^levels - 1) / 3 nodes; reserved so that no push_back moves the nodes during Generate.
    m_nodes.reserve(size_t(((int64_t(1) << (2 * m_levels)) - 1) / 3));
    m_nodes.push_back(Node{m_bounds, {}, {}, -1});
    std::vector<int32_t> creationOrder;
    creationOrder.reserve(size_t(m_leafSide) * size_t(m_leafSide));
    Generate(0, m_levels, creationOrder);
    Linearize(creationOrder);
}

// Depth first, four children at a time in the paper's quadrant order TL, TR, BL, BR. The paper's screen y grows
// downward, so its "top" row is the one nearest y = 0; here that is the row nearest bounds.minY: child 0 is
// (low x, low y), 1 (high x, low y), 2 (low x, high y), 3 (high x, high y). Leaves are recorded as they are created.
void PaperQuadtreeBroadPhase::Generate(int32_t node, int remainingLevels, std::vector<int32_t>& creationOrder)
{
    if (remainingLevels <= 1)
    {
        creationOrder.push_back(node);
        return;
    }
    const Box b = m_nodes[size_t(node)].box;
    const float midX = 0.5f * (b.minX + b.maxX);
    const float midY = 0.5f * (b.minY + b.maxY);
    const Box quadrants[4] = {
        Box{b.minX, b.minY, midX, midY},
        Box{midX, b.minY, b.maxX, midY},
        Box{b.minX, midY, midX, b.maxY},
        Box{midX, midY, b.maxX, b.maxY},
    };
    for (const Box& q : quadrants)
    {
        m_nodes[size_t(node)].children.push_back(int32_t(m_nodes.size()));
        m_nodes.push_back(Node{q, {}, {}, -1});
    }
    for (int i = 0; i < 4; ++i)
    {
        Generate(m_nodes[size_t(node)].children[size_t(i)], remainingLevels - 1, creationOrder);
    }
}

// The paper's linearize (Figure 2): walk rows, then columns, and take the leaf whose creation index is
// 2 * spread(row) + spread(column) (its base-4 "binary to decimal" conversion), numbering leaves row-major.
void PaperQuadtreeBroadPhase::Linearize(const std::vector<int32_t>& creationOrder)
{
    m_leaves.clear();
    m_leaves.reserve(creationOrder.size());
    for (int32_t row = 0; row < m_leafSide; ++row)
    {
        for (int32_t column = 0; column < m_leafSide; ++column)
        {
            const int32_t node = creationOrder[PaperCreationIndex(uint32_t(row), uint32_t(column))];
            m_nodes[size_t(node)].leafIndex = int32_t(m_leaves.size());
            m_leaves.push_back(node);
        }
    }
}

// The paper's insert: from the root, go to the child whose quadrant holds the centre (x < mid: low side, else high
// side), until a leaf. Centres outside the bounds therefore land in border leaves (clamped, never dropped);
// a NaN centre compares false and lands in the (high x, high y) corner leaf.
int32_t PaperQuadtreeBroadPhase::Descend(const Box& fat) const
{
    const float cx = 0.5f * (fat.minX + fat.maxX);
    const float cy = 0.5f * (fat.minY + fat.maxY);
    int32_t node = 0;
    while (!m_nodes[size_t(node)].children.empty())
    {
        const Node& n = m_nodes[size_t(node)];
        const float midX = 0.5f * (n.box.minX + n.box.maxX);
        const float midY = 0.5f * (n.box.minY + n.box.maxY);
        const int quadrant = (cx < midX ? 0 : 1) + (cy < midY ? 0 : 2);
        node = n.children[size_t(quadrant)];
    }
    return node;
}

// ---------------------------------------------------------------------------------------------------------------
// Pair finding.

namespace
{
// One leaf of the paper's loop. For each object, in leaf order: first its edge neighbours, in the paper's edge
// order (top, bottom, left, right = row - 1, row + 1, column - 1, column + 1 here), each one when the object's fat
// box crosses that side of its own leaf (strictly) and the leaf is not on that border of the bounds: the object is
// tested against every object of that neighbour. Then the objects after it in its own leaf.
template <typename Emit>
void ProcessLeaf(const std::vector<ProxyId>& objects, const Box& leafBox, int32_t leafIndex, int32_t side,
                 const std::vector<const std::vector<ProxyId>*>& leafObjects, const ProxyPool& pool,
                 Emit&& emit)
{
    const int32_t row = leafIndex / side;
    const int32_t column = leafIndex % side;
    const size_t count = objects.size();
    for (size_t i = 0; i < count; ++i)
    {
        const ProxyId a = objects[i];
        const Box& fa = pool.Fat(a);
        const bool cross[4] = {
            fa.minY < leafBox.minY && row > 0,
            fa.maxY > leafBox.maxY && (row < side - 1),
            fa.minX < leafBox.minX && (column > 0),
            fa.maxX > leafBox.maxX && column < side - 1,
        };
        const int32_t neighbour[4] = {leafIndex - side, leafIndex + side, leafIndex - 1, leafIndex + 1};
        for (int e = 0; e < 4; ++e)
        {
            if (!cross[e])
            {
                continue;
            }
            for (ProxyId b : *leafObjects[size_t(neighbour[e])])
            {
                if (Overlaps(fa, pool.Fat(b)))
                {
                    emit(a, b);
                }
            }
        }
        for (size_t j = i + 1; j < count; ++j)
        {
            const ProxyId b = objects[j];
            if (Overlaps(fa, pool.Fat(b)))
            {
                emit(a, b);
            }
        }
    }
}
} // namespace

// The paper's frame in one parallel region, as in the author's code: insertion as an OpenMP loop
// (schedule(static)) with a lock per leaf; then the loop over leaves with the chosen schedule, every pair pushed
// into the one shared vector under the one pair lock; then the paper's clearTree. One thread is the paper's
// sequential quadtree ("Seq." in its tables): the region is inactive (no team), insertion still goes through the
// leaf locks (its Box::addParticle), pairs are pushed without the pair lock.
void PaperQuadtreeBroadPhase::FindPairs(std::vector<Pair>& out)
{
    // flags the buffered proxies "in work" for the Buffered filter, clears the buffer
    m_pool.LendBuffer(m_work);
    const int threads = m_threads > 0 ? m_threads : omp_get_max_threads();
    std::vector<const std::vector<ProxyId>*> leafObjects(m_leaves.size());
    for (size_t i = 0; i < m_leaves.size(); ++i)
    {
        leafObjects[i] = &m_nodes[size_t(m_leaves[i])].objects;
    }

    omp_sched_t previousKind;
    int previousChunk;
    omp_get_schedule(&previousKind, &previousChunk);
    omp_set_schedule(OmpKind(m_schedule), 0); // 0: OpenMP's default chunk for that schedule

    const bool filter = m_report == PaperPairReport::Buffered;
    const ProxyId idBound = m_pool.IdBound();
    const int32_t leafCount = int32_t(m_leaves.size());
    Locks& locks = *m_locks;

#pragma omp parallel num_threads(threads) if (threads > 1)
    {
#pragma omp for schedule(static)
        for (ProxyId id = 0; id < idBound; ++id)
        {
            if (m_pool.IsLive(id))
            {
                Node& leaf = m_nodes[size_t(Descend(m_pool.Fat(id)))];
                omp_lock_t& lock = locks.leaf[size_t(leaf.leafIndex)];
                omp_set_lock(&lock);
                leaf.objects.push_back(id);
                omp_unset_lock(&lock);
            }
        }
        // (implicit barrier: every object is inserted before any leaf is searched)

        auto emit = [&](ProxyId a, ProxyId b) {
            if (!filter || m_pool.InWork(a) || m_pool.InWork(b))
            {
                if (threads > 1)
                {
                    omp_set_lock(&locks.pairs);
                }
                out.push_back(Ordered(a, b));
                if (threads > 1)
                {
                    omp_unset_lock(&locks.pairs);
                }
            }
        };
#pragma omp for schedule(runtime)
        for (int32_t li = 0; li < leafCount; ++li)
        {
            const Node& leaf = m_nodes[size_t(m_leaves[size_t(li)])];
            ProcessLeaf(leaf.objects, leaf.box, li, m_leafSide, leafObjects, m_pool, emit);
        }
    }

    omp_set_schedule(previousKind, previousChunk); // the schedule ICV belongs to the caller's thread
    for (int32_t node : m_leaves)
    {
        m_nodes[size_t(node)].objects.clear();
    }
    m_pool.ReturnBuffer(m_work);
}

void PaperQuadtreeBroadPhase::ShiftOrigin(Vec2 newOrigin)
{
    BruteForceBroadPhase::ShiftOrigin(newOrigin);
    m_bounds = Box{m_bounds.minX - newOrigin.x, m_bounds.minY - newOrigin.y, m_bounds.maxX - newOrigin.x,
                   m_bounds.maxY - newOrigin.y};
    BuildTree(); // same leaf count: the locks stay
}

} // namespace bench
} // namespace quadphase
