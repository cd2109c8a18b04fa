// SPDX-License-Identifier: MIT
// Runs quadphase-scene (the front, so both workers and the --broadphase switch are exercised): every scene
// for a few steps in both builds writes valid PNG frames of the asked size; GIF and MP4 come out of ffmpeg;
// bad options exit with status 2 and a message.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "quadphase_scenes/scenes.h"

namespace
{

struct Result
{
    int status = -1;    ///< exit status, -1 when it did not exit normally
    std::string output; ///< stdout and stderr
};

std::string Quote(const std::string& text)
{
    std::string quoted = "'";
    for (char c : text)
    {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}

Result RunScene(const std::vector<std::string>& args)
{
    std::string command = Quote(QUADPHASE_SCENE_FRONT);
    for (const std::string& arg : args)
    {
        command += " " + Quote(arg);
    }
    command += " 2>&1";
    Result result;
    FILE* pipe = popen(command.c_str(), "r");
    REQUIRE(pipe != nullptr);
    char buffer[4096];
    size_t got = 0;
    while ((got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0)
    {
        result.output.append(buffer, got);
    }
    const int status = pclose(pipe);
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

std::vector<unsigned char> ReadFile(const std::string& path)
{
    std::ifstream file(path, std::ios::binary);
    return std::vector<unsigned char>(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

uint32_t BigEndian32(const std::vector<unsigned char>& bytes, size_t at)
{
    return (uint32_t(bytes[at]) << 24) | (uint32_t(bytes[at + 1]) << 16) | (uint32_t(bytes[at + 2]) << 8) |
           uint32_t(bytes[at + 3]);
}

/// Checks the PNG signature, that the first chunk is a 13-byte IHDR, its width and height, and the IEND
/// trailer.
void CheckPng(const std::string& path, uint32_t width, uint32_t height)
{
    INFO("PNG " << path);
    const std::vector<unsigned char> bytes = ReadFile(path);
    REQUIRE(bytes.size() > 8 + 25 + 12);
    const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    CHECK(std::equal(signature, signature + 8, bytes.begin()));
    CHECK(BigEndian32(bytes, 8) == 13);
    CHECK(std::string(bytes.begin() + 12, bytes.begin() + 16) == "IHDR");
    CHECK(BigEndian32(bytes, 16) == width);
    CHECK(BigEndian32(bytes, 20) == height);
    CHECK(std::string(bytes.end() - 8, bytes.end() - 4) == "IEND");
}

} // namespace

TEST_CASE("every scene runs a few steps in both builds and writes valid PNG frames", "[scene_cli][run]")
{
    for (const quadphase::scenes::SceneInfo& info : quadphase::scenes::AllScenes())
    {
        for (const char* broadphase : {"quadtree", "stock"})
        {
            const int size = std::max(info.minSize, std::min(info.defaultSize, 100));
            const std::string dir = std::string(QUADPHASE_SCENE_OUT) + "/" + info.name + "_" + broadphase;
            std::remove((dir + "/frame_00000.png").c_str());
            std::remove((dir + "/frame_00001.png").c_str());
            // Odd sizes, different per build: the header must carry exactly what was asked.
            const uint32_t width = broadphase[0] == 'q' ? 161 : 203;
            const uint32_t height = broadphase[0] == 'q' ? 97 : 120;
            const Result result =
                RunScene({"--scene", info.name, "--size", std::to_string(size), "--steps", "4", "--every",
                          "4", "--broadphase", broadphase, "--png", dir, "--width", std::to_string(width),
                          "--height", std::to_string(height)});
            INFO("scene " << info.name << " size " << size << ", " << broadphase << ":\n" << result.output);
            REQUIRE(result.status == 0);
            CHECK(result.output.find("done: 4 steps") != std::string::npos);
            CHECK(result.output.find(std::string("broadphase ") + broadphase) != std::string::npos);
            CHECK(result.output.find("2 frames") != std::string::npos);
            CheckPng(dir + "/frame_00000.png", width, height); // before the first step
            CheckPng(dir + "/frame_00001.png", width, height); // after step 4
        }
    }
}

TEST_CASE("GIF and MP4 animations through ffmpeg", "[scene_cli][run]")
{
    const std::string dir = std::string(QUADPHASE_SCENE_OUT) + "/animation";
    const std::string gif = dir + ".gif";
    const std::string mp4 = dir + ".mp4";
    std::remove(gif.c_str());
    std::remove(mp4.c_str());
    const Result result =
        RunScene({"--scene", "churn", "--size", "60", "--steps", "6", "--every", "2", "--png", dir, "--width",
                  "120", "--height", "90", "--gif", gif, "--mp4", mp4, "--quiet"});
    INFO(result.output);
    REQUIRE(result.status == 0);
    const std::vector<unsigned char> gifBytes = ReadFile(gif);
    REQUIRE(gifBytes.size() > 13);
    CHECK(std::string(gifBytes.begin(), gifBytes.begin() + 6) == "GIF89a");
    CHECK((gifBytes[6] | (gifBytes[7] << 8)) == 120); // logical screen width, little-endian
    CHECK((gifBytes[8] | (gifBytes[9] << 8)) == 90);
    const std::vector<unsigned char> mp4Bytes = ReadFile(mp4);
    REQUIRE(mp4Bytes.size() > 12);
    CHECK(std::string(mp4Bytes.begin() + 4, mp4Bytes.begin() + 8) == "ftyp");
}

TEST_CASE("bad options exit with status 2 and say why", "[scene_cli][run]")
{
    struct Case
    {
        std::vector<std::string> args;
        const char* expect;
    };
    const Case cases[] = {
        {{"--broadphase", "octree"}, "--broadphase must be 'quadtree' or 'stock'"},   // the front
        {{"--broadphase", "stock", "--scene", "drizzle"}, "unknown scene 'drizzle'"}, // stock worker
        {{"--size", "0"}, "--size must be in"},                                       // quadtree worker
        {{"--frobnicate"}, "unknown option '--frobnicate'"},
        {{"--gif", "x.gif"}, "give --png DIR too"},
    };
    for (const Case& c : cases)
    {
        const Result result = RunScene(c.args);
        INFO(result.output);
        CHECK(result.status == 2);
        CHECK(result.output.find("quadphase-scene: error: ") != std::string::npos);
        CHECK(result.output.find(c.expect) != std::string::npos);
    }
    const Result help = RunScene({"--help"});
    CHECK(help.status == 0);
    CHECK(help.output.find("--broadphase") != std::string::npos);
}
