// SPDX-License-Identifier: MIT
// Pyramid: placing proxies in the static quadtree, moving them between cells (one at a time and in batches),
// rebuilding, occupancy counts and the invariant check.
#include "pyramid.h"

#include <algorithm>
#include <string>

namespace quadphase
{
namespace
{

// Number of significant bits of v > 0.
int BitLength(uint32_t v)
{
    return 32 - compiler::CountLeadingZeros32(v);
}

} // namespace

void Pyramid::Reset(float originX, float originY, float side, int depth)
{
    m_depth = depth;
    m_originX = originX;
    m_originY = originY;
    m_side = side;
    m_leafSize = side / float(LevelSide(depth));
    m_invLeaf = 1.0f / m_leafSize;
    m_maxCoord = float(LevelSide(depth) - 1);

    m_store.Reset(PyramidCellCount(depth));
    m_stored = 0;
    m_levelProxies.assign(size_t(depth + 1), {});
    m_occupiedLevels = 0;
    for (Location& loc : m_location)
    {
        loc = Location{};
    }
    m_outsideCount = 0;
    ++m_version;
}

void Pyramid::PlaceCell(const Box& box, int& level, int32_t& cell) const
{
    const int32_t ix0 = CoordX(box.minX);
    const int32_t iy0 = CoordY(box.minY);
    const int32_t ix1 = CoordX(box.maxX);
    const int32_t iy1 = CoordY(box.maxY);
    const int32_t dx = ix1 - ix0;
    const int32_t dy = iy1 - iy0;
    const int32_t d = dx > dy ? dx : dy;
    // (b >> k) - (a >> k) <= ((b - a) >> k) + 1, so k = BitLength(d) always fits; often one less does.
    int k = d <= 1 ? 0 : BitLength(uint32_t(d)) - 1;
    while (((ix1 >> k) - (ix0 >> k)) > 1 || ((iy1 >> k) - (iy0 >> k)) > 1)
    {
        ++k;
    }
    level = m_depth - k;
    cell = LevelOffset(level) + RowMajorIndex(level, ix0 >> k, iy0 >> k);
}

void Pyramid::Place(const Box& box, int& level, int32_t& index) const
{
    PlaceCell(box, level, index);
    index -= LevelOffset(level);
}

void Pyramid::ReserveLevelSlot(int level)
{
    std::vector<ProxyId>& levelList = m_levelProxies[size_t(level)];
    if (levelList.size() == levelList.capacity())
    {
        levelList.reserve(std::max<size_t>(16, 2 * levelList.capacity()));
    }
}

void Pyramid::AppendToLevel(ProxyId id, int level)
{
    std::vector<ProxyId>& levelList = m_levelProxies[size_t(level)];
    Location& loc = m_location[size_t(id)];
    loc.level = int8_t(level);
    loc.levelSlot = int32_t(levelList.size());
    levelList.push_back(id); // within the capacity ReserveLevelSlot made
    m_occupiedLevels |= uint32_t(1) << level;
}

void Pyramid::Store(ProxyId id, const Box& box, int level, int32_t cell)
{
    // Everything that allocates comes first, so std::bad_alloc leaves the pyramid as it was.
    ReserveLevelSlot(level);
    const int32_t slot = m_store.Push(cell, Entry{box, id});
    Location& loc = m_location[size_t(id)];
    loc.cell = cell;
    loc.slot = slot;
    ++m_stored;
    AppendToLevel(id, level);
}

void Pyramid::Insert(ProxyId id, const Box& box)
{
    if (size_t(id) >= m_location.size())
    {
        m_location.resize(std::max(size_t(id) + 1, 2 * m_location.size()));
    }
    int level;
    int32_t cell;
    PlaceCell(box, level, cell);
    Store(id, box, level, cell);
    Location& loc = m_location[size_t(id)];
    loc.outside = !Inside(box);
    m_outsideCount += loc.outside ? 1 : 0;
}

void Pyramid::RemoveFromCell(ProxyId id)
{
    const Location& loc = m_location[size_t(id)];
    const ProxyId moved = m_store.SwapRemove(loc.cell, loc.slot);
    if (moved >= 0)
    {
        m_location[size_t(moved)].slot = loc.slot;
    }
}

void Pyramid::RemoveFromLevel(ProxyId id)
{
    const Location& loc = m_location[size_t(id)];
    std::vector<ProxyId>& levelList = m_levelProxies[size_t(loc.level)];
    const ProxyId lastId = levelList.back();
    m_location[size_t(lastId)].levelSlot = loc.levelSlot;
    levelList[size_t(loc.levelSlot)] = lastId;
    levelList.pop_back();
    if (levelList.empty())
    {
        m_occupiedLevels &= ~(uint32_t(1) << loc.level);
    }
}

void Pyramid::Remove(ProxyId id)
{
    RemoveFromCell(id);
    RemoveFromLevel(id);
    Location& loc = m_location[size_t(id)];
    m_outsideCount -= loc.outside ? 1 : 0;
    loc = Location{};
    --m_stored;
}

bool Pyramid::Update(ProxyId id, const Box& box)
{
    int level;
    int32_t cell;
    PlaceCell(box, level, cell);
    return UpdatePlaced(id, box, level, cell);
}

bool Pyramid::UpdatePlaced(ProxyId id, const Box& box, int level, int32_t cell)
{
    int32_t outsideDelta = 0;
    if (RewriteIfInCell(id, box, cell, outsideDelta))
    {
        m_outsideCount += outsideDelta;
        return false;
    }
    Location& loc = m_location[size_t(id)];
    const bool outside = !Inside(box);
    if (level == loc.level)
    {
        // Within its level (nearly every change: a moving body crosses into a neighbouring cell), the level's list
        // keeps the id where it is.
        // Pushed first: when the push throws std::bad_alloc the entry is still in its old cell.
        const int32_t slot = m_store.Push(cell, Entry{box, id});
        RemoveFromCell(id);
        loc.cell = cell;
        loc.slot = slot;
    }
    else
    {
        // A change of level. The allocations first (the new level's list, the new cell's entry), so that
        // std::bad_alloc leaves the proxy where it was; then the removal from the old cell and level.
        ReserveLevelSlot(level);
        const int32_t slot = m_store.Push(cell, Entry{box, id});
        RemoveFromCell(id);
        RemoveFromLevel(id);
        loc.cell = cell;
        loc.slot = slot;
        AppendToLevel(id, level);
    }
    m_outsideCount += int32_t(outside) - int32_t(loc.outside);
    loc.outside = outside;
    return true;
}

int64_t Pyramid::UpdateBatch(const std::vector<ProxyId>& ids, const Box* boxes)
{
    // Each cell change is a chain of dependent loads (the id's location and box, then its old and new cells, then
    // their entries, then the location of the entry that fills the hole), mostly cache misses. The ids ahead are
    // prefetched one link further at each distance, so the misses of several changes overlap (docs/design.md,
    // "Grid maintenance", has the measurements). Prefetches read the current state, which the changes in
    // between may alter: they are hints, and every change below reads the state afresh. The loop starts
    // kLocation ids early so that every id goes through every stage.
    constexpr int64_t kLocation = 12, kCell = 8, kEntries = 4, kMoved = 2, kRing = 16;
    // The placement of each id, computed at distance kCell and used at kEntries and by the update itself.
    int32_t newCell[kRing];
    int newLevel[kRing];
    const int64_t n = int64_t(ids.size());
    int64_t changed = 0;
    for (int64_t i = -kLocation; i < n; ++i)
    {
        if (i + kLocation < n)
        {
            const ProxyId id = ids[size_t(i + kLocation)];
            QUADPHASE_PREFETCH(&m_location[size_t(id)]);
            QUADPHASE_PREFETCH(&boxes[id]);
        }
        if (i + kCell >= 0 && i + kCell < n)
        {
            const ProxyId id = ids[size_t(i + kCell)];
            int32_t& cell = newCell[(i + kCell) % kRing];
            PlaceCell(boxes[id], newLevel[(i + kCell) % kRing], cell);
            m_store.PrefetchCell(cell);
            m_store.PrefetchCell(m_location[size_t(id)].cell);
        }
        if (i + kEntries >= 0 && i + kEntries < n)
        {
            const Location& loc = m_location[size_t(ids[size_t(i + kEntries)])];
            m_store.PrefetchSlot(loc.cell, uint32_t(loc.slot));
            // the entry that fills the hole
            m_store.PrefetchSlot(loc.cell, uint32_t(m_store.Size(loc.cell) - 1));
            const int32_t cell = newCell[(i + kEntries) % kRing];
            if (m_store.HasRoom(cell))
            {
                m_store.PrefetchSlot(cell, uint32_t(m_store.Size(cell)));
            }
        }
        if (i + kMoved >= 0 && i + kMoved < n)
        {
            // A stored id's cell holds at least that id, so the last entry exists.
            const Location& loc = m_location[size_t(ids[size_t(i + kMoved)])];
            QUADPHASE_PREFETCH(&m_location[size_t(m_store.Data(loc.cell)[m_store.Size(loc.cell) - 1].id)]);
        }
        if (i < 0)
        {
            continue;
        }
        const ProxyId id = ids[size_t(i)];
        changed += UpdatePlaced(id, boxes[id], newLevel[i % kRing], newCell[i % kRing]) ? 1 : 0;
    }
    if (m_store.Wasteful(m_stored))
    {
        m_store.Compact(); // amortised: the array doubled since it was last compact
    }
    return changed;
}

int64_t Pyramid::VisitCost(int level, const Box& query) const
{
    const int64_t listSize = int64_t(m_levelProxies[size_t(level)].size());
    const int shift = m_depth - level;
    const int64_t x0 = std::max<int64_t>(0, (CoordX(query.minX) >> shift) - 1);
    const int64_t y0 = std::max<int64_t>(0, (CoordY(query.minY) >> shift) - 1);
    const int64_t x1 = CoordX(query.maxX) >> shift;
    const int64_t y1 = CoordY(query.maxY) >> shift;
    const int64_t area = x1 < x0 || y1 < y0 ? 0 : (x1 - x0 + 1) * (y1 - y0 + 1);
    return std::min(area, listSize);
}

void Pyramid::CountOccupancy(int64_t& occupied, int64_t& largest) const
{
    occupied = 0;
    largest = 0;
    for (int32_t cell = 0; cell < m_store.CellCount(); ++cell)
    {
        const int64_t size = m_store.Size(cell);
        occupied += size == 0 ? 0 : 1;
        largest = size > largest ? size : largest;
    }
}

int64_t Pyramid::MemoryBytes() const
{
    int64_t bytes = m_store.MemoryBytes();
    bytes += int64_t(m_levelProxies.capacity() * sizeof(std::vector<ProxyId>));
    for (const std::vector<ProxyId>& list : m_levelProxies)
    {
        bytes += int64_t(list.capacity() * sizeof(ProxyId));
    }
    bytes += int64_t(m_location.capacity() * sizeof(Location));
    return bytes;
}

std::string Pyramid::Validate() const
{
    if (m_store.CellCount() != PyramidCellCount(m_depth) || m_levelProxies.size() != size_t(m_depth + 1))
    {
        return "pyramid arrays do not match depth " + std::to_string(m_depth);
    }
    const std::string storeProblem = m_store.Validate();
    if (!storeProblem.empty())
    {
        return "cells: " + storeProblem;
    }
    int32_t stored = 0;
    int32_t outside = 0;
    const int32_t cellCount = m_store.CellCount();
    for (int32_t cell = 0; cell < cellCount; ++cell)
    {
        // Most cells of a deep pyramid are empty: one read each (the fuzz targets validate after every check).
        const int32_t size = m_store.Size(cell);
        if (size == 0)
        {
            continue;
        }
        const Entry* entries = m_store.Data(cell);
        for (int32_t slot = 0; slot < size; ++slot)
        {
            const Entry& e = entries[slot];
            if (e.id < 0 || size_t(e.id) >= m_location.size())
            {
                return "cell " + std::to_string(cell) + " holds out-of-range id " + std::to_string(e.id);
            }
            const Location& loc = m_location[size_t(e.id)];
            if (loc.cell != cell || loc.slot != slot)
            {
                return "id " + std::to_string(e.id) + " is in cell " + std::to_string(cell) + " slot " +
                       std::to_string(slot) + " but its location says cell " + std::to_string(loc.cell) +
                       " slot " + std::to_string(loc.slot);
            }
            int level;
            int32_t expected;
            PlaceCell(e.box, level, expected);
            if (expected != cell || level != loc.level)
            {
                return "id " + std::to_string(e.id) + " is in cell " + std::to_string(cell) +
                       " but the placement rule gives cell " + std::to_string(expected);
            }
            if (loc.outside != !Inside(e.box))
            {
                return "id " + std::to_string(e.id) + " has a stale outside flag";
            }
            outside += loc.outside ? 1 : 0;
            ++stored;
        }
    }
    int32_t listed = 0;
    for (int level = 0; level <= m_depth; ++level)
    {
        const std::vector<ProxyId>& list = m_levelProxies[size_t(level)];
        for (int32_t i = 0; i < int32_t(list.size()); ++i)
        {
            const Location& loc = m_location[size_t(list[size_t(i)])];
            if (loc.level != level || loc.levelSlot != i || loc.cell < 0)
            {
                return "level " + std::to_string(level) + " list slot " + std::to_string(i) + " holds id " +
                       std::to_string(list[size_t(i)]) + " whose location disagrees";
            }
        }
        listed += int32_t(list.size());
        if (((m_occupiedLevels >> level) & 1u) != (list.empty() ? 0u : 1u))
        {
            return "level " + std::to_string(level) + " holds " + std::to_string(list.size()) +
                   " ids but its occupied bit says otherwise";
        }
    }
    if ((m_occupiedLevels >> (m_depth + 1)) != 0)
    {
        return "occupied bits above depth " + std::to_string(m_depth);
    }
    if (stored != m_stored)
    {
        return "stored count " + std::to_string(m_stored) + " but cells hold " + std::to_string(stored);
    }
    if (listed != stored)
    {
        return "level lists hold " + std::to_string(listed) + " ids but cells hold " + std::to_string(stored);
    }
    if (outside != m_outsideCount)
    {
        return "outside count " + std::to_string(m_outsideCount) + " but " + std::to_string(outside) +
               " outside";
    }
    return {};
}

} // namespace quadphase
