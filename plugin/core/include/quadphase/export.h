// SPDX-License-Identifier: MIT
// QUADPHASE_API: what marks quadphase's public functions (the extras beside Box2D's API) for export from the Box2D
// library, by Box2D's own rule for B2_API (box2d/b2_api.h), so that the two are exported or imported together.
// C++11-clean, and the only compiler-specific spelling a public header needs (the rest is plugin/core/src/compiler.h).
#pragma once

/// Before a public function's declaration. With B2_SHARED (a shared Box2D library, as for B2_API): on Windows the
/// DLL's own build (box2d_EXPORTS, CMake's definition for a target named box2d) exports the function and a program
/// using the DLL imports it; elsewhere it has default visibility in a library compiled with hidden visibility.
/// Without B2_SHARED (static libraries) it is empty. tests/abi checks what the library exports.
#if defined(B2_SHARED)
#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(box2d_EXPORTS)
#define QUADPHASE_API __declspec(dllexport)
#else
#define QUADPHASE_API __declspec(dllimport)
#endif
#elif defined(__GNUC__) && __GNUC__ >= 4
#define QUADPHASE_API __attribute__((visibility("default")))
#else
#define QUADPHASE_API
#endif
#else
#define QUADPHASE_API
#endif
