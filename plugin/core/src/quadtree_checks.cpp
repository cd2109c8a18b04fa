// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase's statistics (GetStats, ResetCounters) and its invariant check (Validate).
#include "quadtree_broad_phase.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace quadphase
{

Stats QuadtreeBroadPhase::GetStats() const
{
    // Const calls on other threads may be applying queued moves (under this lock), which writes the counters,
    // the stale list and the pyramid.
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
        int64_t((m_work.capacity() + m_stale.capacity() + m_queuedIds.capacity()) * sizeof(ProxyId)) +
        int64_t(m_queued.capacity() * sizeof(QueuedMove)) +
        int64_t(m_blockPairs.capacity() * sizeof(std::vector<Pair>)) +
        m_blockRoom * int64_t(sizeof(uint8_t)) + int64_t(m_applyCounts.capacity() * sizeof(ApplyCounts)) +
        int64_t(m_refattened.capacity() * sizeof(ProxyId));
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
