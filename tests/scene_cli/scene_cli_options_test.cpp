// SPDX-License-Identifier: MIT
// quadphase-scene's options parser: defaults, both option forms, and a clear UsageError for each kind of
// mistake.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "scene_cli_options.h"

namespace
{

using quadphase::scene_cli::Options;
using quadphase::scene_cli::ParseOptions;
using quadphase::scene_cli::UsageError;
using quadphase::scenes::SceneId;

Options Parse(std::vector<std::string> args)
{
    return ParseOptions(args);
}

/// The UsageError message of `args`, or "no error".
std::string ErrorOf(std::vector<std::string> args)
{
    try
    {
        ParseOptions(args);
    }
    catch (const UsageError& error)
    {
        return error.what();
    }
    return "no error";
}

} // namespace

TEST_CASE("defaults: rain at its default size, quadtree, no frames", "[scene_cli][options]")
{
    const Options options = Parse({});
    CHECK(options.sceneId == SceneId::Rain);
    CHECK(options.size == quadphase::scenes::GetSceneInfo(SceneId::Rain).defaultSize);
    CHECK(options.broadphase == "quadtree");
    CHECK(options.threads == -1);
    CHECK(Parse({"--broadphase", "stock"}).broadphase == "stock");
    CHECK(options.pngDir.empty());
    CHECK(options.every == 10);
    CHECK(options.autoView);
    CHECK(options.overlay);
    CHECK_FALSE(options.help);
}

TEST_CASE("every option, in both forms", "[scene_cli][options]")
{
    const Options options = Parse({"--scene",      "CHURN",  "--size=300",    "--steps",
                                   "42",           "--seed", "4294967295",    "--broadphase=quadtree",
                                   "--threads",    "1",      "--png",         "out/frames",
                                   "--every",      "3",      "--width",       "320",
                                   "--height=200", "--view", "-5,-2.5,5,2.5", "--no-overlay",
                                   "--gif",        "a.gif",  "--mp4=b.mp4",   "--fps",
                                   "12",           "--quiet"});
    CHECK(options.sceneId == SceneId::Churn);
    CHECK(options.scene == "churn");
    CHECK(options.size == 300);
    CHECK(options.steps == 42);
    CHECK(options.seed == 4294967295u);
    CHECK(options.broadphase == "quadtree");
    CHECK(options.threads == 1);
    CHECK(options.pngDir == "out/frames");
    CHECK(options.every == 3);
    CHECK(options.width == 320);
    CHECK(options.height == 200);
    CHECK_FALSE(options.autoView);
    CHECK(options.view.minX == -5.0f);
    CHECK(options.view.minY == -2.5f);
    CHECK(options.view.maxX == 5.0f);
    CHECK(options.view.maxY == 2.5f);
    CHECK_FALSE(options.overlay);
    CHECK(options.gifPath == "a.gif");
    CHECK(options.mp4Path == "b.mp4");
    CHECK(options.fps == 12);
    CHECK(options.quiet);
}

TEST_CASE("--help skips the checks of the other options", "[scene_cli][options]")
{
    CHECK(Parse({"--help"}).help);
    CHECK(Parse({"--size", "1", "-h"}).help);
    const std::string help = quadphase::scene_cli::HelpText("quadphase-scene");
    for (const char* option :
         {"--scene", "--size", "--steps", "--seed", "--broadphase", "--threads", "--png", "--every",
          "--width", "--height", "--view", "--no-overlay", "--gif", "--mp4", "--fps", "--quiet", "--help"})
    {
        INFO(option);
        CHECK(help.find(option) != std::string::npos);
    }
    for (const auto& info : quadphase::scenes::AllScenes())
    {
        CHECK(help.find(info.name) != std::string::npos);
    }
}

TEST_CASE("bad input is rejected with a message naming the problem", "[scene_cli][options]")
{
    struct Case
    {
        std::vector<std::string> args;
        const char* expect; // part of the message
    };
    const Case cases[] = {
        {{"--bogus"}, "unknown option '--bogus'"},
        {{"rain"}, "unknown option 'rain'"},
        {{"--scene", "drizzle"}, "unknown scene 'drizzle'"},
        {{"--scene"}, "--scene needs a value"},
        {{"--size", "abc"}, "--size expects an integer, got 'abc'"},
        {{"--size", "12x"}, "expects an integer"},
        {{"--size", ""}, "expects an integer"},
        {{"--size", "0"}, "--size must be in"},
        {{"--scene", "pyramid", "--size", "201"}, "outside the range of scene 'pyramid'"},
        {{"--steps", "-1"}, "--steps must be in"},
        {{"--seed", "4294967296"}, "--seed must be in"},
        {{"--broadphase", "bvh"}, "--broadphase must be 'quadtree' or 'stock', got 'bvh'"},
        {{"--png", ""}, "--png needs a directory"},
        {{"--threads", "-1"}, "--threads must be in"},
        {{"--threads", "2", "--broadphase", "stock"}, "needs --broadphase quadtree"},
        {{"--every", "0", "--png", "d"}, "--every must be in"},
        {{"--every", "5"}, "give --png DIR too"},
        {{"--width", "15"}, "--width must be in"},
        {{"--height", "9000"}, "--height must be in"},
        {{"--view", "0,0,1"}, "four numbers"},
        {{"--view", "0,0,1,1,2"}, "four numbers"},
        {{"--view", "0,0,x,1"}, "expects a finite number, got 'x'"},
        {{"--view", "1,0,0,1"}, "MINX must be below MAXX"},
        {{"--view", "0,0,1,nan"}, "finite number"},
        {{"--gif", "a.png", "--png", "d"}, "ending in .gif"},
        {{"--mp4", "a.avi", "--png", "d"}, "ending in .mp4"},
        {{"--gif", "a.gif"}, "give --png DIR too"},
        {{"--fps", "0"}, "--fps must be in"},
        {{"--quiet=yes"}, "--quiet takes no value"},
        {{"--no-overlay=1"}, "takes no value"},
    };
    for (const Case& c : cases)
    {
        std::string joined;
        for (const std::string& arg : c.args)
        {
            joined += "[" + arg + "] ";
        }
        INFO("args " << joined);
        const std::string message = ErrorOf(c.args);
        CHECK(message.find(c.expect) != std::string::npos);
    }
}

TEST_CASE("FindBroadphase picks the worker and checks only --broadphase", "[scene_cli][options]")
{
    using quadphase::scene_cli::FindBroadphase;
    CHECK(FindBroadphase({}) == "quadtree");
    CHECK(FindBroadphase({"--scene", "rain", "--broadphase", "stock"}) == "stock");
    CHECK(FindBroadphase({"--broadphase=quadtree", "--bogus"}) == "quadtree");
    CHECK_THROWS_AS(FindBroadphase({"--broadphase", "octree"}), UsageError);
    CHECK_THROWS_AS(FindBroadphase({"--broadphase"}), UsageError);
}
