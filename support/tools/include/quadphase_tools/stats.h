// SPDX-License-Identifier: MIT
// Medians and means of the tools' samples.
#pragma once

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

namespace quadphase::tools
{

/// The median of `v` (the mean of the two middle values for an even count); T{} when empty.
template <typename T>
T Median(std::vector<T> v)
{
    if (v.empty())
    {
        return T{};
    }
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : T((v[n / 2 - 1] + v[n / 2]) / 2);
}

/// The nearest-rank `q`-quantile of `v` (0 < q <= 1: the smallest value with at least q of the values at or
/// below it; 1 gives the maximum); T{} when empty.
template <typename T>
T Quantile(std::vector<T> v, double q)
{
    if (v.empty())
    {
        return T{};
    }
    const size_t rank = size_t(std::ceil(q * double(v.size())));
    const size_t k = std::min(v.size(), std::max<size_t>(1, rank)) - 1;
    std::nth_element(v.begin(), v.begin() + long(k), v.end());
    return v[k];
}

/// The mean of `v`; 0 when empty.
inline double Mean(const std::vector<double>& v)
{
    return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

} // namespace quadphase::tools
