// SPDX-License-Identifier: MIT
// The error hook as built without NDEBUG (CMake compiles plugin/core/src/error.cpp into this program with
// -UNDEBUG): an installed handler receives the report and the program goes on; the default handler prints the
// message to stderr and goes on too, as a stock Box2D debug build goes on with a runaway body; strict mode
// (SetStrictErrors, or QUADPHASE_STRICT=1) makes it abort after printing. Each default-handler case runs in a
// child process. Exit status 0 when all hold, 1 otherwise (a message says which).
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "report_error.h"

namespace
{

int g_calls = 0;
std::string g_message;

void Record(quadphase::ErrorCode code, const char* message, void*)
{
    g_calls += code == quadphase::ErrorCode::NonFiniteBox ? 1 : 0;
    g_message = message;
}

int Fail(const char* what)
{
    std::fprintf(stderr, "qp_debug_error_hook: FAIL: %s\n", what);
    return 1;
}

struct ChildResult
{
    bool ok = false; // fork and pipe worked
    int status = 0;  // waitpid status
    std::string stderrText;
};

// Runs `body` in a child whose stderr is captured; the child exits with 0 when body returns.
template <typename Body>
ChildResult RunChild(Body body)
{
    ChildResult result;
    int pipeFd[2];
    if (pipe(pipeFd) != 0)
    {
        return result;
    }
    const pid_t child = fork();
    if (child < 0)
    {
        return result;
    }
    if (child == 0)
    {
        dup2(pipeFd[1], STDERR_FILENO);
        close(pipeFd[0]);
        body();
        _exit(0);
    }
    close(pipeFd[1]);
    char text[512] = {};
    size_t used = 0;
    ssize_t got = 0;
    while (used + 1 < sizeof(text) && (got = read(pipeFd[0], text + used, sizeof(text) - 1 - used)) > 0)
    {
        used += size_t(got);
    }
    close(pipeFd[0]);
    waitpid(child, &result.status, 0);
    result.ok = true;
    result.stderrText = text;
    return result;
}

bool Aborted(const ChildResult& r)
{
    return WIFSIGNALED(r.status) && WTERMSIG(r.status) == SIGABRT;
}

bool ExitedCleanly(const ChildResult& r)
{
    return WIFEXITED(r.status) && WEXITSTATUS(r.status) == 0;
}

const char* const kDiagnostic = "quadphase: inverted box: CreateProxy: proxy 7 got an inverted box";

void ReportInverted()
{
    quadphase::ReportError(quadphase::ErrorCode::InvertedBox, "CreateProxy: proxy %d got an inverted box", 7);
}

} // namespace

int main()
{
#ifdef NDEBUG
    return Fail("compiled with NDEBUG; this program checks the debug build's behaviour");
#endif
    unsetenv("QUADPHASE_STRICT");
    quadphase::SetErrorHandler(&Record);
    quadphase::ReportError(quadphase::ErrorCode::NonFiniteBox, "MoveProxy: proxy %d got box (%g, ...)", 3,
                           0.5);
    if (g_calls != 1 || g_message != "MoveProxy: proxy 3 got box (0.5, ...)")
    {
        return Fail("an installed handler did not get the report");
    }
    quadphase::SetErrorHandler(nullptr); // the default handler again

    // Default: print and go on, in a debug build too.
    const ChildResult lenient = RunChild([] { ReportInverted(); });
    if (!lenient.ok)
    {
        return Fail("fork or pipe");
    }
    if (!ExitedCleanly(lenient))
    {
        return Fail("the default handler ended the program in a build without NDEBUG (stock Box2D goes on)");
    }
    if (lenient.stderrText.find(kDiagnostic) == std::string::npos)
    {
        std::fprintf(stderr, "child's stderr: %s\n", lenient.stderrText.c_str());
        return Fail("the default handler did not print the diagnostic");
    }

    // Strict mode, set through the API: print, then abort.
    const ChildResult strict = RunChild([] {
        if (quadphase::SetStrictErrors(true))
        {
            std::fprintf(stderr, "strict mode was already on\n");
            _exit(3);
        }
        ReportInverted();
    });
    if (!strict.ok || !Aborted(strict) || strict.stderrText.find(kDiagnostic) == std::string::npos)
    {
        std::fprintf(stderr, "child's stderr: %s\n", strict.stderrText.c_str());
        return Fail("strict mode (SetStrictErrors) did not print and abort");
    }

    // Strict mode, from the environment.
    const ChildResult fromEnvironment = RunChild([] {
        setenv("QUADPHASE_STRICT", "1", 1);
        ReportInverted();
    });
    if (!fromEnvironment.ok || !Aborted(fromEnvironment))
    {
        return Fail("QUADPHASE_STRICT=1 did not make the default handler abort");
    }
    std::printf(
        "qp_debug_error_hook: a recording handler got the report; the default handler printed it and went "
        "on (debug build); strict mode, from the API or QUADPHASE_STRICT=1, aborted\n");
    return 0;
}
