// The fat-box policy of Box2D 2.4.1's b2DynamicTree, reproduced operation for operation so that the stored
// boxes are bit-identical to the stock tree's. Contacts live and die on TestOverlap of these boxes, so any
// difference here would change the simulation.
#pragma once

#include "quadphase/box.h"

namespace quadphase
{

/// Margins in world units. Box2D's values are b2_aabbExtension (0.1 m) and b2_aabbMultiplier (4).
struct FatPolicy
{
    float extension = 0.1f;  ///< grown on every side of the shape's box
    float multiplier = 4.0f; ///< displacement prediction: the box is stretched by multiplier x displacement
};

/// Fat box of a newly created proxy: the shape's box grown by `extension` on every side.
inline Box FattenNew(const FatPolicy& policy, const Box& tight)
{
    const float r = policy.extension;
    return Box{tight.minX - r, tight.minY - r, tight.maxX + r, tight.maxY + r};
}

/// Decides whether a moved shape needs a new fat box, as b2DynamicTree::MoveProxy does.
/// Returns false and leaves `stored` alone when the stored fat box still contains `tight` and is not too large
/// (it lies inside the new fat box grown by a further 4 x extension). Otherwise writes the new fat box
/// (grown by `extension`, then stretched by multiplier x displacement in the direction of motion) and returns true.
inline bool Refatten(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    const float r = policy.extension;
    Box fat{tight.minX - r, tight.minY - r, tight.maxX + r, tight.maxY + r};

    const float dx = policy.multiplier * displacement.x;
    const float dy = policy.multiplier * displacement.y;
    // Written as selects: the side that does not move is selected unchanged, as in Box2D's if/else, so the results
    // are the same floats with any compiler and flags. (An addition of "-0.0f" for that side was tried: exact in
    // IEEE arithmetic, but clang -O1 then produced a different sign of zero in one fuzzed case.)
    fat.minX = dx < 0.0f ? fat.minX + dx : fat.minX;
    fat.maxX = dx < 0.0f ? fat.maxX : fat.maxX + dx;
    fat.minY = dy < 0.0f ? fat.minY + dy : fat.minY;
    fat.maxY = dy < 0.0f ? fat.maxY : fat.maxY + dy;

    // Keep the stored box when it still contains the shape's box and lies inside the new fat box grown by a
    // further 4 x extension. The eight comparisons are combined with & rather than &&: whether a body's box
    // still fits is close to random from one body to the next, so short-circuit branches mispredict often.
    const float h = 4.0f * r;
    const Box huge{fat.minX - h, fat.minY - h, fat.maxX + h, fat.maxY + h};
    const int keep = int(stored.minX <= tight.minX) & int(stored.minY <= tight.minY) &
                     int(tight.maxX <= stored.maxX) & int(tight.maxY <= stored.maxY) & int(huge.minX <= stored.minX) &
                     int(huge.minY <= stored.minY) & int(stored.maxX <= huge.maxX) & int(stored.maxY <= huge.maxY);
    if (keep != 0)
    {
        return false;
    }
    stored = fat;
    return true;
}

} // namespace quadphase
