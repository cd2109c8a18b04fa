// SPDX-License-Identifier: MIT
// Counters describing a broadphase's current shape and its recent work.
#pragma once

#include <cstdint>
#include <vector>

#include "quadphase/box.h"

namespace quadphase
{

/// A snapshot of the broadphase. Cheap to take except `occupiedCells`, `largestCell` and `proxiesPerLevel`,
/// which walk the pyramid (O(cells)).
struct Stats
{
    int depth = 0;         ///< pyramid levels are 0..depth
    Box bounds{};          ///< region covered by the pyramid
    float leafSize = 0.0f; ///< side of a deepest-level cell, world units
    int32_t proxyCount = 0;
    int32_t outsideCount = 0;  ///< proxies whose fat box is not inside the bounds (clamped to a border)
    int64_t occupiedCells = 0; ///< cells holding at least one proxy
    int64_t largestCell = 0;   ///< proxies in the most crowded cell
    std::vector<int32_t> proxiesPerLevel; ///< index = level
    int64_t memoryBytes = 0;              ///< heap bytes held by the broadphase (capacity, not size)
    int64_t rebuilds = 0; ///< times the pyramid was rebuilt (automatic re-tuning, ShiftOrigin, Configure)

    // Work counters since creation (or since ResetCounters()).
    int64_t updatePairsCalls = 0;
    int64_t parallelCalls = 0;  ///< FindPairs calls that ran an OpenMP parallel region
    int64_t serialByChoice = 0; ///< FindPairs calls run serially because parallel ones measured slower
    int64_t pairsReported = 0;  ///< pairs handed to the caller
    int64_t lastPairs = 0;      ///< pairs of the last UpdatePairs
    int64_t proxiesQueried = 0; ///< moved/touched proxies whose neighbourhoods were searched
    int64_t reinserts = 0;      ///< times a proxy changed cell
    double updateSeconds = 0.0; ///< time in MoveProxy/CreateProxy/DestroyProxy grid maintenance
    double pairSeconds = 0.0;   ///< time in pair generation (UpdatePairs without the caller's callbacks)
};

} // namespace quadphase
