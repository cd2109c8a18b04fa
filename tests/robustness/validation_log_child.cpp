// SPDX-License-Identifier: MIT
// Child process of robustness_validation_log (RunValidationLog.cmake): a program that validates its broadphase
// (QUADPHASE_VALIDATE=1), finds mismatches, and never exits normally: `validation_log_child abort|kill|strict N`
// runs N UpdatePairs, of which every tenth follows a move made behind the shadow tree's back (straight into the
// quadtree, as a buggy broadphase would), then aborts, kills itself with SIGKILL, or (strict) dies at the first
// mismatch through quadphase's strict error mode. QUADPHASE_VALIDATE_LOG must keep what was found.
#include <box2d/b2_broad_phase.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#if defined(_WIN32)
#include <windows.h>
#endif

#include "box2d_internal.h"
#include "child_broad_phase.h"
#include "quadphase/box2d.h"
#include "quadphase/error.h"

int main(int argc, char** argv)
{
    if (argc != 3)
    {
        std::fprintf(stderr, "usage: validation_log_child abort|kill|strict N\n");
        return 2;
    }
    const char* mode = argv[1];
    const int count = std::atoi(argv[2]);
    quadphase::SetStrictErrors(std::strcmp(mode, "strict") == 0);
    b2BroadPhase bp; // validating: QUADPHASE_VALIDATE=1
    if (!quadphase::IsValidating(bp))
    {
        std::fprintf(stderr, "validation is off: QUADPHASE_VALIDATE=1 expected\n");
        return 2;
    }
    const int32 a = bp.CreateProxy(Aabb(0.0f, 0.0f), nullptr);
    bp.CreateProxy(Aabb(10.0f, 0.0f), nullptr);
    NoPairs pairs;
    for (int i = 1; i <= count; ++i)
    {
        if (i % 10 == 0)
        {
            // Moved onto the other proxy (to and fro, a new fat box each time) in the quadtree only: the quadtree
            // reports a pair the shadow tree, which still has the proxy at the origin, does not.
            const float x = (i / 10) % 2 == 1 ? 10.0f : 10.25f;
            quadphase::GetQuadtree(bp).MoveProxy(a, quadphase::Box{x, 0.0f, x + 1.0f, 1.0f},
                                                 quadphase::Vec2{0.0f, 0.0f});
        }
        bp.UpdatePairs(&pairs);
    }
    std::fflush(stdout);
    if (std::strcmp(mode, "kill") == 0)
    {
#if defined(_WIN32)
        // Windows has no SIGKILL; TerminateProcess ends the process as abruptly (no handler, no flush, no atexit).
        TerminateProcess(GetCurrentProcess(), 137);
#else
        std::raise(SIGKILL);
#endif
    }
    std::abort();
}
