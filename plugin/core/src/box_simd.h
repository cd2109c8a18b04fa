// SPDX-License-Identifier: MIT
// The two tests the broadphase runs most, on the four floats of a box at once (SSE2, baseline on x86-64), with the
// same results, bit for bit, as the scalar definitions in box.h and fat_policy.h, which other targets use.
//
// Why: the candidate test of a pair query (Overlaps) ran as four compares with short-circuit branches whose outcome
// is close to random, and the branch-free fat-box test (RefattenNoBranch) spent half its instructions moving floats
// between vector and integer registers for its bit selects (docs/design.md, "Fat boxes").
#pragma once

#include <cstdint>

#include "compiler.h"

#if defined(QUADPHASE_SSE2)
#include <emmintrin.h>
#endif

#include "fat_policy.h"
#include "quadphase/box.h"

namespace quadphase
{

#if defined(QUADPHASE_SSE2)

/// A query box prepared for OverlapsPrepared: (maxX, maxY, -minX, -minY).
struct PreparedBox
{
    __m128 v;
};

namespace simd_detail
{
// Flips the sign of the two upper lanes: (a, b, c, d) -> (a, b, -c, -d), exactly (NaN stays NaN).
inline __m128 NegateUpper(__m128 x)
{
    return _mm_xor_ps(x, _mm_castsi128_ps(_mm_set_epi32(int32_t(0x80000000u), int32_t(0x80000000u), 0, 0)));
}

inline __m128 Load(const Box& b)
{
    return _mm_loadu_ps(&b.minX); // the four floats of Box, in order (may_alias load)
}

// A box's four floats, (lower.x, lower.y, upper.x, upper.y), as two 8-byte loads, one per corner: for a box the
// caller has just written corner by corner, as Box2D writes a b2AABB (b2Fixture::Synchronize's Combine stores
// lowerBound, then upperBound, 8 bytes each). One 16-byte load of two fresh 8-byte stores cannot be forwarded from
// the store buffer and waits until they reach the cache: 8 ns more per MoveProxy (qp-moves-*).
inline __m128 LoadCorners(const float* lower, const float* upper)
{
    return _mm_movelh_ps(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(lower))),
                         _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(upper))));
}
} // namespace simd_detail

inline PreparedBox Prepare(const Box& query)
{
    // (minX, minY, maxX, maxY) -> (maxX, maxY, minX, minY), then the upper lanes negated.
    const __m128 q = simd_detail::Load(query);
    return PreparedBox{simd_detail::NegateUpper(_mm_shuffle_ps(q, q, _MM_SHUFFLE(1, 0, 3, 2)))};
}

/// Overlaps(e, query) for a query prepared with Prepare(): e.minX <= q.maxX, e.minY <= q.maxY, and q.minX <= e.maxX,
/// q.minY <= e.maxY written as -e.maxX <= -q.minX, -e.maxY <= -q.minY (negation is exact, so every float, signed
/// zeros and infinities included, compares as before; a NaN fails its lane as it fails the scalar compare).
inline bool OverlapsPrepared(const Box& e, const PreparedBox& query)
{
    const __m128 lhs = simd_detail::NegateUpper(simd_detail::Load(e));
    return _mm_movemask_ps(_mm_cmple_ps(lhs, query.v)) == 0xF;
}

namespace simd_detail
{
// IsSane's four lanes: all set when every coordinate is finite (x - x is 0 exactly for finite x, NaN for infinities
// and NaN) and min <= max on both axes.
inline __m128 SaneMask(__m128 v)
{
    const __m128 finite = _mm_cmpeq_ps(_mm_sub_ps(v, v), _mm_setzero_ps());
    const __m128 ordered = _mm_cmple_ps(_mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 1, 0)),
                                        _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 2, 3, 2)));
    return _mm_and_ps(finite, ordered);
}

