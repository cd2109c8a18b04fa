// SPDX-License-Identifier: MIT
// Clock readings shared by the parts of QuadtreeBroadPhase (private to the core's sources).
#pragma once

#include <chrono>

namespace quadphase
{
namespace detail
{

using Clock = std::chrono::steady_clock;

inline double SecondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

} // namespace detail
} // namespace quadphase
