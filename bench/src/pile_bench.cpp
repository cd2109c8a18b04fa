// SPDX-License-Identifier: MIT
// qp-pile-stock / qp-pile-quadtree: the cost of the worst case for any grid, thousands of proxies piled into one
// cell, through b2BroadPhase itself (one source, two builds: Box2D 2.4.1's dynamic tree in qp-pile-stock, the
// quadtree in qp-pile-quadtree; docs/robustness.md). Every proxy overlaps every other, so each UpdatePairs after
// all of them moved must report n (n - 1) / 2 pairs: the output's own size. The question is whether the cost
// stays in proportion to it.
//
//   qp-pile-<variant> [--counts N1,N2,...] [--rounds R]
//
// For each count n: n boxes of 0.1 m within 1 cm of one point; R rounds of (move every proxy 3 m right or
// left, so every one leaves its fat AABB, then UpdatePairs). Prints per count: pairs per round, the median
// round time in ms (MoveProxy and UpdatePairs; the callback only counts), and ns per pair. Exit status 1 when
// a round reports a pair count other than n (n - 1) / 2.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "box2d_variant.h"
#include "tool_common.h"

namespace
{

struct Counter
{
    int64_t pairs = 0;
    void AddPair(void*, void*) { ++pairs; }
};

} // namespace

int main(int argc, char** argv)
{
    const std::string tool = "qp-pile-" + std::string(kVariant);
    const qpbench::Args args(argc, argv, tool, {"counts", "rounds"});
    args.Check(true, "usage: %s [--counts N1,N2,...] [--rounds R]\n", tool.c_str());
    std::vector<int> counts;
    std::stringstream list(args.Get("counts", "1000,2000,4000,8000"));
    std::string item;
    while (std::getline(list, item, ','))
    {
        const int n = std::atoi(item.c_str());
        if (n < 2 || n > 100000)
        {
            qpbench::Die(2, "%s: counts must be in [2, 100000]\n", tool.c_str());
        }
        counts.push_back(n);
    }
    const int rounds = int(args.GetIntIn("rounds", 7, 1, 1000));

    std::printf("%s (%s build of b2BroadPhase): %d rounds per count\n", tool.c_str(), kVariant, rounds);
    std::printf("%8s %12s %12s %12s\n", "proxies", "pairs/round", "median_ms", "ns/pair");
    for (int n : counts)
    {
        b2BroadPhase bp;
        std::vector<b2AABB> boxes(static_cast<size_t>(n));
        std::vector<int32> ids(static_cast<size_t>(n)); // stock proxy ids are tree node ids, not 0..n-1
        uint32_t state = 12345u;
        auto next = [&state]() {
            state = state * 1664525u + 1013904223u;
            return float(state >> 8) * (1.0f / 16777216.0f);
        };
        for (int i = 0; i < n; ++i)
        {
            b2AABB& b = boxes[size_t(i)];
            b.lowerBound.Set(5.0f + 0.01f * next(), -7.0f + 0.01f * next());
            b.upperBound = b.lowerBound + b2Vec2(0.1f, 0.1f);
            ids[size_t(i)] = bp.CreateProxy(b, reinterpret_cast<void*>(intptr_t(i)));
        }
        Counter first;
        bp.UpdatePairs(&first); // creation: all pairs, not timed
        std::vector<double> ms;
        const int64_t expected = int64_t(n) * (n - 1) / 2;
        for (int r = 0; r < rounds; ++r)
        {
            const float dx = (r % 2 == 0) ? 3.0f : -3.0f;
            Counter c;
            const int64_t t0 = qpbench::NowNs();
            for (int i = 0; i < n; ++i)
            {
                b2AABB& b = boxes[size_t(i)];
                b.lowerBound.x += dx;
                b.upperBound.x += dx;
                bp.MoveProxy(ids[size_t(i)], b, b2Vec2(dx, 0.0f));
            }
            bp.UpdatePairs(&c);
            ms.push_back(double(qpbench::NowNs() - t0) * 1e-6);
            if (c.pairs != expected || first.pairs != expected)
            {
                std::fprintf(stderr, "%s: %d proxies: %lld pairs, expected %lld\n", tool.c_str(), n,
                             (long long)c.pairs, (long long)expected);
                return 1;
            }
        }
        const double median = qpbench::Median(ms);
        std::printf("%8d %12lld %12.2f %12.2f\n", n, (long long)expected, median,
                    1e6 * median / double(expected));
    }
    return 0;
}