// MovedFatBox (fat_policy.h) on the four lanes of the tight box t: the same additions in the same order on the
// same floats, and the same compares, so the box comes out bit-identical.
inline __m128 MovedFat(const FatPolicy& policy, __m128 t, Vec2 displacement)
{
    const float r = policy.extension;
    // tight - r on the min sides, + r on the max sides. For a non-NaN r that is one addition of (-r, -r, r, r)
    // (x - r is x + -r in IEEE arithmetic); a NaN r takes the subtraction, which gives a NaN of the other sign
    // than adding -r does. With Box2D's constant extension the compiler keeps one branch.
    const __m128 grown = r == r ? _mm_add_ps(t, _mm_set_ps(r, r, -r, -r))
                                : _mm_shuffle_ps(_mm_sub_ps(t, _mm_set1_ps(r)), _mm_add_ps(t, _mm_set1_ps(r)),
                                                 _MM_SHUFFLE(3, 2, 1, 0));
    // (dx, dy, dx, dy): the displacement's two floats loaded at once and multiplied lane by lane (the same
    // products as the scalar multiplier * displacement.x and .y).
    const __m128 disp = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&displacement)));
    const __m128 product = _mm_mul_ps(disp, _mm_set1_ps(policy.multiplier));
    const __m128 d = _mm_movelh_ps(product, product);
    // Lanes 0, 1 (min sides) take +d when d < 0; lanes 2, 3 (max sides) when !(d < 0): Box2D's if/else.
    const __m128 negative = _mm_cmplt_ps(d, _mm_setzero_ps());
    const __m128 moveMask = _mm_xor_ps(negative, _mm_castsi128_ps(_mm_set_epi32(-1, -1, 0, 0)));
    const __m128 moved = _mm_add_ps(grown, d);
    return _mm_or_ps(_mm_and_ps(moveMask, moved), _mm_andnot_ps(moveMask, grown));
}

// KeepsFatBox's eight compares as four lanes, all set when the stored box s is kept: s contains the tight box t,
// and the moved fat box grown by 4 x extension on every side contains s.
inline __m128 KeepMask(const FatPolicy& policy, __m128 s, __m128 t, __m128 fat)
{
    const float h = 4.0f * policy.extension;
    const __m128 huge = h == h ? _mm_add_ps(fat, _mm_set_ps(h, h, -h, -h))
                               : _mm_shuffle_ps(_mm_sub_ps(fat, _mm_set1_ps(h)), _mm_add_ps(fat, _mm_set1_ps(h)),
                                                _MM_SHUFFLE(3, 2, 1, 0));
    // (s.minX, s.minY, t.maxX, t.maxY) <= (t.minX, t.minY, s.maxX, s.maxY)
    const __m128 c1 = _mm_cmple_ps(_mm_shuffle_ps(s, t, _MM_SHUFFLE(3, 2, 1, 0)),
                                   _mm_shuffle_ps(t, s, _MM_SHUFFLE(3, 2, 1, 0)));
    // (huge.minX, huge.minY, s.maxX, s.maxY) <= (s.minX, s.minY, huge.maxX, huge.maxY)
    const __m128 c2 = _mm_cmple_ps(_mm_shuffle_ps(huge, s, _MM_SHUFFLE(3, 2, 1, 0)),
                                   _mm_shuffle_ps(s, huge, _MM_SHUFFLE(3, 2, 1, 0)));
    return _mm_and_ps(c1, c2);
}
} // namespace simd_detail

/// IsSane (box.h): every coordinate finite and min <= max on both axes. QueueMove tests every moving body's box
/// with it.
inline bool IsSaneSimd(const Box& b)
{
    return _mm_movemask_ps(simd_detail::SaneMask(simd_detail::Load(b))) == 0xF;
}

/// RefattenNoBranch (fat_policy.h), lane by lane: the same additions in the same order on the same floats, and
/// the same compares, so the stored box comes out bit-identical.
inline bool RefattenSimd(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    const __m128 t = simd_detail::Load(tight);
    const __m128 s = simd_detail::Load(stored);
    const __m128 fat = simd_detail::MovedFat(policy, t, displacement);
    const bool keep = _mm_movemask_ps(simd_detail::KeepMask(policy, s, t, fat)) == 0xF;
    const __m128 keepMask = _mm_castsi128_ps(_mm_set1_epi32(-int32_t(keep)));
    _mm_storeu_ps(&stored.minX, _mm_or_ps(_mm_and_ps(keepMask, s), _mm_andnot_ps(keepMask, fat)));
    return !keep;
}

