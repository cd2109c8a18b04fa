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

/// IsSane (box.h): every coordinate finite (x - x is 0 exactly for finite x, NaN for infinities and NaN) and
/// min <= max on both axes. QueueMove tests every moving body's box with it.
inline bool IsSaneSimd(const Box& b)
{
    const __m128 v = simd_detail::Load(b);
    const __m128 finite = _mm_cmpeq_ps(_mm_sub_ps(v, v), _mm_setzero_ps());
    const __m128 ordered = _mm_cmple_ps(_mm_shuffle_ps(v, v, _MM_SHUFFLE(1, 0, 1, 0)),
                                        _mm_shuffle_ps(v, v, _MM_SHUFFLE(3, 2, 3, 2)));
    return _mm_movemask_ps(_mm_and_ps(finite, ordered)) == 0xF;
}

/// RefattenNoBranch (fat_policy.h), lane by lane: the same additions in the same order on the same floats, and
/// the same compares, so the stored box comes out bit-identical.
inline bool RefattenSimd(const FatPolicy& policy, Box& stored, const Box& tight, Vec2 displacement)
{
    const float r = policy.extension;
    const float h = 4.0f * policy.extension;
    const float dx = policy.multiplier * displacement.x;
    const float dy = policy.multiplier * displacement.y;
    const __m128 t = simd_detail::Load(tight);
    const __m128 s = simd_detail::Load(stored);
    // MovedFatBox: tight - r on the min sides, + r on the max sides (subtracted, not added negated: with a NaN
    // extension the two give NaNs of opposite sign), then + d on the side the body moves toward.
    const __m128 rv = _mm_set1_ps(r);
    const __m128 grown = _mm_shuffle_ps(_mm_sub_ps(t, rv), _mm_add_ps(t, rv), _MM_SHUFFLE(3, 2, 1, 0));
    const __m128 d = _mm_set_ps(dy, dx, dy, dx);
    // lanes 0, 1 (min sides) take +d when d < 0; lanes 2, 3 (max sides) when !(d < 0): Box2D's if/else.
    const __m128 negative = _mm_cmplt_ps(d, _mm_setzero_ps());
    const __m128 moveMask = _mm_xor_ps(negative, _mm_castsi128_ps(_mm_set_epi32(-1, -1, 0, 0)));
    const __m128 moved = _mm_add_ps(grown, d);
    const __m128 fat = _mm_or_ps(_mm_and_ps(moveMask, moved), _mm_andnot_ps(moveMask, grown));
    // KeepsFatBox: stored contains tight, and fat grown by h on every side contains stored.
    const __m128 hv = _mm_set1_ps(h);
    const __m128 huge = _mm_shuffle_ps(_mm_sub_ps(fat, hv), _mm_add_ps(fat, hv), _MM_SHUFFLE(3, 2, 1, 0));
    // (s.minX, s.minY, t.maxX, t.maxY) <= (t.minX, t.minY, s.maxX, s.maxY)
    const __m128 c1 = _mm_cmple_ps(_mm_shuffle_ps(s, t, _MM_SHUFFLE(3, 2, 1, 0)),
                                   _mm_shuffle_ps(t, s, _MM_SHUFFLE(3, 2, 1, 0)));
    // (huge.minX, huge.minY, s.maxX, s.maxY) <= (s.minX, s.minY, huge.maxX, huge.maxY)
    const __m128 c2 = _mm_cmple_ps(_mm_shuffle_ps(huge, s, _MM_SHUFFLE(3, 2, 1, 0)),
                                   _mm_shuffle_ps(s, huge, _MM_SHUFFLE(3, 2, 1, 0)));
    const bool keep = _mm_movemask_ps(_mm_and_ps(c1, c2)) == 0xF;
    const __m128 keepMask = _mm_castsi128_ps(_mm_set1_epi32(-int32_t(keep)));
    _mm_storeu_ps(&stored.minX, _mm_or_ps(_mm_and_ps(keepMask, s), _mm_andnot_ps(keepMask, fat)));
    return !keep;
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

#endif

} // namespace quadphase
