// SPDX-License-Identifier: MIT
// Cell indexing (row_major.h): row-major indices, level offsets, neighbours, parents and children, and the
// paper's creation-order numbering (its Figure 1) with the re-indexing to row-major order.
#include <cstdint>
#include <set>
#include <vector>

#include <catch2/catch.hpp>

#include "row_major.h"

using namespace quadphase;

namespace
{

// Figure 1 of the paper (/work/shared/reference/parallel-collision-detection-paper.md), copied verbatim: the
// index each leaf box of a depth-4 quadtree gets when it is created, laid out as the boxes are on screen.
// clang-format off
const int kFigure1[16][16] = {
    {  0,   1,   4,   5,  16,  17,  20,  21,  64,  65,  68,  69,  80,  81,  84,  85},
    {  2,   3,   6,   7,  18,  19,  22,  23,  66,  67,  70,  71,  82,  83,  86,  87},
    {  8,   9,  12,  13,  24,  25,  28,  29,  72,  73,  76,  77,  88,  89,  92,  93},
    { 10,  11,  14,  15,  26,  27,  30,  31,  74,  75,  78,  79,  90,  91,  94,  95},
    { 32,  33,  36,  37,  48,  49,  52,  53,  96,  97, 100, 101, 112, 113, 116, 117},
    { 34,  35,  38,  39,  50,  51,  54,  55,  98,  99, 102, 103, 114, 115, 118, 119},
    { 40,  41,  44,  45,  56,  57,  60,  61, 104, 105, 108, 109, 120, 121, 124, 125},
    { 42,  43,  46,  47,  58,  59,  62,  63, 106, 107, 110, 111, 122, 123, 126, 127},
    {128, 129, 132, 133, 144, 145, 148, 149, 192, 193, 196, 197, 208, 209, 212, 213},
    {130, 131, 134, 135, 146, 147, 150, 151, 194, 195, 198, 199, 210, 211, 214, 215},
    {136, 137, 140, 141, 152, 153, 156, 157, 200, 201, 204, 205, 216, 217, 220, 221},
    {138, 139, 142, 143, 154, 155, 158, 159, 202, 203, 206, 207, 218, 219, 222, 223},
    {160, 161, 164, 165, 176, 177, 180, 181, 224, 225, 228, 229, 240, 241, 244, 245},
    {162, 163, 166, 167, 178, 179, 182, 183, 226, 227, 230, 231, 242, 243, 246, 247},
    {168, 169, 172, 173, 184, 185, 188, 189, 232, 233, 236, 237, 248, 249, 252, 253},
    {170, 171, 174, 175, 186, 187, 190, 191, 234, 235, 238, 239, 250, 251, 254, 255},
};
// clang-format on

} // namespace

TEST_CASE("LevelSide, LevelOffset and PyramidCellCount", "[row_major]")
{
    int32_t offset = 0;
    for (int level = 0; level <= 15; ++level)
    {
        CAPTURE(level);
        REQUIRE(LevelSide(level) == (int32_t(1) << level));
        REQUIRE(LevelOffset(level) == offset);
        REQUIRE(PyramidCellCount(level) == offset + LevelSide(level) * LevelSide(level));
        offset += LevelSide(level) * LevelSide(level);
    }
    STATIC_REQUIRE(LevelOffset(0) == 0);
    STATIC_REQUIRE(LevelOffset(1) == 1);
    STATIC_REQUIRE(LevelOffset(2) == 5);
    STATIC_REQUIRE(LevelOffset(3) == 21);
    STATIC_REQUIRE(PyramidCellCount(0) == 1);
    STATIC_REQUIRE(PyramidCellCount(4) == 341);
    STATIC_REQUIRE(PyramidCellCount(12) == 22369621);
}

TEST_CASE("RowMajorIndex numbers a level in reading order; neighbours are +-1 and +-side", "[row_major]")
{
    for (int level = 0; level <= 6; ++level)
    {
        const int32_t side = LevelSide(level);
        std::vector<int> seen(size_t(side * side), 0);
        int32_t expected = 0;
        for (int32_t y = 0; y < side; ++y)
        {
            for (int32_t x = 0; x < side; ++x)
            {
                CAPTURE(level, x, y);
                const int32_t i = RowMajorIndex(level, x, y);
                REQUIRE(i == expected++);
                REQUIRE(i / side == y);
                REQUIRE(i % side == x);
                seen[size_t(i)] += 1;
                if (x + 1 < side)
                {
                    REQUIRE(RowMajorIndex(level, x + 1, y) == i + 1);
                }
                if (x > 0)
                {
                    REQUIRE(RowMajorIndex(level, x - 1, y) == i - 1);
                }
                if (y + 1 < side)
                {
                    REQUIRE(RowMajorIndex(level, x, y + 1) == i + side);
                }
                if (y > 0)
                {
                    REQUIRE(RowMajorIndex(level, x, y - 1) == i - side);
                }
            }
        }
        for (int s : seen)
        {
            REQUIRE(s == 1);
        }
    }
    STATIC_REQUIRE(RowMajorIndex(4, 13, 2) == 45);
}