/// The common outcome of a move in one test: true when the tight box (lower.x, lower.y, upper.x, upper.y: two
/// floats at each pointer) is sane (IsSane) and `stored` is kept (KeepsFatBox with MovedFatBox), so nothing changes.
/// Otherwise false, with `fat` the moved fat box (MovedFatBox), the box RefattenSimd would store when the test fails
/// on a sane box, and `sane` IsSane of the tight box; both are written only then. One mask and one branch for both
/// questions; the corners are read as Box2D writes them.
///
/// The kept test runs on the boxes with their min lanes negated, (-minX, -minY, maxX, maxY): there every one of
/// KeepsFatBox's eight compares reads "lane <= lane" (s.min <= t.min is -t.min <= -s.min), so the tight, stored and
/// grown boxes are compared as they come, with no shuffles, and the fat box grows by +r on every lane. Negation is
/// exact, and so is -(a - b) = -a + b in IEEE arithmetic, so each lane holds the negation of the float Box2D
/// compares, and each compare gives Box2D's answer. The side that does not move adds max(0, -d) or max(0, d), a
/// zero, instead of being selected: that can turn a -0 into +0, which compares equal, so the decision is unchanged;
/// the box to store, whose bits matter, is MovedFat's, computed only when the test fails. A NaN displacement gives
/// a NaN lane either way (maxps returns its second operand when one is NaN: SSE's rule, which Emscripten's emulation
/// of _mm_max_ps follows; a wasm pmax would not, and test_fat_policy.cpp's NaN displacements would say so), and a
/// NaN lane fails its compare as in Box2D's. Most moves keep their fat box: this is the whole of their cost in MoveProxy (docs/design.md, "Fat
/// boxes").
inline bool KeptAndSaneSimd(const FatPolicy& policy, const Box& stored, const float* lower, const float* upper,
                            Vec2 displacement, Box& fat, bool& sane)
{
    const __m128 t = simd_detail::LoadCorners(lower, upper);
    const __m128 minSigns = _mm_castsi128_ps(_mm_set_epi32(0, 0, int32_t(0x80000000u), int32_t(0x80000000u)));
    const __m128 zero = _mm_setzero_ps();
    const __m128 u = _mm_xor_ps(t, minSigns);                               // tight, min lanes negated
    const __m128 v = _mm_xor_ps(simd_detail::Load(stored), minSigns);       // stored, min lanes negated
    const __m128 disp = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&displacement)));
    // The policy's three numbers as one vector (m, m, r, h), one 16-byte load: GCC loads a constant _mm_set1_ps as
    // a scalar and broadcasts it, two instructions each. Its lanes 2 and 3 multiply the zeros above the
    // displacement; the products there are never read.
    const __m128 constants = _mm_set_ps(4.0f * policy.extension, policy.extension, policy.multiplier,
                                        policy.multiplier);
    const __m128 product = _mm_mul_ps(disp, constants); // (m dx, m dy, -, -)
    const __m128 ahead = _mm_max_ps(zero, _mm_xor_ps(_mm_movelh_ps(product, product), minSigns));
    const __m128 grown = _mm_add_ps(_mm_add_ps(u, _mm_shuffle_ps(constants, constants, _MM_SHUFFLE(2, 2, 2, 2))),
                                    ahead);
    const __m128 huge = _mm_add_ps(grown, _mm_shuffle_ps(constants, constants, _MM_SHUFFLE(3, 3, 3, 3)));
    // u <= v: the stored box contains the tight one; v <= huge: the grown box's margin contains the stored one.
    const __m128 keep = _mm_and_ps(_mm_cmple_ps(u, v), _mm_cmple_ps(v, huge));
    // IsSane: t - t is 0 for finite lanes (NaN for infinities and NaN), and (minX, minY) <= (maxX, maxY).
    const __m128 finite = _mm_cmpeq_ps(_mm_sub_ps(t, t), zero);
    const __m128 ordered = _mm_cmple_ps(t, _mm_movehl_ps(t, t));
    const __m128 saneMask = _mm_and_ps(finite, ordered);
    if (QUADPHASE_LIKELY(_mm_movemask_ps(_mm_and_ps(keep, saneMask)) == 0xF))
    {
        return true;
    }
    _mm_storeu_ps(&fat.minX, simd_detail::MovedFat(policy, t, displacement));
    sane = _mm_movemask_ps(saneMask) == 0xF;
    return false;
}

#else

struct PreparedBox
{
    Box box;
};

inline PreparedBox Prepare(const Box& query)
{
    return PreparedBox{query};
}

inline bool OverlapsPrepared(const Box& e, const PreparedBox& query)
{
    return Overlaps(e, query.box);
}

inline bool RefattenSimd(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    return RefattenNoBranch(policy, stored, tight, displacement);
}

inline bool IsSaneSimd(const Box& b)
{
    return IsSane(b);
}

inline bool KeptAndSaneSimd(const FatPolicy& policy, const Box& stored, const float* lower, const float* upper,
                            Vec2 displacement, Box& fat, bool& sane)
{
    const Box tight{lower[0], lower[1], upper[0], upper[1]};
    fat = MovedFatBox(policy, tight, displacement);
    sane = IsSane(tight);
    return int(sane) & int(KeepsFatBox(policy, stored, tight, fat));
}

#endif

} // namespace quadphase
