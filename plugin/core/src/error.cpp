#include "quadphase/error.h"

#include <cassert>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>

namespace quadphase
{
namespace
{

void DefaultHandler(ErrorCode code, const char* message, void*)
{
    std::fprintf(stderr, "quadphase: %s: %s\n", ErrorCodeName(code), message);
#ifndef NDEBUG
    // Debug builds treat bad input like Box2D's b2Assert does.
    std::abort();
#endif
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
    case ErrorCode::ValidationMismatch:
        return "validation mismatch";
    }
    return "error";
}

} // namespace quadphase
