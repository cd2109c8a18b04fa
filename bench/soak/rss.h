// Resident memory of this process, from /proc/self/status (Linux).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace qpsoak
{

struct Rss
{
    long currentKiB = -1; ///< VmRSS: resident now
    long peakKiB = -1;    ///< VmHWM: the largest VmRSS so far
};

/// Reads VmRSS and VmHWM; -1 where /proc is not available.
inline Rss ReadRss()
{
    Rss rss;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (f == nullptr)
    {
        return rss;
    }
    char line[256];
    while (std::fgets(line, sizeof(line), f) != nullptr)
    {
        if (std::strncmp(line, "VmRSS:", 6) == 0)
        {
            rss.currentKiB = std::strtol(line + 6, nullptr, 10);
        }
        else if (std::strncmp(line, "VmHWM:", 6) == 0)
        {
            rss.peakKiB = std::strtol(line + 6, nullptr, 10);
        }
    }
    std::fclose(f);
    return rss;
}

} // namespace qpsoak
