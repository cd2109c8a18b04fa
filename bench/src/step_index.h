// SPDX-License-Identifier: MIT
// The ".steps" side file of a trace (qp-record writes it, qp-replay reads it): the op index of every world-step
// boundary.
#pragma once

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace qpbench
{

// ---------------------------------------------------------------------------------------------------------------
// The ".steps" side file qp-record writes next to a trace: which scene it came from and the op index of every
// world-step boundary, so a replay can time the broadphase work of each step.
//
// Text format, one "key value..." per line:
//     qp-steps 1
//     scene particles
//     size 50000
//     seed 1
//     warmup 60            steps replayed untimed (they bring the broadphase to the recorded state)
//     steps 30             steps timed
//     bodies 50001         at the end of the recording
//     proxies 50004        at the end of the recording
//     boundary 50004       op index where step 0 starts (the ops before it create the scene's proxies)
//     boundary 100321      op index where step 1 starts / step 0 ends
//     ...                  warmup + steps + 1 boundary lines in all
// Step k (0-based) is ops [boundary[k], boundary[k+1]): everything the broadphase was asked between the start
// of world.Step number k and the start of world.Step number k+1 (including what the scene's perStep did in
// between).
// ---------------------------------------------------------------------------------------------------------------
struct StepIndex
{
    std::string scene;
    int size = 0, warmup = 0, steps = 0;
    uint32_t seed = 0;
    int64_t bodies = 0, proxies = 0; // at the end of the recording
    std::vector<uint64_t> boundary;  // warmup + steps + 1 entries

    bool Save(const std::string& path, std::string& error) const
    {
        std::ofstream out(path);
        const bool opened = out.is_open(); // a stream that failed to open writes nothing below
        out << "qp-steps 1\n";
        out << "scene " << scene << "\nsize " << size << "\nseed " << seed << "\n";
        out << "warmup " << warmup << "\nsteps " << steps << "\n";
        out << "bodies " << bodies << "\nproxies " << proxies << "\n";
        for (uint64_t b : boundary)
        {
            out << "boundary " << b << "\n";
        }
        error = !opened ? "cannot open " + path + " for writing" : !out ? "cannot write " + path : "";
        return error.empty();
    }

    bool Load(const std::string& path, std::string& error)
    {
        std::ifstream in(path);
        if (!in)
        {
            error = "cannot open " + path;
            return false;
        }
        int version = 0;
        std::string line;
        boundary.clear();
        while (std::getline(in, line))
        {
            std::istringstream fields(line);
            std::string key;
            fields >> key;
            const auto field = [&](const char* name, auto& value) {
                if (key == name)
                {
                    fields >> value;
                }
            };
            if (key == "boundary")
            {
                fields >> boundary.emplace_back();
            }
            field("qp-steps", version);
            field("scene", scene);
            field("size", size);
            field("seed", seed);
            field("warmup", warmup);
            field("steps", steps);
            field("bodies", bodies);
            field("proxies", proxies);
        }
        const bool counted =
            warmup >= 0 && steps > 0 && boundary.size() == size_t(warmup) + size_t(steps) + 1;
        error = version != 1 ? path + " is not a qp-steps v1 file"
                : !counted   ? path + ": expected warmup + steps + 1 boundary lines"
                : !std::is_sorted(boundary.begin(), boundary.end()) ? path + ": boundaries are not increasing"
                                                                    : "";
        return error.empty();
    }
};

} // namespace qpbench
