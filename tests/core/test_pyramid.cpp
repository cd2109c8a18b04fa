// SPDX-License-Identifier: MIT
// The Pyramid (pyramid.h): the placement rule, Visit's "superset, each once" promise, and Validate after
// random insert/update/remove sequences.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

#include <catch2/catch.hpp>

#include "pyramid.h"
#include "row_major.h"

#include "test_support.h"

using namespace quadphase;
using namespace qptest;

namespace
{

// The coordinate function documented in pyramid.h: subtract the origin, multiply by the inverse leaf size,
// clamp into [0, 2^depth - 1], truncate; NaN maps to 0.
struct RefCoords
{
    float originX, originY, invLeaf, maxCoord;

    RefCoords(float ox, float oy, float side, int depth) : originX(ox), originY(oy)
    {
        const float leaf = side / float(LevelSide(depth));
        invLeaf = 1.0f / leaf;
        maxCoord = float(LevelSide(depth) - 1);
    }

    int32_t Coord(float v, float origin) const
    {
        float t = (v - origin) * invLeaf;
        if (std::isnan(t) || t < 0.0f)
        {
            t = 0.0f;
        }
        if (t > maxCoord)
        {
            t = maxCoord;
        }
        return int32_t(t);
    }
    int32_t X(float v) const { return Coord(v, originX); }
    int32_t Y(float v) const { return Coord(v, originY); }
};

/// The deepest level at which the cells of the min and max corners are equal or adjacent on both axes.
int ReferenceLevel(const RefCoords& rc, int depth, const Box& b)
{
    const int32_t x0 = rc.X(b.minX), y0 = rc.Y(b.minY), x1 = rc.X(b.maxX), y1 = rc.Y(b.maxY);
    for (int level = depth; level >= 0; --level)
    {
        const int s = depth - level;
        const int32_t dx = (x1 >> s) - (x0 >> s);
        const int32_t dy = (y1 >> s) - (y0 >> s);
        if (dx <= 1 && dx >= -1 && dy <= 1 && dy >= -1)
        {
            return level;
        }
    }
    return -1; // never: at level 0 every coordinate is 0
}

struct Region
{
    float originX, originY, side;
    int depth;
};

Region RandomRegion(Rng& rng, int depth)
{
    Region r;
    r.depth = depth;
    switch (UniformInt(rng, 0, 3))
    {
    case 0:
        r.originX = -100.0f;
        r.originY = -100.0f;
        r.side = 200.0f;
        break;
    case 1:
        r.originX = Uniform(rng, -1000.0f, 1000.0f);
        r.originY = Uniform(rng, -1000.0f, 1000.0f);
        r.side = LogUniform(rng, -1.0f, 3.0f);
        break;
    case 2:
        r.originX = 0.0f;
        r.originY = 0.0f;
        r.side = 1.0f;
        break;
    default:
        r.originX = Uniform(rng, -1e5f, 1e5f);
        r.originY = Uniform(rng, -1e5f, 1e5f);
        r.side = LogUniform(rng, 2.0f, 5.0f);
        break;
    }
    return r;
}

/// Runs body(pyramid, region, trial) for trial 0 .. trials - 1, each on a fresh pyramid over a random region of
/// depth trial % depths.
template <typename Body>
void ForRandomPyramids(Rng& rng, int trials, int depths, Body body)
{
    for (int trial = 0; trial < trials; ++trial)
    {
        const Region r = RandomRegion(rng, trial % depths);
        Pyramid pyramid;
        pyramid.Reset(r.originX, r.originY, r.side, r.depth);
        body(pyramid, r, trial);
    }
}

/// A coordinate on a cell border of a random level (computed in float, so it may sit just beside the border).
float BorderCoord(Rng& rng, float origin, float side, int depth)
{
    const int level = UniformInt(rng, 0, depth);
    const int32_t k = UniformInt(rng, -1, LevelSide(level) + 1);
    return origin + float(k) * (side / float(LevelSide(level)));
}

/// Boxes of every awkward kind relative to a region.
Box RandomPlacementBox(Rng& rng, const Region& r)
{
    const float cx = r.originX + 0.5f * r.side;
    const float cy = r.originY + 0.5f * r.side;
    const float h = 0.5f * r.side;
    switch (UniformInt(rng, 0, 8))
    {
    case 0: // ordinary, inside
    {
        const float s = r.side * LogUniform(rng, -4.0f, -0.3f);
        const float x = Uniform(rng, r.originX, r.originX + r.side - s);
        const float y = Uniform(rng, r.originY, r.originY + r.side - s);
        return Box{x, y, x + s * Uniform(rng, 0.2f, 1.0f), y + s * Uniform(rng, 0.2f, 1.0f)};
    }
    case 1: // larger than the whole region
        return CentredBox(cx + Uniform(rng, -h, h), cy + Uniform(rng, -h, h), h * LogUniform(rng, 0.0f, 3.0f),
                          h * LogUniform(rng, 0.0f, 3.0f));
    case 2: // outside
    {
        const float d = r.side * LogUniform(rng, 0.0f, 2.0f);
        const float x = Chance(rng, 0.5) ? cx + (Chance(rng, 0.5) ? d : -d) : cx + Uniform(rng, -h, h);
        const float y = Chance(rng, 0.5) ? cy + (Chance(rng, 0.5) ? d : -d) : cy + Uniform(rng, -h, h);
        const float s = r.side * LogUniform(rng, -3.0f, 0.0f);
        return Box{x, y, x + s, y + s};
    }
    case 3: // a point
    {
        const float x = Uniform(rng, r.originX - h, r.originX + r.side + h);
        const float y = Uniform(rng, r.originY - h, r.originY + r.side + h);
        return Box{x, y, x, y};
    }
    case 4: // a point on a cell corner
    {
        const float x = BorderCoord(rng, r.originX, r.side, r.depth);
        const float y = BorderCoord(rng, r.originY, r.side, r.depth);
        return Box{x, y, x, y};
    }
    case 5: // a segment along a border
    {
        const float x = BorderCoord(rng, r.originX, r.side, r.depth);
        const float y0 = Uniform(rng, r.originY, r.originY + r.side);
        const float y1 = std::max(y0, BorderCoord(rng, r.originY, r.side, r.depth));
        return Chance(rng, 0.5) ? Box{x, y0, x, y1}
                                : Box{y0 - r.originY + r.originX, x - r.originX + r.originY,
                                      y1 - r.originY + r.originX, x - r.originX + r.originY};
    }
    case 6: // all four sides on (possibly different levels') cell borders: straddles borders and corners
    {
        float x0 = BorderCoord(rng, r.originX, r.side, r.depth);
        float x1 = BorderCoord(rng, r.originX, r.side, r.depth);
        float y0 = BorderCoord(rng, r.originY, r.side, r.depth);
        float y1 = BorderCoord(rng, r.originY, r.side, r.depth);
        return Box{std::min(x0, x1), std::min(y0, y1), std::max(x0, x1), std::max(y0, y1)};
    }
    case 7: // small box around a cell corner
    {
        const float x = BorderCoord(rng, r.originX, r.side, r.depth);
        const float y = BorderCoord(rng, r.originY, r.side, r.depth);
        const float e = r.side * LogUniform(rng, -7.0f, -2.0f);
        return Box{x - e * Uniform(rng, 0.0f, 1.0f), y - e * Uniform(rng, 0.0f, 1.0f),
                   x + e * Uniform(rng, 0.0f, 1.0f), y + e * Uniform(rng, 0.0f, 1.0f)};
    }
    default: // enormous and infinite extents
    {
        const float inf = std::numeric_limits<float>::infinity();
        const float big = std::numeric_limits<float>::max();
        const float vals[] = {-inf, -big, -1e30f, cx, 1e30f, big, inf};
        float a = vals[UniformInt(rng, 0, 6)], b = vals[UniformInt(rng, 0, 6)];
        float c = vals[UniformInt(rng, 0, 6)], d = vals[UniformInt(rng, 0, 6)];
        return Box{std::min(a, b), std::min(c, d), std::max(a, b), std::max(c, d)};
    }
    }
}

bool InsideRegion(const Region& r, const Box& b)
{
    return r.originX <= b.minX && r.originY <= b.minY && b.maxX <= r.originX + r.side &&
           b.maxY <= r.originY + r.side;
}

} // namespace

