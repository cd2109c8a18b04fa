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
// Step k (0-based) is ops [boundary[k], boundary[k+1]): everything the broadphase was asked between the start of
// world.Step number k and the start of world.Step number k+1 (including what the scene's perStep did in between).
#pragma once

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace qpbench
{

struct StepIndex
{
    std::string scene;
    int size = 0;
    uint32_t seed = 0;
    int warmup = 0;
    int steps = 0;
    int64_t bodies = 0;
    int64_t proxies = 0;
    std::vector<uint64_t> boundary; // warmup + steps + 1 entries

    bool Save(const std::string& path, std::string& error) const
    {
        std::ofstream out(path);
        if (!out)
        {
            error = "cannot open " + path + " for writing";
            return false;
        }
        out << "qp-steps 1\n";
        out << "scene " << scene << "\nsize " << size << "\nseed " << seed << "\n";
        out << "warmup " << warmup << "\nsteps " << steps << "\n";
        out << "bodies " << bodies << "\nproxies " << proxies << "\n";
        for (uint64_t b : boundary)
        {
            out << "boundary " << b << "\n";
        }
        if (!out)
        {
            error = "cannot write " + path;
            return false;
        }
        return true;
    }

    bool Load(const std::string& path, std::string& error)
    {
        std::ifstream in(path);
        if (!in)
        {
            error = "cannot open " + path;
            return false;
        }
        std::string line;
        bool header = false;
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
            if (key == "qp-steps")
            {
                int version = 0;
                fields >> version;
                header = version == 1;
            }
            else if (key == "boundary")
            {
                boundary.emplace_back();
                fields >> boundary.back();
            }
            field("scene", scene);
            field("size", size);
            field("seed", seed);
            field("warmup", warmup);
            field("steps", steps);
            field("bodies", bodies);
            field("proxies", proxies);
        }
        if (!header)
        {
            error = path + " is not a qp-steps v1 file";
            return false;
        }
        if (warmup < 0 || steps <= 0 || boundary.size() != size_t(warmup) + size_t(steps) + 1)
        {
            error = path + ": expected warmup + steps + 1 boundary lines";
            return false;
        }
        for (size_t i = 1; i < boundary.size(); ++i)
        {
            if (boundary[i] < boundary[i - 1])
            {
                error = path + ": boundaries are not increasing";
                return false;
            }
        }
        return true;
    }
};

} // namespace qpbench
