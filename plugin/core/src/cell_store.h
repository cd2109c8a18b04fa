// SPDX-License-Identifier: MIT
// The entries of every cell of the pyramid, kept in one array.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "compiler.h"
#include "quadphase/box.h"

namespace quadphase
{

using ProxyId = int32_t;

/// A proxy as stored in a cell: a copy of its fat box beside its id, so a cell's candidates are read from one
/// contiguous array.
struct Entry
{
    Box box;
    ProxyId id;
};

/// Cells as blocks of one shared array of entries. A cell owns a block of 2^k slots (k = its size class) or
/// none; a full cell moves to a block twice as large. Freed blocks are kept on one free list per size class.
///
/// Why not one std::vector per cell: a vector costs 24 bytes per cell even when empty, and one heap
/// allocation (with its allocator overhead) per occupied cell; most cells hold 0-4 entries. Here a cell costs
/// 8 bytes, and Compact() lays the blocks out in cell order, so neighbouring cells are neighbours in memory.
///
/// Invariants (checked by Validate):
/// - every block of a cell lies inside the array and no two blocks overlap, free blocks included;
/// - a cell's size is at most its block's capacity; a cell without a block has size 0.
///
/// Threading: Push and Compact allocate and are serial. SwapRemove and writes through Data() touch only their
/// cell, so threads may run them on distinct cells at the same time.
class CellStore
{
public:
    CellStore() { Reset(0); }

    /// Empties every cell and sets the number of cells. Frees the array.
    void Reset(int32_t cellCount);

    int32_t CellCount() const { return int32_t(m_cells.size()); }
    int32_t Size(int32_t cell) const { return int32_t(m_cells[size_t(cell)].size); }
    const Entry* Data(int32_t cell) const { return m_entries.data() + m_cells[size_t(cell)].begin; }
    Entry* Data(int32_t cell) { return m_entries.data() + m_cells[size_t(cell)].begin; }
    /// Data() and Size() from one read of the cell's record (every cell a query visits goes through here).
    const Entry* Entries(int32_t cell, int32_t& count) const
    {
        const Cell c = m_cells[size_t(cell)];
        count = int32_t(c.size);
        return m_entries.data() + c.begin;
    }

    /// Prefetch hints, for a caller about to change cells (they never read or write an entry): the cell's
    /// size and block, then (once those are in cache) the entry at `slot` of its block, which must be below
    /// its capacity.
    void PrefetchCell(int32_t cell) const { QUADPHASE_PREFETCH(&m_cells[size_t(cell)]); }
    void PrefetchSlot(int32_t cell, uint32_t slot) const
    {
        QUADPHASE_PREFETCH(m_entries.data() + m_cells[size_t(cell)].begin + slot);
    }

    /// True when one more entry fits in the cell's block.
    bool HasRoom(int32_t cell) const
    {
        const Cell& c = m_cells[size_t(cell)];
        return c.sizeClass != kNoBlock && c.size < (uint32_t(1) << c.sizeClass);
    }

    /// Appends an entry to a cell, moving the cell to a larger block when full. Returns its slot.
    /// Invalidates pointers returned by Data() (the array may grow).
    int32_t Push(int32_t cell, const Entry& entry);

    /// Removes the entry at `slot` by moving the cell's last entry into it. Returns the id of the moved
    /// entry, or -1 when the removed entry was the last one. The block is kept (Compact frees blocks of empty
    /// cells).
    ProxyId SwapRemove(int32_t cell, int32_t slot)
    {
        Cell& c = m_cells[size_t(cell)];
        const uint32_t last = c.size - 1;
        c.size = last;
        if (uint32_t(slot) == last)
        {
            return -1;
        }
        m_entries[c.begin + uint32_t(slot)] = m_entries[c.begin + last];
        return m_entries[c.begin + uint32_t(slot)].id;
    }

    /// True when the array holds much more than `stored` entries need (blocks of cells that emptied, free
    /// blocks): time for Compact(). Compaction stays amortised O(1) per block allocation with any factor
    /// above the blocks' own rounding (about 4/3). Small worlds compact at 1.5 times what they need, larger
    /// ones at 1.75. Since Compact keeps the array's capacity, the factor also bounds what the array holds for
    /// good (docs/design.md, "Memory").
    bool Wasteful(int64_t stored) const
    {
        const size_t need = size_t(stored);
        return need < 8192 ? 2 * m_entries.size() > 3 * need + 512 : 4 * m_entries.size() > 7 * need + 1024;
    }

    /// Lays the blocks out again in cell order, each of the smallest class that holds its entries, with no
    /// free blocks. Slots within cells are unchanged. O(cells + entries). The array keeps its capacity (only
    /// a temporary copy of the live entries is allocated), so a game that compacts every few steps reuses the
    /// same memory instead of faulting in fresh pages each time.
    void Compact();

    int64_t MemoryBytes() const;

    /// Checks the invariants above. Empty string when they hold, otherwise the first violation.
    std::string Validate() const;

private:
    static constexpr uint32_t kNoBlock = 63;
    static constexpr int kClasses = 27; // blocks of up to 2^26 entries

    struct Cell
    {
        uint32_t begin = 0;
        uint32_t size : 26;
        uint32_t sizeClass : 6;
        Cell() : size(0), sizeClass(kNoBlock) {}
    };
    static_assert(sizeof(Cell) == 8, "a cell is 8 bytes");

    // Appends an entry to a cell that HasRoom; returns its slot.
    int32_t PushNoGrow(int32_t cell, const Entry& entry)
    {
        Cell& c = m_cells[size_t(cell)];
        m_entries[c.begin + c.size] = entry;
        return int32_t(c.size++);
    }
    uint32_t Allocate(uint32_t sizeClass);
    void Free(uint32_t begin, uint32_t sizeClass);
    static uint32_t ClassFor(uint32_t count);

    std::vector<Cell> m_cells;
    std::vector<Entry> m_entries;  // all blocks, used or free
    uint32_t m_freeHead[kClasses]; // first free block of each class, or kNone; the next is in its first id
    static constexpr uint32_t kNone = 0xffffffffu;
};

} // namespace quadphase
