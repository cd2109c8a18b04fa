// SPDX-License-Identifier: MIT
// Gathers the occupied cells through quadphase's read-only accessors (GetQuadtree, GetPool, GetPyramid).
#include "quadtree_overlay.h"

#include <algorithm>
#include <utility>

#if QUADPHASE_VARIANT_QUADPHASE
#include "box2d_internal.h"
#include "quadphase/box2d.h"
#include "quadtree_broad_phase.h"
#include "row_major.h"
#endif

namespace quadphase::scene_cli
{

Overlay CollectOverlay(const b2World& world)
{
    Overlay overlay;
#if QUADPHASE_VARIANT_QUADPHASE
    const QuadtreeBroadPhase& tree = GetQuadtree(world);
    const Pyramid& pyramid = tree.GetPyramid();
    const ProxyPool& pool = tree.GetPool();
    overlay.available = true;
    overlay.depth = pyramid.Depth();
    overlay.cellsPerLevel.assign(size_t(overlay.depth) + 1, 0);
    overlay.proxiesPerLevel.assign(size_t(overlay.depth) + 1, 0);

    // Walking the proxies, not the cells: a deep pyramid has up to 4^15 cells, most of them empty.
    std::vector<std::pair<int64_t, int32_t>> keys; // (level << 32 | index, 1)
    keys.reserve(size_t(pool.LiveCount()));
    for (ProxyId id = 0; id < pool.IdBound(); ++id)
    {
        if (!pool.IsLive(id))
        {
            continue;
        }
        int level = 0;
        int32_t index = 0;
        pyramid.Place(pool.Fat(id), level, index);
        keys.emplace_back((int64_t(level) << 32) | int64_t(uint32_t(index)), 1);
    }
    std::sort(keys.begin(), keys.end());

    const Box bounds = pyramid.Bounds();
    const float side = bounds.maxX - bounds.minX;
    for (size_t i = 0; i < keys.size();)
    {
        size_t j = i;
        while (j < keys.size() && keys[j].first == keys[i].first)
        {
            ++j;
        }
        const int level = int(keys[i].first >> 32);
        const int32_t index = int32_t(keys[i].first & 0xffffffff);
        const int32_t levelSide = LevelSide(level);
        OverlayCell cell;
        cell.level = level;
        cell.side = side / float(levelSide);
        cell.x = bounds.minX + cell.side * float(index % levelSide);
        cell.y = bounds.minY + cell.side * float(index / levelSide);
        cell.count = int32_t(j - i);
        overlay.cells.push_back(cell);
        overlay.cellsPerLevel[size_t(level)] += 1;
        overlay.proxiesPerLevel[size_t(level)] += cell.count;
        overlay.largestCount = std::max(overlay.largestCount, cell.count);
        i = j;
    }
#else
    (void)world;
#endif
    return overlay;
}

} // namespace quadphase::scene_cli
