// SPDX-License-Identifier: MIT
// The static quadtree: a complete pyramid of levels 0..depth over a square region, every level a dense
// row-major grid (see row_major.h).
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cell_store.h"
#include "compiler.h"
#include "quadphase/box.h"
#include "row_major.h"

namespace quadphase
{

/// The placement rule. Cell coordinates are computed once, at the deepest level, by a monotone function of the
/// coordinate (subtract the origin, multiply by the inverse leaf size, clamp into [0, 2^depth - 1], truncate; NaN
/// maps to 0); a coarser level's coordinate is that value shifted right. A proxy lives in exactly one cell: at the
/// deepest level where the cells of its box's min and max corners are equal or adjacent on both axes, in the cell
/// of its min corner. A proxy stored in cell c therefore lies within cells c and c+1 on each axis, so a box q can
/// only overlap proxies of level l stored in cells [cell(q.min) - 1, cell(q.max)] on each axis. Because the
/// coordinate function is monotone and both sides use it, this holds exactly in floating point, for boxes of any
/// size, and for boxes outside the region (they are clamped into border cells: found, only slower).
///
/// Invariants (checked by Validate):
/// - every stored id is in exactly one cell, the one the placement rule gives for its stored box;
/// - Location(id) names that cell and the entry's slot in it, and its slot in its level's list;
/// - a level's list holds exactly the ids stored in that level's cells;
/// - bit l of OccupiedLevels() is set exactly when level l's list is not empty.
class Pyramid
{
public:
    /// Empties the pyramid and sets its shape: levels 0..depth over the square [originX, originX + side) x
    /// [originY, originY + side). Requires 0 <= depth <= 15 and side > 0.
    void Reset(float originX, float originY, float side, int depth);

    /// Stores `id` with box `box`. Requires id >= 0 and id not stored.
    void Insert(ProxyId id, const Box& box);

    /// Removes a stored id.
    void Remove(ProxyId id);

    /// Lays the cells' entries out in cell order (see CellStore::Compact). Call after inserting many proxies.
    void Compact() { m_store.Compact(); }

    /// Takes the contents of `built` (a pyramid filled from scratch) in place of this one's. The version still
    /// increases, so walks across calls see the change. For rebuilds with the strong guarantee: a rebuild that
    /// throws std::bad_alloc half way leaves this pyramid untouched.
    void ReplaceWith(Pyramid&& built)
    {
        const uint64_t version = m_version;
        *this = std::move(built);
        m_version = version + 1;
    }

    /// Replaces the stored box of `id`, moving it to another cell when the placement rule says so (within its
    /// level, its slot in the level's list is kept). Returns true when it changed cell.
    bool Update(ProxyId id, const Box& box);

    /// For a stored id whose box changed: when the placement rule keeps it in its cell, rewrites the entry's box
    /// and the id's outside flag, adds the change of OutsideCount() to `outsideDelta` (the caller hands the sum to
    /// AddOutsideDelta) and returns true. Otherwise changes nothing and returns false: the caller re-places the id
    /// later (Update, UpdateBatch). Threads may call it at the same time for distinct ids: it writes only this id's
    /// location and entry.
    bool RewriteInPlace(ProxyId id, const Box& box, int32_t& outsideDelta)
    {
        int level;
        int32_t cell;
        PlaceCell(box, level, cell);
        return RewriteIfInCell(id, box, cell, outsideDelta);
    }
    void AddOutsideDelta(int32_t delta) { m_outsideCount += delta; }

    /// Update for each of the (distinct, stored) `ids`, with box `boxes[id]`, in `ids` order; then compacts the
    /// cell store when it has grown wasteful. Returns how many changed cell. One thread: a parallel version (place
    /// over ids, then leave and join cells, each cell owned by one thread) was slower, because each id's location
    /// and cells passed between the cores' caches from phase to phase (docs/design.md, "Grid maintenance"). The
    /// loop prefetches the data of the ids ahead: the misses of several changes overlap.
    int64_t UpdateBatch(const std::vector<ProxyId>& ids, const Box* boxes);

    /// Calls visit(const Entry&) for every stored entry that may overlap `query` (a superset of the overlapping
    /// ones, each entry at most once), level by level from the root, until visit returns false. The ranges of
    /// a level are computed from `query` when that level starts, so a caller may shrink `query` (through the
    /// reference it passed) while visiting. Cost per level: min(cells in the range, proxies in the level).
    template <typename Visitor>
    void Visit(const Box& query, Visitor&& visit) const;

    /// Visit restricted to one level. Returns false when visit did.
    template <typename Visitor>
    bool VisitLevel(int level, const Box& query, Visitor&& visit) const;