TEST_CASE("Pyramid::Place picks the deepest level where the corners' cells are equal or adjacent",
          "[pyramid]")
{
    Rng rng(20240601u);
    int levelsSeen[11] = {};
    int checked = 0;
    ForRandomPyramids(rng, 120, 11, [&](Pyramid& pyramid, const Region& r, int trial) {
        const int depth = r.depth; // 0..10
        const RefCoords rc(r.originX, r.originY, r.side, depth);
        REQUIRE(pyramid.Depth() == depth);
        for (int i = 0; i < 400; ++i)
        {
            const Box b = RandomPlacementBox(rng, r);
            int level = -1;
            int32_t index = -1;
            pyramid.Place(b, level, index);
            INFO("trial " << trial << " depth " << depth << " region (" << r.originX << ", " << r.originY
                          << ") side " << r.side << " box " << Str(b));
            REQUIRE(level >= 0);
            REQUIRE(level <= depth);
            REQUIRE(index >= 0);
            REQUIRE(index < LevelSide(level) * LevelSide(level));

            const int s = depth - level;
            const int32_t x0 = rc.X(b.minX) >> s, y0 = rc.Y(b.minY) >> s;
            const int32_t x1 = rc.X(b.maxX) >> s, y1 = rc.Y(b.maxY) >> s;
            // stored in the cell of its min corner, its max corner in the same or the next cell
            REQUIRE(index == RowMajorIndex(level, x0, y0));
            REQUIRE((x1 - x0 == 0 || x1 - x0 == 1));
            REQUIRE((y1 - y0 == 0 || y1 - y0 == 1));
            // and no deeper level would do
            REQUIRE(level == ReferenceLevel(rc, depth, b));
            if (level < depth)
            {
                const int t = s - 1;
                const int32_t dx = (rc.X(b.maxX) >> t) - (rc.X(b.minX) >> t);
                const int32_t dy = (rc.Y(b.maxY) >> t) - (rc.Y(b.minY) >> t);
                REQUIRE((dx > 1 || dy > 1));
            }
            // Geometric check for boxes inside the region: the box lies within cells x0 and x0 + 1 (and y0,
            // y0 + 1) of its level, up to float rounding of the cell borders.
            if (InsideRegion(r, b))
            {
                const double cell = double(r.side) / double(LevelSide(level));
                const double tol =
                    1e-5 * (std::fabs(double(r.originX)) + std::fabs(double(r.originY)) + r.side);
                REQUIRE(double(b.minX) >= double(r.originX) + double(x0) * cell - tol);
                REQUIRE(double(b.maxX) <= double(r.originX) + double(x0 + 2) * cell + tol);
                REQUIRE(double(b.minY) >= double(r.originY) + double(y0) * cell - tol);
                REQUIRE(double(b.maxY) <= double(r.originY) + double(y0 + 2) * cell + tol);
            }
            levelsSeen[level] += 1;
            ++checked;
        }
    });
    REQUIRE(checked == 120 * 400);
    // the boxes exercised every level
    for (int level = 0; level <= 10; ++level)
    {
        CAPTURE(level);
        CHECK(levelsSeen[level] > 0);
    }
}

