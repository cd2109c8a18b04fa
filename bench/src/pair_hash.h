// SPDX-License-Identifier: MIT
// Pair keys and the pair-set hash of every UpdatePairs call: computed, written, read and compared.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "tool_common.h"

namespace qpbench
{

// ---------------------------------------------------------------------------------------------------------------
// Pair-set hashes: for each UpdatePairs call, the sorted unique list of pairs in recorded ids (a < b) is
// hashed (FNV-1a over the 64-bit keys a << 32 | b). Duplicates (the stock class may report a pair twice) do
// not count.
// ---------------------------------------------------------------------------------------------------------------
struct CallHash
{
    uint64_t count = 0; // unique pairs
    uint64_t hash = 0;
};

inline uint64_t PairKey(int32_t a, int32_t b)
{
    if (a > b)
    {
        std::swap(a, b);
    }
    return (uint64_t(uint32_t(a)) << 32) | uint64_t(uint32_t(b));
}

inline CallHash HashPairKeys(std::vector<uint64_t>& keys)
{
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return CallHash{uint64_t(keys.size()), Fnv1a64(keys)};
}

/// Writes "call count hash" lines (call = index of the UpdatePairs call in the trace, from 0); exits when it
/// cannot.
inline void SaveHashesOrDie(const std::string& path, const std::vector<CallHash>& hashes)
{
    std::FILE* out = std::fopen(path.c_str(), "w");
    bool ok =
        out != nullptr &&
        std::fprintf(out,
                     "# qp-pairhash 1: call unique_pairs fnv1a64(sorted unique pairs in recorded ids)\n") > 0;
    for (size_t i = 0; ok && i < hashes.size(); ++i)
    {
        ok = std::fprintf(out, "%zu %llu %016llx\n", i, static_cast<unsigned long long>(hashes[i].count),
                          static_cast<unsigned long long>(hashes[i].hash)) > 0;
    }
    if (out == nullptr || std::fclose(out) != 0 || !ok)
    {
        Die(1, "qp-replay: cannot write %s\n", path.c_str());
    }
}

/// The hashes SaveHashesOrDie wrote to `path` (none when `path` is empty); exits when they cannot be read.
inline std::vector<CallHash> LoadHashesOrDie(const std::string& path)
{
    std::vector<CallHash> hashes;
    if (path.empty())
    {
        return hashes;
    }
    std::ifstream in(path);
    bool ok = in.is_open();
    std::string line;
    while (ok && std::getline(in, line))
    {
        unsigned long long index = 0, count = 0, hash = 0;
        if (!line.empty() && line[0] != '#')
        {
            ok = std::sscanf(line.c_str(), "%llu %llu %llx", &index, &count, &hash) == 3 &&
                 index == hashes.size();
            hashes.push_back(CallHash{count, hash});
        }
    }
    if (!ok)
    {
        Die(1, "qp-replay: cannot read hashes from %s\n", path.c_str());
    }
    return hashes;
}

/// Number of calls whose hashes differ (a length difference counts as mismatches); prints the first few.
inline int64_t CompareHashes(const std::vector<CallHash>& mine, const std::vector<CallHash>& reference,
                             const char* mineName, const char* referenceName)
{
    int64_t mismatches = 0;
    const size_t n = std::max(mine.size(), reference.size());
    for (size_t i = 0; i < n; ++i)
    {
        const bool same = i < mine.size() && i < reference.size() && mine[i].hash == reference[i].hash &&
                          mine[i].count == reference[i].count;
        if (!same)
        {
            if (mismatches < 5)
            {
                std::fprintf(
                    stderr, "MISMATCH at UpdatePairs call %zu: %s %llu pairs, %s %llu pairs\n", i, mineName,
                    i < mine.size() ? static_cast<unsigned long long>(mine[i].count) : 0ull, referenceName,
                    i < reference.size() ? static_cast<unsigned long long>(reference[i].count) : 0ull);
            }
            ++mismatches;
        }
    }
    return mismatches;
}

} // namespace qpbench
