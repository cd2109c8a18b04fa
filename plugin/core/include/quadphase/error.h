// The error hook: how bad input (non-finite or inverted boxes, unknown proxy ids) is reported.
#pragma once

namespace quadphase
{

/// What went wrong.
enum class ErrorCode
{
    NonFiniteBox, ///< a box with NaN or infinite coordinates was given to CreateProxy or MoveProxy
    InvertedBox,  ///< a box with min > max on an axis was given to CreateProxy or MoveProxy
    UnknownProxy, ///< an id that is out of range or already destroyed was given
    ValidationMismatch, ///< validation mode found the quadtree and the shadow tree disagree
};

/// Called with a code and a human-readable message that names the call and the offending values.
/// May be called from the thread that made the broadphase call; never from a worker thread.
using ErrorHandler = void (*)(ErrorCode code, const char* message, void* context);

/// Installs a process-wide handler (nullptr restores the default) and returns the previous one.
/// The default handler prints the message to stderr and, in builds without NDEBUG, aborts like an assert.
/// Not thread-safe: install it before creating broadphases.
ErrorHandler SetErrorHandler(ErrorHandler handler, void* context = nullptr);

/// Reports an error through the installed handler. printf-style.
void ReportError(ErrorCode code, const char* format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/// Human-readable name of a code.
const char* ErrorCodeName(ErrorCode code);

} // namespace quadphase
