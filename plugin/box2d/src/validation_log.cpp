// SPDX-License-Identifier: MIT
// QUADPHASE_VALIDATE_LOG: see validation_log.h.
#include "validation_log.h"

#if defined(_WIN32)
#include <process.h> // _getpid (MSVC has no unistd.h)
#else
#include <fcntl.h>
#include <unistd.h>
#endif

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "environment.h"

namespace quadphase
{
namespace detail
{
namespace
{

long ProcessId()
{
#if defined(_WIN32)
    return static_cast<long>(_getpid());
#else
    return static_cast<long>(getpid());
#endif
}

// `path` opened for appending (created 0666 less the umask, as fopen does), close-on-exec: the descriptor must not
// leak into the children the program starts (a shell, a game's helper processes). nullptr with errno on failure.
std::FILE* OpenForAppending(const char* path)
{
#if defined(_WIN32)
    return std::fopen(path, "aN"); // N: not inherited by child processes (the C runtime's _O_NOINHERIT)
#else
    const int fd = open(path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0)
    {
        return nullptr;
    }
    std::FILE* file = fdopen(fd, "a");
    if (file == nullptr)
    {
        const int error = errno;
        close(fd);
        errno = error;
    }
    return file;
#endif
}

struct ValidationLog
{
    std::mutex mutex;
    std::FILE* file = nullptr;
    int64_t every = 100;
    int64_t lastSummaryAt = 0;

    ValidationLog()
    {
        const char* path = EnvironmentValue("QUADPHASE_VALIDATE_LOG");
        if (path == nullptr || path[0] == '\0')
        {
            return;
        }
        file = OpenForAppending(path);
        if (file == nullptr)
        {
            std::fprintf(stderr,
                         "quadphase: validation: cannot open QUADPHASE_VALIDATE_LOG=%s for appending: %s\n",
                         path, std::strerror(errno));
            return;
        }
        const char* every_text = EnvironmentValue("QUADPHASE_VALIDATE_LOG_EVERY");
        if (every_text != nullptr && std::atoll(every_text) > 0)
        {
            every = std::atoll(every_text);
        }
    }

    // Called with `mutex` held. One fprintf per line, then fflush: the line is in the file before the call returns.
    void Line(const char* text)
    {
        std::fprintf(file, "quadphase[%ld]: validation: %s\n", ProcessId(), text);
        std::fflush(file);
    }
};

// Never destroyed: validators may report from other static destructors and atexit handlers.
ValidationLog& Log()
{
    static ValidationLog* log = new ValidationLog;
    return *log;
}

} // namespace

void LogValidationMismatch(const std::string& what)
{
    ValidationLog& log = Log();
    if (log.file == nullptr)
    {
        return;
    }
    std::lock_guard<std::mutex> lock(log.mutex);
    log.Line(("mismatch: " + what).c_str());
}

void LogValidationTotals(int64_t checks, int64_t mismatches, bool final)
{
    ValidationLog& log = Log();
    if (log.file == nullptr)
    {
        return;
    }
    std::lock_guard<std::mutex> lock(log.mutex);
    if (!final && checks / log.every == log.lastSummaryAt / log.every)
    {
        return;
    }
    log.lastSummaryAt = checks;
    char text[160];
    std::snprintf(text, sizeof text, "%lld UpdatePairs checked, %lld mismatches%s",
                  static_cast<long long>(checks), static_cast<long long>(mismatches),
                  final ? " (at exit)" : "");
    log.Line(text);
}

} // namespace detail
} // namespace quadphase
