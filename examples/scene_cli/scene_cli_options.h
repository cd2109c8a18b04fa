// SPDX-License-Identifier: MIT
// Command-line options of quadphase-scene and its two workers (quadphase-scene-quadtree,
// quadphase-scene-stock).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "quadphase_scenes/scenes.h"
#include "scene_options.h"

namespace quadphase::scene_cli
{

/// A command-line mistake: the program prints "quadphase-scene: error: <message>" and exits with status 2.
using scenes::UsageError;

/// A world rectangle, metres.
struct ViewRect
{
    float minX = 0.0f;
    float minY = 0.0f;
    float maxX = 0.0f;
    float maxY = 0.0f;
};

struct Options
{
    scenes::SceneId sceneId = scenes::SceneId::Rain;
    std::string scene = "rain";
    int size = -1; ///< the scene's default size until ParseOptions resolves it
    int steps = 600;
    uint32_t seed = 1;
    std::string broadphase = "quadtree"; ///< "quadtree" or "stock"
    int threads = -1;                    ///< quadtree pair-generation threads; -1: the library's default
    std::string pngDir;                  ///< empty: no frames
    int every = 10;                      ///< render a frame every this many steps
    int width = 800;
    int height = 600;
    bool autoView = true;
    ViewRect view;       ///< when !autoView
    bool overlay = true; ///< draw the quadtree's occupied cells (quadtree build only)
    std::string gifPath; ///< empty: no GIF
    std::string mp4Path; ///< empty: no MP4
    int fps = 30;        ///< animation frames per second
    bool quiet = false;  ///< no per-second summary lines
    bool help = false;
};

/// Parses argv without argv[0]: "--name value" or "--name=value". Resolves the scene and its default size and
/// checks every value and combination; throws UsageError with a message naming the option on any mistake.
Options ParseOptions(const std::vector<std::string>& args);

/// The --help text (every option, the scenes with their size ranges).
std::string HelpText(const char* program);

/// The value of --broadphase in `args` without checking anything else ("quadtree" when absent). Throws
/// UsageError for a missing or unknown value. Used by the front program to pick its worker.
std::string FindBroadphase(const std::vector<std::string>& args);

} // namespace quadphase::scene_cli
