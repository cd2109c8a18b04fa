// SPDX-License-Identifier: MIT
// The fat-box policy of Box2D 2.4.1's b2DynamicTree, reproduced operation for operation so that the stored
// boxes are bit-identical to the stock tree's. Contacts live and die on TestOverlap of these boxes, so any
// difference here would change the simulation.
#pragma once

#include <cstdint>
#include <cstring>

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

/// `condition ? a : b`, bit for bit, without a branch.
inline float SelectBits(bool condition, float a, float b)
{
    const uint32_t mask = uint32_t(0) - uint32_t(condition);
    uint32_t ia;
    uint32_t ib;
    std::memcpy(&ia, &a, sizeof(ia));
    std::memcpy(&ib, &b, sizeof(ib));
    const uint32_t r = (ia & mask) | (ib & ~mask);
    float out;
    std::memcpy(&out, &r, sizeof(out));
    return out;
}

/// `v < 0.0f` decided on the bits: negative, not zero, not NaN.
inline bool IsNegative(float v)
{
    uint32_t bits;
    std::memcpy(&bits, &v, sizeof(bits));
    return bits > 0x80000000u && bits <= 0xFF800000u; // -0 is 0x80000000; -infinity 0xFF800000, then NaNs
}

/// The fat box b2DynamicTree::MoveProxy would give a moved shape: its box grown by `extension`, then stretched by
/// multiplier x displacement in the direction of motion.
inline Box MovedFatBox(const FatPolicy& policy, const Box& tight, Vec2 displacement)
{
    const float r = policy.extension;
    Box fat{tight.minX - r, tight.minY - r, tight.maxX + r, tight.maxY + r};

    const float dx = policy.multiplier * displacement.x;
    const float dy = policy.multiplier * displacement.y;
    // Selects, as in Box2D's if/else: the side that does not move is selected unchanged, so the results are the
    // same floats with any compiler and flags. (An addition of "-0.0f" for that side was tried: exact in IEEE
    // arithmetic, but clang -O1 then produced a different sign of zero in one fuzzed case.) The selects copy bits
    // through a mask rather than use ?: on floats, which compilers turn into branches on the (random) direction.
    // The direction is tested on the bits: from a float compare, clang 14 (-O1 and up, Emscripten's too) rewrites
    // select(dx < 0, maxX, maxX + dx) as maxX + (dx <= 0 ? -0.0f : dx), which turns maxX = -0 into -0 instead of
    // +0 when dx = +0 (reached with extension -0; docs/design.md, "Platforms and floating point").
    const bool left = IsNegative(dx);
    const bool down = IsNegative(dy);
    fat.minX = SelectBits(left, fat.minX + dx, fat.minX);
    fat.maxX = SelectBits(left, fat.maxX, fat.maxX + dx);
    fat.minY = SelectBits(down, fat.minY + dy, fat.minY);
    fat.maxY = SelectBits(down, fat.maxY, fat.maxY + dy);
    return fat;
}

/// True when b2DynamicTree::MoveProxy keeps the stored fat box: it still contains the shape's box and lies inside
/// the new fat box `fat` (MovedFatBox) grown by a further 4 x extension.
inline bool KeepsFatBox(const FatPolicy& policy, const Box& stored, const Box& tight, const Box& fat)
{
    // The eight comparisons are combined with & rather than &&: whether a body's box still fits is close to random
    // from one body to the next, so short-circuit branches mispredict often.
    const float h = 4.0f * policy.extension;
    const Box huge{fat.minX - h, fat.minY - h, fat.maxX + h, fat.maxY + h};
    return (int(stored.minX <= tight.minX) & int(stored.minY <= tight.minY) & int(tight.maxX <= stored.maxX) &
            int(tight.maxY <= stored.maxY) & int(huge.minX <= stored.minX) & int(huge.minY <= stored.minY) &
            int(stored.maxX <= huge.maxX) & int(stored.maxY <= huge.maxY)) != 0;
}

/// Decides whether a moved shape needs a new fat box, as b2DynamicTree::MoveProxy does.
/// Returns false and leaves `stored` alone when KeepsFatBox; otherwise writes MovedFatBox and returns true.
inline bool Refatten(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    const Box fat = MovedFatBox(policy, tight, displacement);
    if (KeepsFatBox(policy, stored, tight, fat))
    {
        return false;
    }
    stored = fat;
    return true;
}

/// Refatten without a branch on the outcome, for loops over many proxies (the outcome is close to random from one
/// proxy to the next): `stored` is always rewritten, with its own bits or the new box's. Same results as Refatten.
inline bool RefattenNoBranch(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    const Box fat = MovedFatBox(policy, tight, displacement);
    const bool keep = KeepsFatBox(policy, stored, tight, fat);
    // Bitwise selects, one float at a time (copies float bits exactly, no arithmetic on them). Selecting the
    // whole box through an array made the compiler store two 8-byte halves and reload them as one 16-byte value:
    // a store-forwarding stall that cost more than the test itself.
    const Box old = stored;
    stored.minX = SelectBits(keep, old.minX, fat.minX);
    stored.minY = SelectBits(keep, old.minY, fat.minY);
    stored.maxX = SelectBits(keep, old.maxX, fat.maxX);
    stored.maxY = SelectBits(keep, old.maxY, fat.maxY);
    return !keep;
}

} // namespace quadphase
