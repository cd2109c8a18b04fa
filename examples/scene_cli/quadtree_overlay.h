// SPDX-License-Identifier: MIT
// The quadtree's occupied cells of a world, gathered for drawing (empty in the stock build).
#pragma once

#include <cstdint>
#include <vector>

#include "box2d/box2d.h"

namespace quadphase::scene_cli
{

/// One occupied cell: square [x, x + side) x [y, y + side) in world metres at pyramid level `level`.
struct OverlayCell
{
    float x = 0.0f;
    float y = 0.0f;
    float side = 0.0f;
    int level = 0;
    int32_t count = 0; ///< proxies stored in the cell
};

struct Overlay
{
    bool available = false;               ///< false in the stock build (no quadtree)
    int depth = 0;                        ///< levels 0..depth
    std::vector<OverlayCell> cells;       ///< coarse levels first
    std::vector<int32_t> cellsPerLevel;   ///< occupied cells, index = level
    std::vector<int32_t> proxiesPerLevel; ///< index = level
    int32_t largestCount = 0;             ///< proxies in the fullest cell
};

/// The occupied cells of `world`'s quadtree, from the proxies' current fat boxes and the pyramid's placement
/// rule (the cells the proxies are stored in once the pending re-placements of the last UpdatePairs are done;
/// after b2World::Step there are none). O(proxies log proxies). In the stock build: available = false.
Overlay CollectOverlay(const b2World& world);

} // namespace quadphase::scene_cli
