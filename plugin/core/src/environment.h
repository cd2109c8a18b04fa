// SPDX-License-Identifier: MIT
// Reading quadphase's settings from the environment (the QUADPHASE_* variables): the one place that does it.
#pragma once

namespace quadphase
{
namespace detail
{

/// The value of the environment variable `name` (non-null), or nullptr when it is unset or when the process runs
/// in secure-execution mode: a set-user-ID or set-group-ID program, or one that gained capabilities when it was
/// started. A privileged program linked with quadphase must not let whoever starts it choose the file the
/// validation log appends to, or switch on modes that abort or slow it down. Detected with glibc's
/// secure_getenv; elsewhere with getauxval(AT_SECURE) (other Linux C libraries) or issetugid() (macOS, the BSDs);
/// where the system has neither (Windows, emscripten), the plain value. The pointer is the environment's own:
/// valid until the environment changes.
const char* EnvironmentValue(const char* name);

/// True when EnvironmentValue(name) is set, non-empty and not "0" (so QUADPHASE_VALIDATE=0 switches it off).
bool EnvironmentFlag(const char* name);

} // namespace detail
} // namespace quadphase
