// Command-line options shared by quadphase-demo (side_by_side.cpp) and its two workers (step_scene.cpp).
#pragma once

#include <charconv>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "quadphase_scenes/scenes.h"

namespace quadphase::demo
{

/// A command-line mistake: the program prints the message and exits with status 2.
class UsageError : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

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

inline int64_t ParseInteger(std::string_view option, std::string_view text, int64_t lo, int64_t hi)
{
    int64_t value = 0;
    const char* first = text.data();
    const char* last = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(first, last, value);
    if (text.empty() || ec != std::errc() || ptr != last)
    {
        throw UsageError("option " + std::string(option) + " expects an integer, got '" + std::string(text) +
                         "'");
    }
    if (value < lo || value > hi)
    {
        throw UsageError("option " + std::string(option) + " must be in [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "], got " + std::to_string(value));
    }
    return value;
}

/// Parses argv (without argv[0]). Accepts "--name value" and "--name=value". Throws UsageError.
inline Options ParseOptions(const std::vector<std::string>& args, Accepts accepts)
{
    Options options;
    bool warmupGiven = false;
    for (size_t i = 0; i < args.size(); ++i)
    {
        std::string name = args[i];
        std::string value;
        bool hasValue = false;
        const size_t equals = name.find('=');
        if (name.rfind("--", 0) == 0 && equals != std::string::npos)
        {
            value = name.substr(equals + 1);
            name = name.substr(0, equals);
            hasValue = true;
        }
        auto takeValue = [&]() -> std::string {
            if (hasValue)
            {
                return value;
            }
            if (i + 1 >= args.size())
            {
                throw UsageError("option " + name + " needs a value");
            }
            return args[++i];
        };
        auto noValue = [&]() {
            if (hasValue)
            {
                throw UsageError("option " + name + " takes no value");
            }
        };

        if (name == "--help" || name == "-h")
        {
            noValue();
            options.help = true;
        }
        else if (name == "--scene")
        {
            options.scene = takeValue();
            const auto id = scenes::ParseSceneName(options.scene);
            if (!id)
            {
                throw UsageError("unknown scene '" + options.scene + "' (scenes: " + scenes::SceneNameList() +
                                 ")");
            }
            options.sceneId = *id;
            options.scene = scenes::SceneName(*id);
        }
        else if (name == "--size")
        {
            options.size = static_cast<int>(ParseInteger(name, takeValue(), 1, 100000000));
        }
        else if (name == "--steps")
        {
            options.steps = static_cast<int>(ParseInteger(name, takeValue(), 1, 10000000));
        }
        else if (name == "--warmup")
        {
            options.warmup = static_cast<int>(ParseInteger(name, takeValue(), 0, 10000000));
            warmupGiven = true;
        }
        else if (name == "--seed")
        {
            options.seed = static_cast<uint32_t>(ParseInteger(name, takeValue(), 0, UINT32_MAX));
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
            throw UsageError("unknown option '" + args[i] + "'");
        }
    }
    if (options.help)
    {
        return options;
    }

    const scenes::SceneInfo& info = scenes::GetSceneInfo(options.sceneId);
    if (options.size < 0)
    {
        options.size = info.defaultSize;
    }
    else if (options.size < info.minSize || options.size > info.maxSize)
    {
        throw UsageError("--size " + std::to_string(options.size) + " is outside the range of scene '" +
                         info.name + "' [" + std::to_string(info.minSize) + ", " +
                         std::to_string(info.maxSize) + "] (size = " + info.sizeMeaning + ")");
    }
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