TEST_CASE("Pyramid::Place handles NaN coordinates (cell 0) and inverted boxes without crashing", "[pyramid]")
{
    const float nan = std::numeric_limits<float>::quiet_NaN();
    Pyramid pyramid;
    pyramid.Reset(-8.0f, -8.0f, 16.0f, 4);
    int level = -1;
    int32_t index = -1;
    pyramid.Place(Box{nan, nan, nan, nan}, level, index);
    REQUIRE(level == 4);
    REQUIRE(index == 0);
    pyramid.Place(Box{5.0f, 5.0f, -5.0f, -5.0f}, level, index);
    REQUIRE(level >= 0);
    REQUIRE(level <= 4);
}

TEST_CASE("Pyramid::Visit visits every overlapping entry exactly once, and stops when told", "[pyramid]")
{
    Rng rng(777u);
    ForRandomPyramids(rng, 60, 9, [&](Pyramid& pyramid, const Region& r, int trial) {
        const int depth = r.depth;
        std::vector<Box> boxes;
        const int n = UniformInt(rng, 1, 300);
        for (int id = 0; id < n; ++id)
        {
            Box b = RandomPlacementBox(rng, r);
            boxes.push_back(b);
            pyramid.Insert(id, b);
        }
        REQUIRE(pyramid.Validate() == "");
        for (int q = 0; q < 60; ++q)
        {
            const Box query = RandomPlacementBox(rng, r);
            INFO("trial " << trial << " depth " << depth << " query " << Str(query));
            std::vector<int> visits(size_t(n), 0);
            int total = 0;
            bool badEntry = false;
            pyramid.Visit(query, [&](const Entry& e) {
                if (e.id < 0 || e.id >= n || !SameBox(e.box, boxes[size_t(e.id)]))
                {
                    badEntry = true;
                    return true;
                }
                visits[size_t(e.id)] += 1;
                ++total;
                return true;
            });
            REQUIRE_FALSE(badEntry);
            for (int id = 0; id < n; ++id)
            {
                if (visits[size_t(id)] > 1 || (Overlaps(boxes[size_t(id)], query) && visits[size_t(id)] != 1))
                {
                    FAIL("box " << id << " " << Str(boxes[size_t(id)]) << " visited " << visits[size_t(id)]
                                << " times");
                }
            }
            if (total > 0)
            {
                int calls = 0;
                pyramid.Visit(query, [&](const Entry&) {
                    ++calls;
                    return false;
                });
                REQUIRE(calls == 1);
            }
        }
    });
}

