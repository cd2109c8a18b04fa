// SPDX-License-Identifier: MIT
// The CellStore (cell_store.h): Compact keeps every cell's entries in their slots, lays the blocks out in
// cell order with the smallest class each, and reuses the array it has rather than allocating a new one.
#include <vector>

#include <catch2/catch.hpp>

#include "cell_store.h"

#include "test_support.h"

using namespace quadphase;
using namespace qptest;

namespace
{

std::vector<std::vector<ProxyId>> Contents(const CellStore& store)
{
    std::vector<std::vector<ProxyId>> cells(size_t(store.CellCount()));
    for (int32_t cell = 0; cell < store.CellCount(); ++cell)
    {
        for (int32_t slot = 0; slot < store.Size(cell); ++slot)
        {
            cells[size_t(cell)].push_back(store.Data(cell)[slot].id);
        }
    }
    return cells;
}

} // namespace

TEST_CASE("CellStore::Compact keeps the entries, orders the blocks by cell and reuses the array", "[pyramid]")
{
    Rng rng(777u);
    for (int trial = 0; trial < 20; ++trial)
    {
        INFO("trial " << trial);
        const int32_t cellCount = UniformInt(rng, 1, 300);
        CellStore store;
        store.Reset(cellCount);
        // Grow cells, empty some, grow others: blocks move to larger classes and leave free blocks behind.
        ProxyId next = 0;
        for (int op = 0; op < 4000; ++op)
        {
            const int32_t cell = UniformInt(rng, 0, cellCount - 1);
            if (store.Size(cell) > 0 && Chance(rng, 0.45))
            {
                store.SwapRemove(cell, UniformInt(rng, 0, store.Size(cell) - 1));
            }
            else
            {
                const float x = float(next % 97);
                store.Push(cell, Entry{Box{x, 0.0f, x + 1.0f, 1.0f}, next++});
            }
        }
        REQUIRE(store.Validate() == "");
        const auto before = Contents(store);
        const int64_t bytes = store.MemoryBytes();

        store.Compact();

        REQUIRE(store.Validate() == "");
        REQUIRE(Contents(store) == before); // same entries, same slots
        // The array is reused: a compaction that allocated a new, tighter array would report fewer bytes.
        REQUIRE(store.MemoryBytes() == bytes);
        const Entry* end = nullptr;
        for (int32_t cell = 0; cell < cellCount; ++cell)
        {
            const int32_t size = store.Size(cell);
            if (size == 0)
            {
                continue;
            }
            // Cell order, no gaps: each block starts where the previous one ends.
            if (end != nullptr)
            {
                REQUIRE(store.Data(cell) == end);
            }
            int32_t capacity = 1;
            while (capacity < size)
            {
                capacity *= 2;
            }
            // The smallest class that holds the entries: full exactly when the size is a power of two.
            REQUIRE(store.HasRoom(cell) == (capacity != size));
            end = store.Data(cell) + capacity;
            REQUIRE(store.Data(cell)->box.minX == float(store.Data(cell)->id % 97)); // the box came along
        }
    }
}
