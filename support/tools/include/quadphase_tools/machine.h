// The machine a tool ran on (CPU model, threads, compiler), its peak memory, and the line every tool prints.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

namespace quadphase::tools
{

/// The rest of the first line of /proc file `path` that starts with `key`; `fallback` when there is none.
inline std::string ProcField(const char* path, const std::string& key, const std::string& fallback)
{
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line))
    {
        if (line.rfind(key, 0) == 0)
        {
            return line.substr(key.size());
        }
    }
    return fallback;
}

inline std::string CpuModel()
{
    const std::string model = ProcField("/proc/cpuinfo", "model name", "unknown");
    const size_t colon = model.find(':'), start = model.find_first_not_of(' ', colon + 1);
    return colon == std::string::npos ? "unknown" : start == std::string::npos ? "" : model.substr(start);
}

inline std::string Compiler()
{
#if defined(__clang__)
    return std::string("clang ") + __clang_version__;
#elif defined(__GNUC__)
    return std::string("g++ ") + __VERSION__;
#else
    return "unknown";
#endif
}

/// "machine: CPU, N hardware threads; compiler: ...; flags: `flags`" and a newline.
inline void PrintMachine(std::FILE* out, const char* flags)
{
    std::fprintf(out, "machine: %s, %u hardware threads; compiler: %s; flags: %s\n", CpuModel().c_str(),
                 std::thread::hardware_concurrency(), Compiler().c_str(), flags);
}

/// Peak resident set size of this process in bytes (VmHWM of /proc/self/status); 0 when unknown.
inline int64_t PeakRss()
{
    return std::atoll(ProcField("/proc/self/status", "VmHWM:", "0").c_str()) * 1024;
}

} // namespace quadphase::tools