TEST_CASE("Pyramid stays valid through random insert, update and remove sequences", "[pyramid]")
{
    Rng rng(4242u);
    ForRandomPyramids(rng, 40, 9, [&](Pyramid& pyramid, const Region& r, int trial) {
        const int depth = r.depth;
        std::map<ProxyId, Box> stored;
        ProxyId nextId = 0;
        std::vector<ProxyId> freeIds;
        for (int op = 0; op < 1500; ++op)
        {
            INFO("trial " << trial << " depth " << depth << " op " << op);
            const int roll = UniformInt(rng, 0, 99);
            if (stored.empty() || roll < 35)
            {
                ProxyId id;
                if (!freeIds.empty() && Chance(rng, 0.7))
                {
                    id = freeIds.back();
                    freeIds.pop_back();
                }
                else
                {
                    id = nextId;
                    nextId += ProxyId(UniformInt(rng, 1, 3)); // leave holes in the id range
                }
                const Box b = RandomPlacementBox(rng, r);
                pyramid.Insert(id, b);
                stored[id] = b;
            }
            else
            {
                auto it = stored.begin();
                std::advance(it, UniformInt(rng, 0, int(stored.size()) - 1));
                const ProxyId id = it->first;
                if (roll < 50)
                {
                    pyramid.Remove(id);
                    stored.erase(it);
                    freeIds.push_back(id);
                }
                else
                {
                    Box b = RandomPlacementBox(rng, r);
                    if (Chance(rng, 0.5))
                    {
                        // a small move, often staying in the same cell
                        const float d = r.side * LogUniform(rng, -6.0f, -2.0f);
                        b = Translate(it->second, Vec2{Uniform(rng, -d, d), Uniform(rng, -d, d)});
                    }
                    int oldLevel, newLevel;
                    int32_t oldIndex, newIndex;
                    pyramid.Place(it->second, oldLevel, oldIndex);
                    pyramid.Place(b, newLevel, newIndex);
                    const bool changed = pyramid.Update(id, b);
                    REQUIRE(changed == (oldLevel != newLevel || oldIndex != newIndex));
                    it->second = b;
                }
            }
            if (op % 25 == 0 || op > 1450)
            {
                REQUIRE(pyramid.Validate() == "");
                int32_t total = 0;
                for (int level = 0; level <= depth; ++level)
                {
                    total += pyramid.LevelCount(level);
                }
                REQUIRE(total == int32_t(stored.size()));
                int32_t outside = 0;
                for (const auto& kv : stored)
                {
                    int level;
                    int32_t index;
                    pyramid.Place(kv.second, level, index);
                    REQUIRE(pyramid.LevelOf(kv.first) == level);
                    REQUIRE(pyramid.CellCount(level, index) >= 1);
                    outside += InsideRegion(r, kv.second) ? 0 : 1;
                }
                REQUIRE(pyramid.OutsideCount() == outside);
                int64_t occupied = 0, largest = 0;
                pyramid.CountOccupancy(occupied, largest);
                REQUIRE(occupied <= int64_t(stored.size()));
                REQUIRE(largest <= int64_t(stored.size()));
                REQUIRE((stored.empty() || occupied >= 1));
            }
        }
        // Reset empties it
        pyramid.Reset(r.originX, r.originY, r.side, depth);
        REQUIRE(pyramid.Validate() == "");
        for (int level = 0; level <= depth; ++level)
        {
            REQUIRE(pyramid.LevelCount(level) == 0);
        }
        REQUIRE(pyramid.OutsideCount() == 0);
    });
}
