// SPDX-License-Identifier: MIT
// The error hook: the process-wide handler, the default one (print, and abort in strict mode) and the code names.
#include "quadphase/error.h"
#include "report_error.h"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>

#include "environment.h"

namespace quadphase
{
namespace
{

// -1: not decided yet (QUADPHASE_STRICT is read at the first report), 0: off, 1: on.
int g_strict = -1;

bool StrictFromEnvironment()
{
    return detail::EnvironmentFlag("QUADPHASE_STRICT");
}

void DefaultHandler(ErrorCode code, const char* message, void*)
{
    std::fprintf(stderr, "quadphase: %s: %s\n", ErrorCodeName(code), message);
    if (g_strict < 0)
    {
        g_strict = StrictFromEnvironment() ? 1 : 0;
    }
    if (g_strict == 1)
    {
        // Opt-in: bad input treated like a failed assertion. Not the default in any build type: a stock Box2D
        // debug build survives a runaway body, and so must a game linked with quadphase.
        std::abort();
    }
}

ErrorHandler g_handler = &DefaultHandler;
void* g_context = nullptr;

} // namespace

ErrorHandler SetErrorHandler(ErrorHandler handler, void* context)
{
    ErrorHandler previous = g_handler;
    g_handler = handler != nullptr ? handler : &DefaultHandler;
    g_context = handler != nullptr ? context : nullptr;
    return previous;
}

bool SetStrictErrors(bool strict)
{
    const bool previous = g_strict < 0 ? StrictFromEnvironment() : g_strict == 1;
    g_strict = strict ? 1 : 0;
    return previous;
}

void ReportError(ErrorCode code, const char* format, ...)
{
    char message[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(message, sizeof(message), format, args);
    va_end(args);
    g_handler(code, message, g_context);
}

const char* ErrorCodeName(ErrorCode code)
{
    switch (code)
    {
    case ErrorCode::NonFiniteBox:
        return "non-finite box";
    case ErrorCode::InvertedBox:
        return "inverted box";
    case ErrorCode::UnknownProxy:
        return "unknown proxy";
    case ErrorCode::TaskSystemMisuse:
        return "task system misuse";
    case ErrorCode::FirstAdapterCode:
        break;
    }
    return int(code) >= int(ErrorCode::FirstAdapterCode) ? "engine adapter error" : "error";
}

} // namespace quadphase