    /// A query's range in deepest-level cell coordinates (CoordX/CoordY of its corners), shifted per level.
    struct LeafRange
    {
        int32_t x0, y0, x1, y1;
    };
    template <typename Visitor>
    bool VisitLevel(int level, const LeafRange& range, Visitor&& visit) const;

    /// What VisitLevel(level, query, ...) reads: the number of cells of the level that `query`'s range covers, or
    /// the level's proxy count when that is smaller (VisitLevel then walks the level's list).
    int64_t VisitCost(int level, const Box& query) const;

    /// Incremented by Reset (a new shape: every cell index changes meaning). A caller that walks cells across
    /// calls that may change the pyramid (RayCast, whose callbacks may call back into the broadphase) starts again
    /// when it changes. Other changes keep every entry they do not move or remove in its cell (Insert and Push
    /// append, removal swaps a cell's last entry into the hole, Compact moves blocks, not entries between cells),
    /// so a walk that reads cells by index again after each callback misses only entries that moved.
    uint64_t Version() const { return m_version; }

    /// The placement rule's coordinate function, for walks that compute cells themselves (RayCast): a point with
    /// coordinate x is at deepest-level column trunc(clamp((x - OriginX()) * InvLeaf(), 0, MaxCoord())), and at
    /// level l at that column shifted right by Depth() - l. The same for y with OriginY().
    float OriginX() const { return m_originX; }
    float OriginY() const { return m_originY; }
    float InvLeaf() const { return m_invLeaf; }
    float MaxCoord() const { return m_maxCoord; }

    /// The entries of cell (x, y) of `level` (row-major; 0 <= x, y < LevelSide(level)), `count` of them. Valid
    /// until the next change of the pyramid.
    const Entry* CellEntries(int level, int32_t x, int32_t y, int32_t& count) const
    {
        const int32_t cell = LevelOffset(level) + y * LevelSide(level) + x;
        count = m_store.Size(cell);
        return m_store.Data(cell);
    }

    int Depth() const { return m_depth; }
    float LeafSize() const { return m_leafSize; }
    Box Bounds() const { return Box{m_originX, m_originY, m_originX + m_side, m_originY + m_side}; }

    /// Level a stored id lives at.
    int LevelOf(ProxyId id) const { return m_location[size_t(id)].level; }

    /// Number of proxies stored at `level`.
    int32_t LevelCount(int level) const { return int32_t(m_levelProxies[size_t(level)].size()); }

    /// Bit l set when level l stores at least one proxy. Visit walks only these levels: most scenes fill two or
    /// three of a pyramid's 8-12 levels (docs/design.md, "Pair generation").
    uint32_t OccupiedLevels() const { return m_occupiedLevels; }

    /// Number of stored ids whose box is not inside the bounds.
    int32_t OutsideCount() const { return m_outsideCount; }

    /// Cells holding at least one proxy, and the size of the most crowded one. O(cells).
    void CountOccupancy(int64_t& occupied, int64_t& largest) const;

    /// Number of proxies in cell `index` of `level` (row-major). For drawing and tests.
    int32_t CellCount(int level, int32_t index) const { return m_store.Size(LevelOffset(level) + index); }

    /// The (level, row-major index) the placement rule gives for `box`.
    void Place(const Box& box, int& level, int32_t& index) const;

    int64_t MemoryBytes() const;

    /// Checks the invariants above. Empty string when they hold, otherwise the first violation.
    std::string Validate() const;

private:
    // 12 bytes per proxy: the level and the outside flag share a word with the cell index (a pyramid of depth
    // kMaxDepth has 22.4 million cells, under the 2^25 that 26 signed bits hold).
    struct Location
    {
        Location() : cell(-1), level(-1), outside(0) {}
        int32_t cell : 26; // index into m_store (all levels), -1 when not stored
        int32_t level : 5; // -1 when not stored
        uint32_t outside : 1;
        int32_t slot = -1;      // index of the entry in that cell
        int32_t levelSlot = -1; // index in m_levelProxies[level]
    };
    static_assert(sizeof(Location) == 12, "Location packs into three words");

    void ReserveLevelSlot(int level);
    // Appends `id` to `level`'s list, within the capacity ReserveLevelSlot made (no allocation), and records its slot.
    void AppendToLevel(ProxyId id, int level);
    void RemoveFromLevel(ProxyId id);

