// SPDX-License-Identifier: MIT
// The machine a tool ran on (CPU model, threads, compiler), its peak memory and CPU time, and the line every tool
// prints.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <thread>

#include <pthread.h>
#include <sys/resource.h>
#include <time.h>

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

/// CPU time this process has used so far, user plus system, every thread together (getrusage RUSAGE_SELF), in
/// seconds: what the process takes from the machine's other programs, spinning worker threads included.
inline double ProcessCpuSeconds()
{
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) != 0)
    {
        return NAN;
    }
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           double(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

/// CPU time a running thread of this process has used so far (user plus system), in seconds; NaN when its CPU
/// clock cannot be read.
inline double ThreadCpuSeconds(pthread_t thread)
{
    clockid_t clock{};
    timespec t{};
    if (pthread_getcpuclockid(thread, &clock) != 0 || clock_gettime(clock, &t) != 0)
    {
        return NAN;
    }
    return double(t.tv_sec) + double(t.tv_nsec) * 1e-9;
}

} // namespace quadphase::tools
