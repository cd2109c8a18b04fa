// The error hook as built without NDEBUG (CMake compiles plugin/core/src/error.cpp into this program with
// -UNDEBUG): an installed handler receives the report and the program goes on; the default handler prints the
// message to stderr and aborts, like Box2D's b2Assert. The abort is checked in a child process.
// Exit status 0 when both hold, 1 otherwise (a message says which).
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "quadphase/error.h"

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

} // namespace

int main()
{
#ifdef NDEBUG
    return Fail("compiled with NDEBUG; this program checks the debug build's behaviour");
#endif
    quadphase::SetErrorHandler(&Record);
    quadphase::ReportError(quadphase::ErrorCode::NonFiniteBox, "MoveProxy: proxy %d got box (%g, ...)", 3,
                           0.5);
    if (g_calls != 1 || g_message != "MoveProxy: proxy 3 got box (0.5, ...)")
    {
        return Fail("an installed handler did not get the report");
    }
    quadphase::SetErrorHandler(nullptr); // the default handler again

    int pipeFd[2];
    if (pipe(pipeFd) != 0)
    {
        return Fail("pipe");
    }
    const pid_t child = fork();
    if (child < 0)
    {
        return Fail("fork");
    }
    if (child == 0)
    {
        dup2(pipeFd[1], STDERR_FILENO);
        close(pipeFd[0]);
        quadphase::ReportError(quadphase::ErrorCode::InvertedBox, "CreateProxy: proxy %d got an inverted box",
                               7);
        _exit(0); // reached only when the default handler did not abort
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
    int status = 0;
    waitpid(child, &status, 0);
    if (!WIFSIGNALED(status) || WTERMSIG(status) != SIGABRT)
    {
        return Fail("the default handler did not abort in a build without NDEBUG");
    }
    if (std::strstr(text, "quadphase: inverted box: CreateProxy: proxy 7 got an inverted box") == nullptr)
    {
        std::fprintf(stderr, "child's stderr: %s\n", text);
        return Fail("the default handler did not print the diagnostic");
    }
    std::printf("qp_debug_error_hook: a recording handler got the report; the default handler printed it and "
                "aborted (debug build)\n");
    return 0;
}