    int32_t CoordX(float x) const
    {
        float t = (x - m_originX) * m_invLeaf;
        t = t > 0.0f ? t : 0.0f; // also maps NaN to 0
        t = t < m_maxCoord ? t : m_maxCoord;
        return int32_t(t);
    }
    int32_t CoordY(float y) const
    {
        float t = (y - m_originY) * m_invLeaf;
        t = t > 0.0f ? t : 0.0f;
        t = t < m_maxCoord ? t : m_maxCoord;
        return int32_t(t);
    }
    bool Inside(const Box& b) const
    {
        return m_originX <= b.minX && m_originY <= b.minY && b.maxX <= m_originX + m_side &&
               b.maxY <= m_originY + m_side;
    }
    void PlaceCell(const Box& box, int& level, int32_t& cell) const;
    // RewriteInPlace for a box the placement rule puts in `cell` (shared with Update, which places it once).
    bool RewriteIfInCell(ProxyId id, const Box& box, int32_t cell, int32_t& outsideDelta)
    {
        Location& loc = m_location[size_t(id)];
        if (cell != loc.cell)
        {
            return false;
        }
        m_store.Data(cell)[loc.slot].box = box;
        const bool outside = !Inside(box);
        outsideDelta += int32_t(outside) - int32_t(loc.outside);
        loc.outside = outside;
        return true;
    }
    void Store(ProxyId id, const Box& box, int level, int32_t cell);
    // Update for a box the placement rule puts in (level, cell) (UpdateBatch places it ahead, for its prefetches).
    bool UpdatePlaced(ProxyId id, const Box& box, int level, int32_t cell);
    void RemoveFromCell(ProxyId id);

    int m_depth = 0;
    float m_originX = 0.0f;
    float m_originY = 0.0f;
    float m_side = 1.0f;
    float m_leafSize = 1.0f;
    float m_invLeaf = 1.0f;
    float m_maxCoord = 0.0f; // 2^depth - 1, as float

    CellStore m_store;                                // all levels' cells, level l at LevelOffset(l)
    int64_t m_stored = 0;                             // ids stored
    std::vector<std::vector<ProxyId>> m_levelProxies; // per level
    uint32_t m_occupiedLevels = 0;                    // bit l: m_levelProxies[l] is not empty (depth <= 15)
    std::vector<Location> m_location;                 // per id
    int32_t m_outsideCount = 0;
    uint64_t m_version = 0;
};

template <typename Visitor>
void Pyramid::Visit(const Box& query, Visitor&& visit) const
{
    // The query's deepest-level coordinates once; each level shifts them (every query of FindPairs comes here;
    // docs/design.md, "Pair generation").
    const LeafRange range{CoordX(query.minX), CoordY(query.minY), CoordX(query.maxX), CoordY(query.maxY)};
    for (uint32_t levels = m_occupiedLevels; levels != 0; levels &= levels - 1)
    {
        if (!VisitLevel(compiler::CountTrailingZeros32(levels), range, visit))
        {
            return;
        }
    }
}

template <typename Visitor>
bool Pyramid::VisitLevel(int level, const Box& query, Visitor&& visit) const
{
    const LeafRange range{CoordX(query.minX), CoordY(query.minY), CoordX(query.maxX), CoordY(query.maxY)};
    return VisitLevel(level, range, visit);
}

template <typename Visitor>
bool Pyramid::VisitLevel(int level, const LeafRange& range, Visitor&& visit) const
{
    const std::vector<ProxyId>& levelList = m_levelProxies[size_t(level)];
    if (levelList.empty())
    {
        return true; // levels nobody uses cost one comparison
    }
    const int shift = m_depth - level;
    int32_t x0 = (range.x0 >> shift) - 1;
    int32_t y0 = (range.y0 >> shift) - 1;
    const int32_t x1 = range.x1 >> shift;
    const int32_t y1 = range.y1 >> shift;
    x0 = x0 < 0 ? 0 : x0;
    y0 = y0 < 0 ? 0 : y0;
    if (x1 < x0 || y1 < y0)
    {
        return true;
    }
    const int64_t area = int64_t(x1 - x0 + 1) * int64_t(y1 - y0 + 1);
    if (area > int64_t(levelList.size()))
    {
        // The range covers more cells than the level has proxies: walking the level's list is cheaper.
        for (ProxyId id : levelList)
        {
            const Location& loc = m_location[size_t(id)];
            if (!visit(m_store.Data(loc.cell)[loc.slot]))
            {
                return false;
            }
        }
        return true;
    }
    const int32_t side = LevelSide(level);
    const int32_t offset = LevelOffset(level);
    for (int32_t y = y0; y <= y1; ++y)
    {
        const int32_t rowBase = offset + y * side;
        for (int32_t x = x0; x <= x1; ++x)
        {
            int32_t count;
            const Entry* entries = m_store.Entries(rowBase + x, count);
            for (int32_t i = 0; i < count; ++i)
            {
                if (!visit(entries[i]))
                {
                    return false;
                }
            }
        }
    }
    return true;
}

} // namespace quadphase
