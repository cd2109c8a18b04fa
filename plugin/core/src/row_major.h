// SPDX-License-Identifier: MIT
// Cell indexing of the static quadtree (a complete pyramid of levels 0..depth).
//
// Level l is a 2^l x 2^l grid. Within a level, cells are numbered in row-major order:
//     index = y * 2^l + x      (x = column, y = row, both from 0)
// so the left/right neighbours are index -/+ 1 and the neighbours below/above are index -/+ 2^l. The parent of
// (x, y) at level l is (x/2, y/2) at level l-1 and its children are (2x + i, 2y + j), i, j in {0, 1}, at level
// l+1: computed, never searched. All levels live in one array; level l starts at LevelOffset(l) = (4^l - 1) / 3.
//
// The paper this design comes from numbered a level's cells in creation order (depth-first, four children at a
// time; its Figure 1), which is the Morton (Z-order) code with the row bits above the column bits:
//     creation = 2 * spread(row) + spread(column),   spread(b3 b2 b1 b0) = b3 0 b2 0 b1 0 b0
// and re-indexed them to row-major order for O(1) neighbour look-up. PaperCreationIndex gives that mapping.
#pragma once

#include <cstdint>

namespace quadphase
{

/// Number of cells along one side of level `level`.
constexpr int32_t LevelSide(int level)
{
    return int32_t(1) << level;
}

/// Index of the first cell of `level` in the array that holds all levels: (4^level - 1) / 3.
constexpr int32_t LevelOffset(int level)
{
    // In 64 bits: PyramidCellCount(15) needs LevelOffset(16), whose 4^16 overflows 32 bits (the result fits).
    return int32_t(((int64_t(1) << (2 * level)) - 1) / 3);
}

/// Total number of cells of a pyramid with levels 0..depth.
constexpr int32_t PyramidCellCount(int depth)
{
    return LevelOffset(depth + 1);
}

/// Row-major index of cell (x, y) within `level`.
constexpr int32_t RowMajorIndex(int level, int32_t x, int32_t y)
{
    return y * LevelSide(level) + x;
}

/// Cell containing (x, y)'s parent cell, as row-major index within `level - 1`. Requires level >= 1.
/// (Single return statements, here and below: installed headers are C++11.)
constexpr int32_t ParentIndex(int level, int32_t index)
{
    return RowMajorIndex(level - 1, (index % LevelSide(level)) >> 1, (index / LevelSide(level)) >> 1);
}

/// Row-major index within `level + 1` of child (i, j), i, j in {0, 1}, of cell `index` of `level`.
constexpr int32_t ChildIndex(int level, int32_t index, int i, int j)
{
    return RowMajorIndex(level + 1, 2 * (index % LevelSide(level)) + i, 2 * (index / LevelSide(level)) + j);
}

/// One step of SpreadBits: (v | v << shift) & mask.
constexpr uint32_t SpreadStep(uint32_t v, int shift, uint32_t mask)
{
    return (v | (v << shift)) & mask;
}

/// Spreads the bits of v apart: bit k moves to bit 2k (the low 16 bits of v).
constexpr uint32_t SpreadBits(uint32_t v)
{
    return SpreadStep(
        SpreadStep(SpreadStep(SpreadStep(v & 0x0000ffffu, 8, 0x00ff00ffu), 4, 0x0f0f0f0fu), 2, 0x33333333u),
        1, 0x55555555u);
}

/// The paper's creation-order index (its Figure 1) of the cell at `row`, `column` (both from 0).
constexpr uint32_t PaperCreationIndex(uint32_t row, uint32_t column)
{
    return 2u * SpreadBits(row) + SpreadBits(column);
}

} // namespace quadphase
