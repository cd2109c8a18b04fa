// SPDX-License-Identifier: MIT
// CellStore: block allocation in the shared entry array, compaction in cell order, and the invariant check.
#include "cell_store.h"

#include <algorithm>

namespace quadphase
{

void CellStore::Reset(int32_t cellCount)
{
    m_cells.clear();
    m_cells.shrink_to_fit();
    m_cells.resize(size_t(cellCount));
    m_entries.clear();
    m_entries.shrink_to_fit();
    std::fill(std::begin(m_freeHead), std::end(m_freeHead), kNone);
}

uint32_t CellStore::ClassFor(uint32_t count)
{
    uint32_t k = 0;
    while ((uint32_t(1) << k) < count)
    {
        ++k;
    }
    return k;
}

uint32_t CellStore::Allocate(uint32_t sizeClass)
{
    const uint32_t head = m_freeHead[sizeClass];
    if (head != kNone)
    {
        m_freeHead[sizeClass] = uint32_t(m_entries[head].id);
        return head;
    }
    const size_t begin = m_entries.size();
    const size_t end = begin + (size_t(1) << sizeClass);
    if (end > m_entries.capacity())
    {
        // Grow by an eighth rather than double: the array is most of the pyramid's memory, and Compact keeps
        // its capacity, so the overshoot stays (docs/design.md, "Memory").
        m_entries.reserve(std::max(end, m_entries.capacity() + m_entries.capacity() / 8));
    }
    m_entries.resize(end);
    return uint32_t(begin);
}

void CellStore::Free(uint32_t begin, uint32_t sizeClass)
{
    m_entries[begin].id = ProxyId(m_freeHead[sizeClass]);
    m_freeHead[sizeClass] = begin;
}

int32_t CellStore::Push(int32_t cell, const Entry& entry)
{
    if (!HasRoom(cell))
    {
        Cell& c = m_cells[size_t(cell)];
        const uint32_t newClass = c.sizeClass == kNoBlock ? 0 : c.sizeClass + 1;
        const uint32_t begin = Allocate(newClass); // may move m_entries
        if (c.sizeClass != kNoBlock)
        {
            std::copy_n(m_entries.begin() + c.begin, c.size, m_entries.begin() + begin);
            Free(c.begin, c.sizeClass);
        }
        c.begin = begin;
        c.sizeClass = newClass;
    }
    return PushNoGrow(cell, entry);
}

void CellStore::Compact()
{
    // The live entries go to a scratch array in cell order, then back into the same array, each cell's block
    // of the smallest class that holds them. The array keeps its capacity: a fresh array per compaction came
    // from the system as new pages every time (glibc serves large blocks by mmap), and faulting them in costs
    // more than the copy itself (docs/design.md, "Memory").
    size_t live = 0;
    for (const Cell& c : m_cells)
    {
        live += c.size;
    }
    std::vector<Entry> scratch(live);
    size_t at = 0;
    for (const Cell& c : m_cells)
    {
        at = size_t(std::copy_n(m_entries.begin() + c.begin, c.size, scratch.begin() + at) - scratch.begin());
    }
    // Each occupied cell's new block is no larger than the one it has, so the blocks fit in the current
    // array.
    uint32_t begin = 0;
    at = 0;
    for (Cell& c : m_cells)
    {
        if (c.size == 0)
        {
            c.begin = 0;
            c.sizeClass = kNoBlock;
            continue;
        }
        const uint32_t sizeClass = ClassFor(c.size);
        std::copy_n(scratch.begin() + at, c.size, m_entries.begin() + begin);
        at += c.size;
        c.begin = begin;
        c.sizeClass = sizeClass;
        begin += uint32_t(1) << sizeClass;
    }
    m_entries.resize(begin);
    if (m_entries.capacity() > 4 * size_t(begin) + 4096)
    {
        // Most proxies are gone: give the memory back (the steady state stays below 2x).
        m_entries.shrink_to_fit();
    }
    std::fill(std::begin(m_freeHead), std::end(m_freeHead), kNone);
}

int64_t CellStore::MemoryBytes() const
{
    return int64_t(m_cells.capacity() * sizeof(Cell) + m_entries.capacity() * sizeof(Entry));
}

std::string CellStore::Validate() const
{
    // Mark every slot owned by a cell or a free block; an overlap or an out-of-range block is a violation.
    // The owner's name is built only for a message: Validate() runs after every check of the fuzz targets.
    std::vector<uint8_t> owned(m_entries.size(), 0);
    auto claim = [&](uint32_t begin, uint32_t sizeClass, const char* kind, size_t which) -> std::string {
        const size_t end = size_t(begin) + (size_t(1) << sizeClass);
        if (end > m_entries.size())
        {
            return kind + std::to_string(which) + " has a block past the end of the array";
        }
        for (size_t i = begin; i < end; ++i)
        {
            if (owned[i]++ != 0)
            {
                return kind + std::to_string(which) + " has a block overlapping another one at slot " +
                       std::to_string(i);
            }
        }
        return {};
    };
    for (size_t i = 0; i < m_cells.size(); ++i)
    {
        const Cell& c = m_cells[i];
        if (c.sizeClass == kNoBlock)
        {
            if (c.size != 0)
            {
                return "cell " + std::to_string(i) + " holds entries but no block";
            }
            continue;
        }
        if (c.size > (uint32_t(1) << c.sizeClass))
        {
            return "cell " + std::to_string(i) + " holds more entries than its block";
        }
        std::string problem = claim(c.begin, c.sizeClass, "cell ", i);
        if (!problem.empty())
        {
            return problem;
        }
    }
    for (uint32_t k = 0; k < uint32_t(kClasses); ++k)
    {
        size_t steps = 0;
        for (uint32_t b = m_freeHead[k]; b != kNone; b = uint32_t(m_entries[b].id))
        {
            if (b >= m_entries.size() || ++steps > m_entries.size())
            {
                return "free list " + std::to_string(k) + " is broken";
            }
            std::string problem = claim(b, k, "free list ", k);
            if (!problem.empty())
            {
                return problem;
            }
        }
    }
    return {};
}

} // namespace quadphase
