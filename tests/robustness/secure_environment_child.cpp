// SPDX-License-Identifier: MIT
// Child process of robustness_secure_environment (RunSecureEnvironment.cmake), run once as it is and once as a
// set-group-ID copy: `secure_environment_child LOG` reports on one line which QUADPHASE_* variables it obeyed, and
// how the kernel started it, so that the driver can tell "ignored because secure" from "never set":
//   at_secure=0|1         getauxval(AT_SECURE): the kernel started the program in secure-execution mode;
//   nosuid=0|1            the program's file system is mounted nosuid (set-ID bits have no effect there);
//   no_new_privs=0|1      the process may not gain privileges (set-ID bits have no effect either);
//   validate=0|1          QUADPHASE_VALIDATE=1 switched validation on for a new broadphase;
//   stock_tree=0|1        QUADPHASE_STOCK_TREE=1 kept a stock tree in m_tree (its height is then above 0);
//   strict=0|1            QUADPHASE_STRICT=1 made error reports strict;
//   log=none|cloexec|inherited
//                         after validation (switched on here whatever the environment says) has checked a few
//                         UpdatePairs: whether a descriptor of the file LOG (QUADPHASE_VALIDATE_LOG) is open, and
//                         if so whether it is closed on exec or would leak into a child process.
// Exit status 0 once the line is written, 2 on a usage error.
#include <box2d/b2_broad_phase.h>

#include <dirent.h>
#include <fcntl.h>
#include <sys/auxv.h>
#include <sys/prctl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "child_broad_phase.h"
#include "quadphase/box2d.h"
#include "quadphase/error.h"

namespace
{

bool OnNosuidFileSystem()
{
    struct statvfs fs;
    return statvfs("/proc/self/exe", &fs) == 0 && (fs.f_flag & ST_NOSUID) != 0;
}

// "none", "cloexec" or "inherited": the descriptors of this process open on `path` (a canonical path).
const char* LogDescriptor(const std::string& path)
{
    DIR* fds = opendir("/proc/self/fd");
    if (fds == nullptr)
    {
        std::perror("/proc/self/fd");
        std::exit(2);
    }
    const char* result = "none";
    while (const dirent* entry = readdir(fds))
    {
        const std::string link = std::string("/proc/self/fd/") + entry->d_name;
        char target[PATH_MAX];
        const ssize_t length = readlink(link.c_str(), target, sizeof target - 1);
        if (entry->d_name[0] == '.' || length < 0 || std::string(target, size_t(length)) != path)
        {
            continue;
        }
        const int flags = fcntl(std::atoi(entry->d_name), F_GETFD);
        if ((flags & FD_CLOEXEC) == 0)
        {
            result = "inherited";
            break;
        }
        result = "cloexec";
    }
    closedir(fds);
    return result;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc != 2)
    {
        std::fprintf(stderr, "usage: secure_environment_child LOG\n");
        return 2;
    }
    b2BroadPhase bp;
    const bool validate = quadphase::IsValidating(bp);
    bp.CreateProxy(Aabb(0.0f, 0.0f), nullptr);
    bp.CreateProxy(Aabb(0.5f, 0.0f), nullptr);
    const bool stockTree = bp.GetTreeHeight() > 0;
    const bool strict = quadphase::SetStrictErrors(false); // the previous setting: QUADPHASE_STRICT's
    quadphase::SetValidation(bp, true);
    NoPairs pairs;
    for (int i = 0; i < 3; ++i)
    {
        bp.UpdatePairs(&pairs);
    }
    // The log is created by then if QUADPHASE_VALIDATE_LOG was obeyed; otherwise there is nothing to look for.
    char canonical[PATH_MAX];
    const char* log = realpath(argv[1], canonical) != nullptr ? LogDescriptor(canonical) : "none";
    std::printf("at_secure=%d nosuid=%d no_new_privs=%d validate=%d stock_tree=%d strict=%d log=%s\n",
                getauxval(AT_SECURE) != 0 ? 1 : 0, OnNosuidFileSystem() ? 1 : 0,
                prctl(PR_GET_NO_NEW_PRIVS, 0, 0, 0, 0) == 1 ? 1 : 0, validate ? 1 : 0, stockTree ? 1 : 0,
                strict ? 1 : 0, log);
    return 0;
}
