// SPDX-License-Identifier: MIT
// Extreme proxy counts at the core level (no Box2D): one million proxies, and thousands in one cell. The
// million is checked against a uniform-grid reference written here (independent of the quadtree's code), and
// that reference against the brute force on a sample of proxies; the pile against the brute force in full.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "brute_force_broad_phase.h"
#include "quadtree_broad_phase.h"

using namespace quadphase;

namespace
{

/// Portable uniform float in [lo, hi) from a 32-bit draw.
float Uniform(std::mt19937& rng, float lo, float hi)
{
    return lo + (hi - lo) * float(rng() >> 8) * (1.0f / 16777216.0f);
}

std::vector<Pair> Sorted(std::vector<Pair> pairs)
{
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

/// All overlapping pairs of `boxes` (indexed by id) among which at least one is marked, found through a
/// uniform grid of `cell`-sized squares; cell must exceed every box's extent, so a box touches at most 4
/// cells. Each pair is reported by the cell holding the lower-left corner of the two boxes' intersection,
/// hence once.
std::vector<Pair> GridPairs(const std::vector<Box>& boxes, const std::vector<char>& marked, float cell)
{
    struct Entry
    {
        int64_t cx, cy;
        ProxyId id;
        bool operator<(const Entry& o) const
        {
            return cx < o.cx || (cx == o.cx && (cy < o.cy || (cy == o.cy && id < o.id)));
        }
    };
    auto cellOf = [cell](float v) {
        return int64_t(std::floor(double(v) / double(cell)));
    };
    std::vector<Entry> entries;
    entries.reserve(boxes.size() * 2);
    for (size_t i = 0; i < boxes.size(); ++i)
    {
        const Box& b = boxes[i];
        for (int64_t cx = cellOf(b.minX); cx <= cellOf(b.maxX); ++cx)
        {
            for (int64_t cy = cellOf(b.minY); cy <= cellOf(b.maxY); ++cy)
            {
                entries.push_back(Entry{cx, cy, ProxyId(i)});
            }
        }
    }
    std::sort(entries.begin(), entries.end());
    std::vector<Pair> out;
    for (size_t first = 0; first < entries.size();)
    {
        size_t last = first;
        while (last < entries.size() && entries[last].cx == entries[first].cx &&
               entries[last].cy == entries[first].cy)
        {
            ++last;
        }
        for (size_t i = first; i < last; ++i)
        {
            for (size_t j = i + 1; j < last; ++j)
            {
                const ProxyId ia = entries[i].id;
                const ProxyId ib = entries[j].id;
                const Box& a = boxes[size_t(ia)];
                const Box& b = boxes[size_t(ib)];
                if (!Overlaps(a, b) || !(marked[size_t(ia)] || marked[size_t(ib)]))
                {
                    continue;
                }
                if (cellOf(std::max(a.minX, b.minX)) == entries[first].cx &&
                    cellOf(std::max(a.minY, b.minY)) == entries[first].cy)
                {
                    out.push_back(Pair{std::min(ia, ib), std::max(ia, ib)});
                }
            }
        }
        first = last;
    }
    return Sorted(out);
}

/// Pairs of `pairs` that involve `id`, as the sorted list of partners.
std::vector<ProxyId> PartnersIn(const std::vector<Pair>& pairs, ProxyId id)
{
    std::vector<ProxyId> out;
    for (const Pair& p : pairs)
    {
        if (p.a == id || p.b == id)
        {
            out.push_back(p.a == id ? p.b : p.a);
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

} // namespace

TEST_CASE("one million proxies: exact pairs after creation and after a tenth of them moved",
          "[extreme][million]")
{
    const int n = 1000000;
    std::mt19937 rng(1000003u);
    QuadtreeBroadPhase qt;
    std::vector<Box> tight(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
    {
        // 2000 m x 2000 m, boxes of 0.2 m to 1.5 m: about one pair per proxy
        const float x = Uniform(rng, -1000.0f, 1000.0f);
        const float y = Uniform(rng, -1000.0f, 1000.0f);
        tight[size_t(i)] = Box{x, y, x + Uniform(rng, 0.2f, 1.5f), y + Uniform(rng, 0.2f, 1.5f)};
        REQUIRE(qt.CreateProxy(tight[size_t(i)], nullptr) == ProxyId(i));
    }
    REQUIRE(qt.GetProxyCount() == n);

    std::vector<Box> fat(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i)
    {
        fat[size_t(i)] = qt.GetFatBox(ProxyId(i));
    }
    std::vector<Pair> pairs;
    qt.FindPairs(pairs);
    const std::vector<Pair> all = Sorted(pairs);
    REQUIRE(std::adjacent_find(all.begin(), all.end()) == all.end());
    const std::vector<Pair> reference = GridPairs(fat, std::vector<char>(size_t(n), 1), 4.0f);
    CHECK(all.size() > size_t(n) / 2);
    REQUIRE(all.size() == reference.size());
    REQUIRE(all == reference);

    // the reference itself, against the brute force's definition on a sample of proxies
    for (int s = 0; s < 20; ++s)
    {
        const ProxyId id = ProxyId(rng() % uint32_t(n));
        std::vector<ProxyId> partners;
        for (int j = 0; j < n; ++j)
        {
            if (j != id && Overlaps(fat[size_t(id)], fat[size_t(j)]))
            {
                partners.push_back(ProxyId(j));
            }
        }
        REQUIRE(PartnersIn(reference, id) == partners);
    }

    // a tenth of them move by up to 3 m: the new pairs are those of the moved proxies
    std::vector<char> moved(static_cast<size_t>(n), 0);
    for (int k = 0; k < n / 10; ++k)
    {
        const ProxyId id = ProxyId(rng() % uint32_t(n));
        const Vec2 d{Uniform(rng, -3.0f, 3.0f), Uniform(rng, -3.0f, 3.0f)};
        Box& b = tight[size_t(id)];
        b = Box{b.minX + d.x, b.minY + d.y, b.maxX + d.x, b.maxY + d.y};
        moved[size_t(id)] = qt.MoveProxy(id, b, d) ? 1 : moved[size_t(id)];
    }
    for (int i = 0; i < n; ++i)
    {
        fat[size_t(i)] = qt.GetFatBox(ProxyId(i));
    }
    pairs.clear();
    qt.FindPairs(pairs);
    const std::vector<Pair> after = Sorted(pairs);
    REQUIRE(std::adjacent_find(after.begin(), after.end()) == after.end());
    const std::vector<Pair> movedReference = GridPairs(fat, moved, 4.0f);
    CHECK(movedReference.size() > size_t(n) / 20);
    REQUIRE(after == movedReference);
    REQUIRE(qt.Validate().empty());
}

TEST_CASE("thousands of proxies in one cell: every pair once, the rest unaffected", "[extreme][pile]")
{
    std::mt19937 rng(777u);
    QuadtreeBroadPhase qt;
    BruteForceBroadPhase bf;
    const int pile = 2000;
    const int spread = 1200;
    std::vector<Box> tight;
    for (int i = 0; i < pile + spread; ++i)
    {
        Box b;
        if (i % 8 < 5) // five in eight on top of each other
        {
            const float x = 5.0f + Uniform(rng, 0.0f, 0.01f);
            const float y = -7.0f + Uniform(rng, 0.0f, 0.01f);
            b = Box{x, y, x + 0.2f, y + 0.2f};
        }
        else
        {
            const float x = Uniform(rng, -200.0f, 200.0f);
            const float y = Uniform(rng, -200.0f, 200.0f);
            b = Box{x, y, x + 1.0f, y + 1.0f};
        }
        REQUIRE(qt.CreateProxy(b, nullptr) == bf.CreateProxy(b, nullptr));
        tight.push_back(b);
    }
    for (int round = 0; round < 3; ++round)
    {
        INFO("round " << round);
        std::vector<Pair> a, b;
        qt.FindPairs(a);
        bf.FindPairs(b);
        a = Sorted(a);
        b = Sorted(b);
        REQUIRE(std::adjacent_find(a.begin(), a.end()) == a.end());
        REQUIRE(a.size() >= size_t(pile) * size_t(pile - 1) / 2);
        REQUIRE(a == b);
        REQUIRE(qt.Validate().empty());
        // the whole pile moves 3 m together, alternately right and left, so every member leaves its fat box
        // and all of its pairs are reported again; a few spread proxies move into the pile
        const float dx = (round % 2 == 0) ? 3.0f : -3.0f;
        for (ProxyId id = 0; id < pile + spread; ++id)
        {
            Box& t = tight[size_t(id)];
            const bool inPile = id % 8 < 5;
            if (inPile)
            {
                t = Box{t.minX + dx, t.minY, t.maxX + dx, t.maxY};
                REQUIRE(qt.MoveProxy(id, t, Vec2{dx, 0.0f}));
                REQUIRE(bf.MoveProxy(id, t, Vec2{dx, 0.0f}));
            }
            else if (id % 97 == 0)
            {
                const Box& p = tight[0];
                const Vec2 d{p.minX - t.minX, p.minY - t.minY};
                t = Box{p.minX, p.minY, p.minX + 1.0f, p.minY + 1.0f};
                REQUIRE(qt.MoveProxy(id, t, d) == bf.MoveProxy(id, t, d));
            }
        }
    }
}
