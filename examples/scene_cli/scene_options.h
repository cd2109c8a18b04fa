// SPDX-License-Identifier: MIT
// The command-line values of quadphase-scene and its workers (CLI11 splits the command line,
// scene_cli_options.cpp): integers with their range, and the scene options --scene, --size, --steps and --seed
// with the check of --size against the scene's range.
#pragma once

#include <charconv>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "quadphase_scenes/scenes.h"

namespace quadphase::scenes
{

/// A command-line mistake: the program prints the message and exits with status 2.
class UsageError : public std::runtime_error
{
public:
    using std::runtime_error::runtime_error;
};

/// `text` as an integer in [lo, hi]; throws UsageError naming `option` otherwise.
inline int64_t ParseInteger(std::string_view option, std::string_view text, int64_t lo, int64_t hi)
{
    int64_t value = 0;
    const char* last = text.data() + text.size();
    const auto [ptr, ec] = std::from_chars(text.data(), last, value);
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

/// Handles --scene, --size, --steps and --seed into `options` (any struct with members sceneId, scene, size,
/// steps and seed); false for any other option name. Throws UsageError for an unknown scene or a value out of
/// range. --size is checked against the scene by ResolveSceneSize, once every option is read.
template <typename Options, typename TakeValue>
bool ParseSceneOption(const std::string& name, TakeValue&& takeValue, Options& options)
{
    if (name == "--scene")
    {
        const std::string value = takeValue();
        const auto id = ParseSceneName(value);
        if (!id)
        {
            throw UsageError("unknown scene '" + value + "' (scenes: " + SceneNameList() + ")");
        }
        options.sceneId = *id;
        options.scene = SceneName(*id);
    }
    else if (name == "--size")
    {
        options.size = static_cast<int>(ParseInteger(name, takeValue(), 1, 100000000));
    }
    else if (name == "--steps")
    {
        options.steps = static_cast<int>(ParseInteger(name, takeValue(), 1, 10000000));
    }
    else if (name == "--seed")
    {
        options.seed = static_cast<uint32_t>(ParseInteger(name, takeValue(), 0, UINT32_MAX));
    }
    else
    {
        return false;
    }
    return true;
}

/// Gives `size` its scene's default when it is negative (not given); throws UsageError when it is outside the
/// scene's range.
inline void ResolveSceneSize(SceneId sceneId, int& size)
{
    const SceneInfo& info = GetSceneInfo(sceneId);
    if (size < 0)
    {
        size = info.defaultSize;
    }
    else if (size < info.minSize || size > info.maxSize)
    {
        throw UsageError("--size " + std::to_string(size) + " is outside the range of scene '" + info.name +
                         "' [" + std::to_string(info.minSize) + ", " + std::to_string(info.maxSize) +
                         "] (size = " + info.sizeMeaning + ")");
    }
}

} // namespace quadphase::scenes