TEST_CASE("ParentIndex and ChildIndex round trip for every cell of levels 0..6", "[row_major]")
{
    for (int level = 0; level <= 6; ++level)
    {
        const int32_t side = LevelSide(level);
        std::vector<int> childSeen(size_t(4 * side * side), 0);
        for (int32_t index = 0; index < side * side; ++index)
        {
            const int32_t x = index % side;
            const int32_t y = index / side;
            CAPTURE(level, index);
            for (int j = 0; j < 2; ++j)
            {
                for (int i = 0; i < 2; ++i)
                {
                    const int32_t child = ChildIndex(level, index, i, j);
                    REQUIRE(child == RowMajorIndex(level + 1, 2 * x + i, 2 * y + j));
                    REQUIRE(child >= 0);
                    REQUIRE(child < 4 * side * side);
                    REQUIRE(ParentIndex(level + 1, child) == index);
                    childSeen[size_t(child)] += 1;
                }
            }
            if (level >= 1)
            {
                const int32_t parent = ParentIndex(level, index);
                REQUIRE(parent == RowMajorIndex(level - 1, x / 2, y / 2));
                // the cell is one of its parent's four children
                bool found = false;
                for (int j = 0; j < 2; ++j)
                {
                    for (int i = 0; i < 2; ++i)
                    {
                        found = found || ChildIndex(level - 1, parent, i, j) == index;
                    }
                }
                REQUIRE(found);
            }
        }
        // the children of a level are exactly the next level, each once
        for (int c : childSeen)
        {
            REQUIRE(c == 1);
        }
    }
}

TEST_CASE("SpreadBits moves bit k to bit 2k", "[row_major]")
{
    for (uint32_t v = 0; v < 65536; v += 7)
    {
        uint32_t expected = 0;
        for (int k = 0; k < 16; ++k)
        {
            expected |= ((v >> k) & 1u) << (2 * k);
        }
        REQUIRE(SpreadBits(v) == expected);
    }
    REQUIRE(SpreadBits(0xffffu) == 0x55555555u);
}

TEST_CASE("PaperCreationIndex: the paper's worked example (row 3, column 14 counted from 1 holds 89)",
          "[row_major]")
{
    STATIC_REQUIRE(PaperCreationIndex(2, 13) == 89u);
    REQUIRE(kFigure1[2][13] == 89);
}

TEST_CASE("PaperCreationIndex reproduces the paper's whole Figure 1", "[row_major]")
{
    std::set<int> values;
    for (uint32_t row = 0; row < 16; ++row)
    {
        for (uint32_t col = 0; col < 16; ++col)
        {
            CAPTURE(row, col);
            REQUIRE(PaperCreationIndex(row, col) == uint32_t(kFigure1[row][col]));
            values.insert(kFigure1[row][col]);
        }
    }
    // the figure numbers 256 distinct boxes 0..255
    REQUIRE(values.size() == 256u);
    REQUIRE(*values.begin() == 0);
    REQUIRE(*values.rbegin() == 255);
}

TEST_CASE("Re-indexing Figure 1 to row-major order gives 0..255 in reading order", "[row_major]")
{
    // The leaf vector in creation order: leafs[creation index] is the box at (row, col) of the figure.
    struct Leaf
    {
        int row;
        int col;
    };
    std::vector<Leaf> leafs(256, Leaf{-1, -1});
    for (int row = 0; row < 16; ++row)
    {
        for (int col = 0; col < 16; ++col)
        {
            leafs[size_t(kFigure1[row][col])] = Leaf{row, col};
        }
    }
    // The paper's linearize(): walk rows then columns, fetch the box through its creation index.
    std::vector<Leaf> temp;
    for (uint32_t i = 0; i < 16; ++i)
    {
        for (uint32_t j = 0; j < 16; ++j)
        {
            temp.push_back(leafs[PaperCreationIndex(i, j)]);
        }
    }
    for (int count = 0; count < 256; ++count)
    {
        CAPTURE(count);
        const Leaf& leaf = temp[size_t(count)];
        REQUIRE(leaf.row == count / 16);
        REQUIRE(leaf.col == count % 16);
        REQUIRE(RowMajorIndex(4, leaf.col, leaf.row) == count);
    }
}

TEST_CASE("PaperCreationIndex is a bijection at every level up to 2^8 x 2^8", "[row_major]")
{
    for (int level = 0; level <= 8; ++level)
    {
        const uint32_t side = uint32_t(LevelSide(level));
        std::vector<uint8_t> seen(size_t(side * side), 0);
        for (uint32_t row = 0; row < side; ++row)
        {
            for (uint32_t col = 0; col < side; ++col)
            {
                const uint32_t c = PaperCreationIndex(row, col);
                REQUIRE(c < side * side);
                REQUIRE(seen[c] == 0);
                seen[c] = 1;
                // creation order is depth-first: a cell's four children get four consecutive indices
                if (level >= 1)
                {
                    REQUIRE(c / 4 == PaperCreationIndex(row / 2, col / 2));
                }
            }
        }
    }
}
