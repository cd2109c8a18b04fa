// SPDX-License-Identifier: MIT
// The error hook: how bad input (non-finite or inverted boxes, unknown proxy ids) is reported.
#pragma once

#include "quadphase/export.h"

namespace quadphase
{

/// What went wrong. The core reports the first four. An engine adapter defines its own codes, from
/// FirstAdapterCode up, beside the code that reports them (the Box2D adapter: kValidationMismatch in
/// quadphase/shadow_validator.h); they reach the same handler.
enum class ErrorCode
{
    NonFiniteBox,     ///< a box with NaN or infinite coordinates was given to CreateProxy or MoveProxy
    InvertedBox,      ///< a box with min > max on an axis was given to CreateProxy or MoveProxy
    UnknownProxy,     ///< an id that is out of range or already destroyed was given
    TaskSystemMisuse, ///< the game's task system skipped items or ran items outside the range it was given
    FirstAdapterCode = 64, ///< the first code an engine adapter may define
};

/// Called with a code and a human-readable message that names the call and the offending values.
/// May be called from the thread that made the broadphase call; never from a worker thread.
using ErrorHandler = void (*)(ErrorCode code, const char* message, void* context);

/// Installs a process-wide handler (nullptr restores the default) and returns the previous one.
/// The default handler prints the message to stderr and goes on, in every build type, as stock Box2D goes on
/// with a runaway body (it has no assertion on the MoveProxy path); in strict mode (SetStrictErrors) it aborts
/// after printing. A bad box is reported once per proxy (the first one it gets), not once per call, so a
/// runaway body costs one line, not one per step; unknown ids are reported at every call.
/// Not thread-safe: install it before creating broadphases.
QUADPHASE_API ErrorHandler SetErrorHandler(ErrorHandler handler, void* context = nullptr);

/// Strict mode: the default handler aborts after printing, like an assert (for tests and debugging). Off by
/// default; also switched on by QUADPHASE_STRICT=1 in the environment (read at the first report; ignored, as every
/// QUADPHASE_* variable, by set-user-ID and set-group-ID programs). Has no effect on an installed handler. Returns
/// the previous setting. Not thread-safe, like SetErrorHandler.
QUADPHASE_API bool SetStrictErrors(bool strict);

/// Human-readable name of a code ("engine adapter error" for every adapter code: its message says more).
QUADPHASE_API const char* ErrorCodeName(ErrorCode code);

} // namespace quadphase
