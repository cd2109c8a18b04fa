// SPDX-License-Identifier: MIT
// Every compiler-specific spelling quadphase's own code uses, for GCC and Clang (MinGW-w64 included) and for MSVC:
// a builtin, attribute or pragma goes here, never into the code that uses it, so that a new compiler is one file's
// work. Internal (not installed): the one public macro, QUADPHASE_API, is quadphase/export.h's. A compiler that is
// none of these gets the portable fallback of each: no hint, and a loop for the bit counts.
#pragma once

#if defined(__GNUC__) || defined(__clang__)
#define QUADPHASE_GNU_BUILTINS 1
#elif defined(_MSC_VER)
#include <intrin.h> // _BitScanForward, _BitScanReverse, _mm_prefetch (x86, x64), __prefetch (ARM64)
#endif
#if defined(__MINGW32__)
#include <cstdio> // __MINGW_PRINTF_FORMAT, once the C++ library has chosen MinGW-w64's C99 printf
#endif

/// QUADPHASE_LIKELY(cond): cond, with a hint that it is almost always true (the fast paths of per-move calls).
#if defined(QUADPHASE_GNU_BUILTINS)
#define QUADPHASE_LIKELY(cond) __builtin_expect(!!(cond), 1)
#else
#define QUADPHASE_LIKELY(cond) (!!(cond))
#endif

/// QUADPHASE_NOINLINE and QUADPHASE_COLD, before a declaration: kept out of line, and laid out away from the hot
/// code (error reports called from inline fast paths). MSVC has no "cold".
#if defined(QUADPHASE_GNU_BUILTINS)
#define QUADPHASE_NOINLINE __attribute__((noinline))
#define QUADPHASE_COLD __attribute__((cold))
#elif defined(_MSC_VER)
#define QUADPHASE_NOINLINE __declspec(noinline)
#define QUADPHASE_COLD
#else
#define QUADPHASE_NOINLINE
#define QUADPHASE_COLD
#endif

/// QUADPHASE_PRINTF_FORMAT(f, a), after a function's declarator: parameter f is a printf format for the parameters
/// from a on, which GCC and Clang check at every call. MinGW-w64 names its printf's dialect itself: GCC's plain
/// "printf" there means msvcrt's, which would reject %zu and %lld.
#if defined(__MINGW_PRINTF_FORMAT)
#define QUADPHASE_PRINTF_FORMAT(f, a) __attribute__((format(__MINGW_PRINTF_FORMAT, f, a)))
#elif defined(QUADPHASE_GNU_BUILTINS)
#define QUADPHASE_PRINTF_FORMAT(f, a) __attribute__((format(printf, f, a)))
#else
#define QUADPHASE_PRINTF_FORMAT(f, a)
#endif

/// QUADPHASE_PREFETCH(p): a hint to bring the cache line at p into every cache level for reading; never faults.
#if defined(QUADPHASE_GNU_BUILTINS)
#define QUADPHASE_PREFETCH(p) __builtin_prefetch(p)
#elif defined(_MSC_VER) && (defined(_M_X64) || defined(_M_IX86))
#define QUADPHASE_PREFETCH(p) _mm_prefetch(reinterpret_cast<const char*>(p), _MM_HINT_T0)
#elif defined(_MSC_VER) && defined(_M_ARM64)
#define QUADPHASE_PREFETCH(p) __prefetch(p)
#else
#define QUADPHASE_PREFETCH(p) static_cast<void>(p)
#endif

namespace quadphase
{
namespace compiler
{

/// Leading (most significant) zero bits of x; x must not be 0 (undefined there, as for the builtin).
inline int CountLeadingZeros32(unsigned x)
{
#if defined(QUADPHASE_GNU_BUILTINS)
    return __builtin_clz(x);
#elif defined(_MSC_VER)
    unsigned long index;
    _BitScanReverse(&index, x);
    return 31 - int(index);
#else
    int n = 0;
    for (unsigned bit = 0x80000000u; (x & bit) == 0; bit >>= 1)
    {
        ++n;
    }
    return n;
#endif
}

/// Trailing (least significant) zero bits of x; x must not be 0.
inline int CountTrailingZeros32(unsigned x)
{
#if defined(QUADPHASE_GNU_BUILTINS)
    return __builtin_ctz(x);
#elif defined(_MSC_VER)
    unsigned long index;
    _BitScanForward(&index, x);
    return int(index);
#else
    return 31 - CountLeadingZeros32(x & (0u - x)); // x & -x keeps the lowest set bit alone
#endif
}

} // namespace compiler
} // namespace quadphase

/// QUADPHASE_SSE2: defined when the SSE2 intrinsics (<emmintrin.h>) may be used. GCC and Clang say so with __SSE2__;
/// MSVC never defines __SSE2__, but SSE2 is the baseline of x64 and of x86's /arch:SSE2 and above.
#if defined(__SSE2__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 2)
#define QUADPHASE_SSE2 1
#endif
