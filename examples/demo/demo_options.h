// Command-line options shared by quadphase-demo (side_by_side.cpp) and its two workers (step_scene.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "quadphase_scenes/scene_options.h"
#include "quadphase_scenes/scenes.h"

namespace quadphase::demo
{

using scenes::ParseInteger;
using scenes::UsageError;
using scenes::WalkOptions;

struct Options
{
    std::string scene = "rain";
    scenes::SceneId sceneId = scenes::SceneId::Rain;
    int size = -1; ///< -1: the scene's default size
    int steps = 300;
    int warmup = 10;
    uint32_t seed = 1;
    bool validate = false;
    bool timing = false;
    bool json = false;
    int repeat = 1; ///< quadphase-demo only
    bool help = false;
};

/// Which options a program accepts besides the common ones.
struct Accepts
{
    bool repeat = false;
};

/// Parses argv (without argv[0]). Accepts "--name value" and "--name=value". Throws UsageError.
inline Options ParseOptions(const std::vector<std::string>& args, Accepts accepts)
{
    Options options;
    bool warmupGiven = false;
    WalkOptions(args, [&](const std::string& name, auto&& takeValue, auto&& noValue, const std::string& raw) {
        if (name == "--help" || name == "-h")
        {
            noValue();
            options.help = true;
        }
        else if (scenes::ParseSceneOption(name, takeValue, options))
        {
            // --scene, --size, --steps or --seed
        }
        else if (name == "--warmup")
        {
            options.warmup = static_cast<int>(ParseInteger(name, takeValue(), 0, 10000000));
            warmupGiven = true;
        }
        else if (name == "--validate")
        {
            noValue();
            options.validate = true;
        }
        else if (name == "--timing")
        {
            noValue();
            options.timing = true;
        }
        else if (name == "--json")
        {
            noValue();
            options.json = true;
        }
        else if (name == "--repeat" && accepts.repeat)
        {
            options.repeat = static_cast<int>(ParseInteger(name, takeValue(), 1, 1000));
        }
        else
        {
            throw UsageError("unknown option '" + raw + "'");
        }
    });
    if (options.help)
    {
        return options;
    }

    scenes::ResolveSceneSize(options.sceneId, options.size);
    if (!warmupGiven && options.warmup >= options.steps)
    {
        options.warmup = options.steps / 10;
    }
    if (options.warmup >= options.steps)
    {
        throw UsageError("--warmup (" + std::to_string(options.warmup) + ") must be smaller than --steps (" +
                         std::to_string(options.steps) + ")");
    }
    return options;
}

/// The scene table for --help.
inline std::string SceneHelp()
{
    std::string text;
    for (const scenes::SceneInfo& info : scenes::AllScenes())
    {
        std::string name = info.name;
        name.resize(11, ' ');
        text += "  " + name + info.description + "\n";
        text += "             size = " + std::string(info.sizeMeaning) + ", " + std::to_string(info.minSize) +
                ".." + std::to_string(info.maxSize) + ", default " + std::to_string(info.defaultSize) + "\n";
    }
    return text;
}

} // namespace quadphase::demo
