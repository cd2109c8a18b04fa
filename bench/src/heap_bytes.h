// SPDX-License-Identifier: MIT
// The heap bytes an engine holds, measured the same way for every engine.
#pragma once

#include <cstdint>

#include <malloc.h>

namespace qpbench
{

// Heap bytes in use by the process (glibc's mallinfo2: small blocks in use plus mmap'ed blocks). The replay
// tools read it before building an engine and after replaying the whole trace through it: the difference is
// what the engine holds (its index, id maps, buffers and its pair vector), measured the same way for every
// engine, whatever allocator wrapper it uses internally (Box2D's b2Alloc, Chipmunk's cpcalloc and Bullet's
// btAlignedAlloc all end in malloc).
inline int64_t HeapBytes()
{
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
    const struct mallinfo2 mi = mallinfo2();
    return int64_t(mi.uordblks) + int64_t(mi.hblkhd);
#else
    return 0; // unknown: reported as 0 bytes
#endif
}

} // namespace qpbench
