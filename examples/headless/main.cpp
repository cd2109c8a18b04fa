// SPDX-License-Identifier: MIT
// quadphase-headless: every example scene stepped without a window, with validation on: at every step a shadow
// b2DynamicTree (Box2D 2.4.1's own broadphase logic) checks the quadtree's pairs and fat AABBs. Prints, per scene,
// the validation counts and a hash of the bodies' positions and angles, then one hash over all scenes: the line to
// compare between builds of the same source (GCC and x86-64, clang and libc++, WebAssembly under Node.js).
//
//   quadphase-headless [--steps N] [--scale F]
//     --steps N   steps per scene (default 300)
//     --scale F   each scene at F x its default size, at least its minimum (default 0.25)
//
// Exit status: 0 when no scene has a validation mismatch, 1 otherwise, 2 for a bad argument.
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "quadphase/box2d.h"
#include "quadphase_scenes/scenes.h"

namespace
{

struct Options
{
    int steps = 300;
    double scale = 0.25;
};

bool ParsePositive(const char* text, double& out)
{
    char* end = nullptr;
    out = std::strtod(text, &end);
    return end != text && *end == '\0' && out > 0.0;
}

bool Parse(int argc, char** argv, Options& options)
{
    for (int i = 1; i < argc; ++i)
    {
        double value = 0.0;
        const bool hasValue = i + 1 < argc && ParsePositive(argv[i + 1], value);
        if (std::strcmp(argv[i], "--steps") == 0 && hasValue && value == double(int(value)))
        {
            options.steps = int(value);
        }
        else if (std::strcmp(argv[i], "--scale") == 0 && hasValue)
        {
            options.scale = value;
        }
        else
        {
            std::fprintf(stderr,
                         "quadphase-headless: bad argument '%s'\nusage: %s [--steps N > 0] [--scale F > 0]\n",
                         argv[i], argv[0]);
            return false;
        }
        ++i;
    }
    return true;
}

void HashU64(uint64_t& hash, uint64_t value)
{
    for (int byte = 0; byte < 8; ++byte)
    {
        hash ^= (value >> (8 * byte)) & 0xffu;
        hash *= 1099511628211ull; // FNV-1a, as HashBodyPositions
    }
}

} // namespace

int main(int argc, char** argv)
{
    Options options;
    if (!Parse(argc, argv, options))
    {
        return 2;
    }
    std::printf("%-10s %6s %6s %8s %14s %10s  %s\n", "scene", "size", "steps", "checks", "pairs compared",
                "mismatches", "position hash");
    uint64_t all = 14695981039346656037ull;
    int64_t mismatches = 0;
    for (const quadphase::scenes::SceneInfo& info : quadphase::scenes::AllScenes())
    {
        const int size = std::clamp(int(info.defaultSize * options.scale), info.minSize, info.maxSize);
        quadphase::scenes::Scene scene = quadphase::scenes::BuildScene(info.id, size, 1);
        quadphase::SetValidation(*scene.world, true);
        for (int step = 0; step < options.steps; ++step)
        {
            quadphase::scenes::StepScene(scene);
        }
        const quadphase::ValidationReport report = quadphase::GetValidationReport(*scene.world);
        const uint64_t hash = quadphase::scenes::HashBodyPositions(*scene.world);
        HashU64(all, hash);
        mismatches += report.mismatches;
        std::printf("%-10s %6d %6d %8" PRId64 " %14" PRId64 " %10" PRId64 "  %016" PRIx64 "\n", info.name,
                    size, options.steps, report.checks, report.pairsCompared, report.mismatches, hash);
        if (report.mismatches > 0)
        {
            std::printf("  first mismatch: %s\n", report.firstMismatch.c_str());
        }
    }
    std::printf("all scenes: %" PRId64 " mismatches, position hash %016" PRIx64 "\n", mismatches, all);
    return mismatches == 0 ? 0 : 1;
}
