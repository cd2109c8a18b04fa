// SPDX-License-Identifier: MIT
// quadphase-scene-quadtree / quadphase-scene-stock: steps one scene, prints a summary per simulated second,
// renders PNG frames and animations. The same source is compiled against each Box2D build (see
// CMakeLists.txt); quadphase-scene (front.cpp) picks one with --broadphase.
#include <sys/stat.h>

#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "animation.h"
#include "box2d/box2d.h"
#include "frame_renderer.h"
#include "quadphase_scenes/scenes.h"
#include "quadphase_tools/counting_filter.h"
#include "quadtree_overlay.h"
#include "scene_cli_options.h"
#include "view_bounds.h"

#if QUADPHASE_VARIANT_QUADPHASE
#include "quadphase/box2d.h"
constexpr const char* kBroadphase = "quadtree";
#elif QUADPHASE_VARIANT_STOCK
constexpr const char* kBroadphase = "stock";
#else
#error                                                                                                       \
    "compile with QUADPHASE_VARIANT_QUADPHASE=1 or QUADPHASE_VARIANT_STOCK=1 (quadphase_link_box2d_variant)"
#endif

namespace
{

using namespace quadphase::scene_cli;
namespace scenes = quadphase::scenes;

using quadphase::tools::CountingFilter;

int32_t CountAwake(const b2World& world)
{
    int32_t awake = 0;
    for (const b2Body* body = world.GetBodyList(); body != nullptr; body = body->GetNext())
    {
        awake += (body->GetType() != b2_staticBody && body->IsAwake()) ? 1 : 0;
    }
    return awake;
}

/// Creates `path` and its missing parents (mkdir -p).
void MakeDirectories(const std::string& path)
{
    for (size_t slash = path.find('/', 1);; slash = path.find('/', slash + 1))
    {
        const std::string prefix = path.substr(0, slash);
        if (!prefix.empty() && mkdir(prefix.c_str(), 0777) != 0 && errno != EEXIST)
        {
            throw std::runtime_error("cannot create directory " + prefix + ": " + std::strerror(errno));
        }
        if (slash == std::string::npos)
        {
            break;
        }
    }
    struct stat info;
    if (stat(path.c_str(), &info) != 0 || !S_ISDIR(info.st_mode))
    {
        throw std::runtime_error(path + " is not a directory");
    }
}

std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Format(const char* format, ...)
{
    char buffer[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(buffer, sizeof buffer, format, args);
    va_end(args);
    return buffer;
}

int Run(const Options& options)
{
    if (options.broadphase != kBroadphase)
    {
        throw UsageError(std::string("this program is the ") + kBroadphase +
                         " build; run quadphase-scene --broadphase " + options.broadphase);
    }
    scenes::Scene scene = scenes::BuildScene(options.sceneId, options.size, options.seed);
    b2World& world = *scene.world;
    CountingFilter filter;
    world.SetContactFilter(&filter);
#if QUADPHASE_VARIANT_QUADPHASE
    if (options.threads >= 0)
    {
        quadphase::Config config = quadphase::GetConfig(world);
        config.threads = options.threads;
        quadphase::Configure(world, config);
    }
#endif

    const bool render = !options.pngDir.empty();
    const ViewRect view = options.autoView ? AutoView(world) : options.view;
    FrameRenderer renderer(options.width, options.height, view);
    int frames = 0;
    if (render)
    {
        MakeDirectories(options.pngDir);
    }

    std::string note;
    if (kBroadphase == std::string("stock"))
    {
        note = " (Box2D's b2DynamicTree: no quadtree overlay)";
    }
    else if (options.threads >= 0)
    {
        note = ", " + std::to_string(options.threads) + " pair-generation threads";
    }
    std::printf("quadphase-scene: %s, size %d, seed %" PRIu32 ", %d steps of %.4f s, broadphase %s%s\n",
                options.scene.c_str(), options.size, options.seed, options.steps, double(scene.timeStep),
                kBroadphase, note.c_str());
    if (render)
    {
        std::printf("quadphase-scene: frames every %d steps into %s/, view [%.1f, %.1f] x [%.1f, %.1f] m\n",
                    options.every, options.pngDir.c_str(), double(view.minX), double(view.maxX),
                    double(view.minY), double(view.maxY));
    }

    auto renderFrame = [&]() {
        const Overlay overlay = options.overlay ? CollectOverlay(world) : Overlay{};
        FrameText text;
        text.lines.push_back(Format("%s %d  seed %" PRIu32 "  broadphase: %s", options.scene.c_str(),
                                    options.size, options.seed, kBroadphase));
        text.lines.push_back(Format("step %d  t %.2f s  bodies %d  awake %d  contacts %d", scene.stepCount,
                                    double(scene.stepCount) * double(scene.timeStep), world.GetBodyCount(),
                                    CountAwake(world), world.GetContactCount()));
        if (overlay.available)
        {
            text.lines.push_back(Format("quadtree depth %d, %zu occupied cells, fullest %d", overlay.depth,
                                        overlay.cells.size(), overlay.largestCount));
        }
        else if (!options.overlay)
        {
            text.lines.push_back("overlay off (--no-overlay)");
        }
        else
        {
            text.lines.push_back("stock b2DynamicTree: no quadtree to draw");
        }
        renderer.Render(world, overlay, options.overlay, text, options.pngDir + "/" + FrameFileName(frames));
        ++frames;
    };

    if (render)
    {
        renderFrame();
    }

    const int stepsPerSecond = static_cast<int>(1.0f / scene.timeStep + 0.5f);
    double broadphaseMs = 0.0;
    double totalBroadphaseMs = 0.0;
    int64_t pairsBefore = 0;
    int intervalSteps = 0;
    const auto start = std::chrono::steady_clock::now();
    for (int step = 0; step < options.steps; ++step)
    {
        scenes::StepScene(scene);
        const double ms = double(world.GetProfile().broadphase);
        broadphaseMs += ms;
        totalBroadphaseMs += ms;
        ++intervalSteps;
        if (render && scene.stepCount % options.every == 0)
        {
            renderFrame();
        }
        if (scene.stepCount % stepsPerSecond == 0 || step + 1 == options.steps)
        {
            if (!options.quiet)
            {
                std::printf("t %6.2f s  bodies %6d  awake %6d  contacts %7d  pairs %7" PRId64
                            "  broadphase %7.3f ms/step\n",
                            double(scene.stepCount) * double(scene.timeStep), world.GetBodyCount(),
                            CountAwake(world), world.GetContactCount(), filter.calls - pairsBefore,
                            broadphaseMs / intervalSteps);
                std::fflush(stdout);
            }
            pairsBefore = filter.calls;
            broadphaseMs = 0.0;
            intervalSteps = 0;
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::printf(
        "quadphase-scene: done: %d steps in %.2f s wall time (rendering included), broadphase mean %.3f "
        "ms/step, %" PRId64 " new pairs",
        options.steps, seconds, totalBroadphaseMs / options.steps, filter.calls);
#if QUADPHASE_VARIANT_QUADPHASE
    {
        const quadphase::Stats stats = quadphase::GetStats(world);
        std::printf(", quadtree depth %d, %" PRId64 " occupied cells", stats.depth, stats.occupiedCells);
    }
#else
    std::printf(", stock build: no quadtree overlay");
#endif
    std::printf("\n");
    if (render)
    {
        std::printf("quadphase-scene: %d frames in %s/\n", frames, options.pngDir.c_str());
    }
    for (const std::string& output : {options.gifPath, options.mp4Path})
    {
        if (!output.empty())
        {
            MakeAnimation(options.pngDir, options.fps, output);
            std::printf("quadphase-scene: wrote %s\n", output.c_str());
        }
    }
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    const std::vector<std::string> args(argv + 1, argv + argc);
    Options options;
    try
    {
        options = ParseOptions(args);
    }
    catch (const UsageError& error)
    {
        std::fprintf(stderr, "quadphase-scene: error: %s\n", error.what());
        return 2;
    }
    if (options.help)
    {
        std::fputs(HelpText("quadphase-scene").c_str(), stdout);
        return 0;
    }
    try
    {
        return Run(options);
    }
    catch (const UsageError& error)
    {
        std::fprintf(stderr, "quadphase-scene: error: %s\n", error.what());
        return 2;
    }
    catch (const std::exception& error)
    {
        std::fprintf(stderr, "quadphase-scene: error: %s\n", error.what());
        return 1;
    }
}
