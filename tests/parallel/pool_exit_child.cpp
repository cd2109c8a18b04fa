// SPDX-License-Identifier: MIT
// A program that ends while the library's pool has threads: a world destroyed by a static destructor at exit
// ("global"), or one the program never destroys ("leak"). Either way the process must exit normally, with status 0
// (no std::terminate over a joinable std::thread, no hang joining threads at exit); CTest runs both
// (tests/parallel/CMakeLists.txt).
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>

#include "quadphase/box2d.h"
#include "quadphase_scenes/scenes.h"

namespace
{

std::unique_ptr<quadphase::scenes::Scene> g_scene; // "global": destroyed after main returns
// "leak": never destroyed. The pointer is volatile so that the optimizer keeps the store (the variable is never read):
// the scene stays reachable from a global, and LeakSanitizer does not report it.
quadphase::scenes::Scene* volatile g_leaked = nullptr;

quadphase::scenes::Scene* BuildStepped()
{
    auto* scene = new quadphase::scenes::Scene(
        quadphase::scenes::BuildScene(quadphase::scenes::SceneId::Particles, 2000, 1));
    quadphase::Config config = quadphase::GetConfig(*scene->world);
    config.threads = 4; // three pool threads
    quadphase::Configure(*scene->world, config);
    for (int step = 0; step < 20; ++step)
    {
        quadphase::scenes::StepScene(*scene);
    }
    if (quadphase::GetStats(*scene->world).parallelCalls == 0)
    {
        std::fprintf(stderr, "pool_exit_child: no parallel call: the pool was never used\n");
        std::exit(2);
    }
    return scene;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc != 2 || (std::strcmp(argv[1], "global") != 0 && std::strcmp(argv[1], "leak") != 0))
    {
        std::fprintf(stderr, "usage: %s global|leak\n", argv[0]);
        return 2;
    }
    quadphase::scenes::Scene* scene = BuildStepped();
    if (std::strcmp(argv[1], "global") == 0)
    {
        g_scene.reset(scene);
    }
    else
    {
        g_leaked = scene; // the scene, its world and the pool's threads stay until the process ends
    }
    return 0;
}
