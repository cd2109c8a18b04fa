// SPDX-License-Identifier: MIT
// quadphase-scene: runs quadphase-scene-quadtree or quadphase-scene-stock (found in this program's directory)
// according to --broadphase, with the same arguments. Two programs because the two Box2D builds define the
// same symbols with different class layouts and cannot share one process.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "scene_cli_options.h"

int main(int argc, char** argv)
{
    using quadphase::scene_cli::UsageError;
    const std::vector<std::string> args(argv + 1, argv + argc);
    std::string broadphase;
    try
    {
        broadphase = quadphase::scene_cli::FindBroadphase(args);
    }
    catch (const UsageError& error)
    {
        std::fprintf(stderr, "quadphase-scene: error: %s\n", error.what());
        return 2;
    }

    std::vector<char> self(4096);
    const ssize_t length = readlink("/proc/self/exe", self.data(), self.size() - 1);
    if (length <= 0)
    {
        std::fprintf(stderr, "quadphase-scene: error: cannot read /proc/self/exe: %s\n",
                     std::strerror(errno));
        return 1;
    }
    std::string path(self.data(), size_t(length));
    path = path.substr(0, path.rfind('/') + 1) + "quadphase-scene-" + broadphase;

    std::vector<char*> workerArgv;
    workerArgv.push_back(path.data());
    for (int i = 1; i < argc; ++i)
    {
        workerArgv.push_back(argv[i]);
    }
    workerArgv.push_back(nullptr);
    execv(path.c_str(), workerArgv.data());
    std::fprintf(stderr, "quadphase-scene: error: cannot run %s: %s (build the target quadphase-scene)\n",
                 path.c_str(), std::strerror(errno));
    return 1;
}
