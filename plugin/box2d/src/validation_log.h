// SPDX-License-Identifier: MIT
// The record validation leaves in a file (QUADPHASE_VALIDATE_LOG), for programs that never reach a normal exit.
#pragma once

#include <cstdint>
#include <string>

namespace quadphase
{
namespace detail
{

/// When QUADPHASE_VALIDATE_LOG names a file, validation appends to it, one line per event, each written and
/// flushed at once (so a program that is killed or aborts leaves what was found up to then):
///   quadphase[PID]: validation: mismatch: <what>                       for each mismatch, as it is found;
///   quadphase[PID]: validation: N UpdatePairs checked, M mismatches    every QUADPHASE_VALIDATE_LOG_EVERY checks
///                                                                      (default 100) of the process, and at exit.
/// Lines of several processes may interleave in one file; PID tells them apart. Without the variable, or in a
/// set-user-ID or set-group-ID program (which ignores it: EnvironmentValue), these do nothing. The file is opened
/// close-on-exec: the programs this one starts do not inherit its descriptor. Thread-safe.
void LogValidationMismatch(const std::string& what);

/// Process-wide totals after a change; writes the running summary each time `checks` crosses a multiple of the
/// interval, or always when `final` (at exit).
void LogValidationTotals(int64_t checks, int64_t mismatches, bool final);

} // namespace detail
} // namespace quadphase
