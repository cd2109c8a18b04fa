// SPDX-License-Identifier: MIT
// Callgrind's client requests, or no-ops where valgrind's header is missing. The replay loop brackets its timed
// steps with them (no-ops outside valgrind too), so that valgrind --tool=callgrind --instr-atstart=no counts the
// timed steps' instructions only.
#pragma once

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif
