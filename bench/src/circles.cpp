// SPDX-License-Identifier: MIT
// qp-circles: the paper's protocol. The largest number of circles whose collision detection (broadphase plus
// the circle-circle test of its candidate pairs) stays under 20 ms per frame, median of 3 repeats.
//
//   qp-circles --engine pairwise|paper|stock|quadtree [--threads T] [--depth D|auto] [--budget-ms 20]
//              [--repeats 3] [--frames 10] [--warmup 20] [--start 1000] [--precision 0.03] [--max-seconds 60]
//              [--max-n 4000000] [--seed 1] [--json FILE] [--label TEXT]
//
// The world (the paper gives no sizes; this is our reading, stated in bench/README.md): circles of radius 0.5
// m at an area fraction of 0.15 in a square box whose side grows with N (the density of the particles scene),
// each moving at a random speed of 1-5 m/s in a random direction, bouncing off the walls, 60 frames per
// second. A frame moves every circle (not timed), then the timed collision detection:
//   pairwise  the paper's n^2 loop: every pair of circles is tested (no broadphase);
//   paper     the paper's design (bench/baselines), --depth = its level 4..9 (auto: leaves at least twice the
//             circle's diameter), --threads 1 = its sequential quadtree, 2 = static schedule; exact boxes (no
//             margins), every frame inserts everything, reports all pairs found; each is circle-tested;
//   stock     Box2D 2.4.1's b2BroadPhase (MoveProxy of every circle, UpdatePairs);
//   quadtree  quadphase::QuadtreeBroadPhase (--depth, --threads) through the same calls.
// Each repeat builds a fresh world, runs one creation frame and, for stock and quadtree, --warmup frames
// untimed (all circles start together, so Box2D's fat boxes expire in bursts at first; the warm-up spreads
// them out; brute force and the paper's design keep no state between frames), then times --frames frames
// (their mean). stock and quadtree keep Box2D's persistent pair list, as b2ContactManager does: new pairs
// from UpdatePairs are added (duplicates dropped), every listed pair whose fat boxes no longer overlap is
// dropped, and every listed pair is circle-tested; all of that is in the frame time, the same code for both.
//
// Each evaluation also gives the part of its frames spent finding pairs (find_ms; Detector::FindMs), and the result
// that part's share of the frame at the largest passing N (find_share): only that part runs on the threads.
//
// Search: N doubles from --start while it passes (or halves while it fails), then bisects until the bracket
// is within --precision; an evaluation fails early when one frame takes more than 5x the budget.
// --max-seconds caps the search (the result is then flagged "capped" and is the largest N that passed).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "box_to_aabb.h"
#include "pair_hash.h"
#include "paper_quadtree.h"
#include "quadtree_broad_phase.h"
#include "tool_common.h"

namespace
{

using namespace qpbench;
using quadphase::Box;

constexpr float kRadius = 0.5f;
constexpr float kAreaFraction = 0.15f;
constexpr float kDt = 1.0f / 60.0f;

struct Circles
{
    std::vector<float> x, y, vx, vy;
    float side = 0.0f;

    Circles(int n, uint32_t seed)
        : x(size_t(n)), y(size_t(n)), vx(size_t(n)), vy(size_t(n)),
          side(std::sqrt(float(n) * 3.14159265f * kRadius * kRadius / kAreaFraction))
    {
        uint64_t state = seed * 0x9E3779B97F4A7C15ull + 1;
        auto next = [&]() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            return float(state >> 40) * (1.0f / 16777216.0f);
        };
        for (int i = 0; i < n; ++i)
        {
            x[size_t(i)] = kRadius + next() * (side - 2 * kRadius);
            y[size_t(i)] = kRadius + next() * (side - 2 * kRadius);
            const float speed = 1.0f + 4.0f * next();
            const float angle = 6.2831853f * next();
            vx[size_t(i)] = speed * std::cos(angle);
            vy[size_t(i)] = speed * std::sin(angle);
        }
    }
    int Count() const { return int(x.size()); }
    Box Tight(int i) const
    {
        return Box{x[size_t(i)] - kRadius, y[size_t(i)] - kRadius, x[size_t(i)] + kRadius,
                   y[size_t(i)] + kRadius};
    }
    void Move()
    {
        for (size_t i = 0; i < x.size(); ++i)
        {
            x[i] += vx[i] * kDt;
            y[i] += vy[i] * kDt;
            if ((x[i] < kRadius && vx[i] < 0) || (x[i] > side - kRadius && vx[i] > 0))
            {
                vx[i] = -vx[i];
            }
            if ((y[i] < kRadius && vy[i] < 0) || (y[i] > side - kRadius && vy[i] > 0))
            {
                vy[i] = -vy[i];
            }
        }
    }
    bool Touching(int a, int b) const
    {
        const float dx = x[size_t(a)] - x[size_t(b)], dy = y[size_t(a)] - y[size_t(b)];
        return dx * dx + dy * dy < 4.0f * kRadius * kRadius;
    }
};

/// One engine's collision detection over a set of circles. Frame() is the timed part; returns touching pairs.
/// FindMs() is the part of the last Frame() spent finding pairs: the only part a quadtree's threads share
/// (FindPairs; stock's UpdatePairs with its callbacks; the whole n^2 loop for brute force). The rest of a frame
/// (the moves, the pair list, the circle tests) runs on one thread whatever --threads says.
class Detector
{
public:
    virtual ~Detector() = default;
    virtual int64_t Frame(const Circles& c) = 0;
    double FindMs() const { return m_findMs; }

protected:
    /// Runs find() and keeps its time for FindMs().
    template <typename Find>
    void TimeFind(Find&& find)
    {
        const int64_t t0 = NowNs();
        find();
        m_findMs = double(NowNs() - t0) * 1e-6;
    }

private:
    double m_findMs = 0.0;
};

class Pairwise final : public Detector
{
public:
    int64_t Frame(const Circles& c) override
    {
        const int n = c.Count();
        const float d2 = 4.0f * kRadius * kRadius;
        int64_t hits = 0;
        TimeFind([&] {
            for (int i = 0; i < n; ++i)
            {
                const float xi = c.x[size_t(i)], yi = c.y[size_t(i)];
                for (int j = i + 1; j < n; ++j)
                {
                    const float dx = xi - c.x[size_t(j)], dy = yi - c.y[size_t(j)];
                    hits += dx * dx + dy * dy < d2 ? 1 : 0;
                }
            }
        });
        return hits;
    }
};

class Paper final : public Detector
{
public:
    Paper(const Circles& c, int levels, int threads)
        : m_bp(levels, Box{0, 0, c.side, c.side}, threads, quadphase::Schedule::Static,
               quadphase::bench::PaperPairReport::All, quadphase::FatPolicy{0.0f, 0.0f})
    {
        for (int i = 0; i < c.Count(); ++i)
        {
            m_bp.CreateProxy(c.Tight(i), reinterpret_cast<void*>(intptr_t(i)));
        }
    }
    int64_t Frame(const Circles& c) override
    {
        for (int i = 0; i < c.Count(); ++i)
        {
            m_bp.MoveProxy(i, c.Tight(i), quadphase::Vec2{0, 0});
        }
        m_pairs.clear();
        TimeFind([&] { m_bp.FindPairs(m_pairs); });
        int64_t hits = 0;
        for (const quadphase::Pair& p : m_pairs)
        {
            hits += c.Touching(p.a, p.b) ? 1 : 0; // ids are 0..n-1 in creation order
        }
        return hits;
    }

private:
    quadphase::bench::PaperQuadtreeBroadPhase m_bp;
    std::vector<quadphase::Pair> m_pairs;
};

/// Stock and quadtree: Box2D's calls (MoveProxy of every circle by its displacement, then the new pairs) and
/// Box2D's persistent pair list (b2ContactManager's role): new pairs are added (duplicates dropped), every
/// listed pair whose fat boxes no longer overlap is dropped (TestOverlap), the others are circle-tested.
template <typename BP>
class Persistent final : public Detector
{
public:
    static constexpr bool kStock = std::is_same_v<BP, b2BroadPhase>;

    template <typename... A>
    explicit Persistent(const Circles& c, A&&... a) : m_bp(std::forward<A>(a)...), m_last(c.x), m_lastY(c.y)
    {
        for (int i = 0; i < c.Count(); ++i)
        {
            void* user = reinterpret_cast<void*>(intptr_t(i));
            if constexpr (kStock)
                m_ids.push_back(m_bp.CreateProxy(ToAabb(c.Tight(i)), user));
            else
                m_ids.push_back(m_bp.CreateProxy(c.Tight(i), user));
        }
    }
    int64_t Frame(const Circles& c) override
    {
        for (int i = 0; i < c.Count(); ++i)
        {
            const float dx = c.x[size_t(i)] - m_last[size_t(i)], dy = c.y[size_t(i)] - m_lastY[size_t(i)];
            if constexpr (kStock)
                m_bp.MoveProxy(m_ids[size_t(i)], ToAabb(c.Tight(i)), b2Vec2(dx, dy));
            else
                m_bp.MoveProxy(m_ids[size_t(i)], c.Tight(i), quadphase::Vec2{dx, dy});
            m_last[size_t(i)] = c.x[size_t(i)];
            m_lastY[size_t(i)] = c.y[size_t(i)];
        }
        if constexpr (kStock)
        {
            TimeFind([&] { m_bp.UpdatePairs(this); });
        }
        else
        {
            m_pairs.clear();
            TimeFind([&] { m_bp.FindPairs(m_pairs); });
            for (const quadphase::Pair& p : m_pairs)
            {
                AddPair(m_bp.GetUserData(p.a), m_bp.GetUserData(p.b));
            }
        }
        int64_t hits = 0;
        for (size_t i = 0; i < m_list.size();)
        {
            const auto [a, b] = m_list[i];
            if (!m_bp.TestOverlap(m_ids[size_t(a)], m_ids[size_t(b)]))
            {
                m_keys.erase(PairKey(a, b));
                m_list[i] = m_list.back();
                m_list.pop_back();
                continue;
            }
            hits += c.Touching(a, b) ? 1 : 0;
            ++i;
        }
        return hits;
    }
    /// b2BroadPhase::UpdatePairs's callback; ids are the circles' indices (user data).
    void AddPair(void* userA, void* userB)
    {
        const int32_t a = int32_t(intptr_t(userA)), b = int32_t(intptr_t(userB));
        if (m_keys.insert(PairKey(a, b)).second)
        {
            m_list.emplace_back(std::min(a, b), std::max(a, b));
        }
    }

private:
    BP m_bp;
    std::vector<int32_t> m_ids;
    std::vector<float> m_last, m_lastY;
    std::vector<quadphase::Pair> m_pairs;
    std::unordered_set<uint64_t> m_keys;
    std::vector<std::pair<int32_t, int32_t>> m_list;
};

// The command line; members are read in declaration order, `args` first.
struct Settings
{
    const Args& args;
    std::string engine = args.Get("engine");
    int threads = int(args.GetInt("threads", 1));
    std::string depthArg = args.Get("depth", "auto");
    int depth = depthArg == "auto" ? -1 : std::atoi(depthArg.c_str()); // -1: auto
    double budgetMs = args.GetDouble("budget-ms", 20.0);
    int repeats = int(args.GetInt("repeats", 3)), frames = int(args.GetInt("frames", 10));
    int warmup = int(args.GetInt("warmup", 20));
    uint32_t seed = uint32_t(args.GetInt("seed", 1));
};

std::unique_ptr<Detector> Make(const Settings& s, const Circles& c)
{
    if (s.engine == "pairwise")
        return std::make_unique<Pairwise>();
    if (s.engine == "paper")
    {
        // auto: leaves at least twice the circle's diameter.
        const int levels = quadphase::bench::PaperQuadtreeBroadPhase::LevelsFor(c.side, 4.0 * kRadius);
        return std::make_unique<Paper>(c, s.depth < 0 ? levels : s.depth, s.threads);
    }
    if (s.engine == "stock")
        return std::make_unique<Persistent<b2BroadPhase>>(c);
    quadphase::Config config;
    config.depth = s.depth;
    config.threads = s.threads;
    return std::make_unique<Persistent<quadphase::QuadtreeBroadPhase>>(c, quadphase::FatPolicy{}, config);
}

struct Evaluation
{
    double medianMs = 0.0; // median over repeats of the mean frame time
    double findMs = 0.0;   // the same repeats' mean time finding pairs (Detector::FindMs)
    int64_t touching = 0;
    bool aborted = false;
};

Evaluation Evaluate(const Settings& s, int n)
{
    std::vector<double> perRepeat, findPerRepeat;
    Evaluation e;
    for (int r = 0; r < s.repeats; ++r)
    {
        Circles c(n, s.seed + uint32_t(r));
        std::unique_ptr<Detector> d = Make(s, c);
        // The creation frame (every proxy new, all pairs found from scratch) is not part of the protocol.
        c.Move();
        d->Frame(c);
        // Brute force and the paper's design keep nothing from one frame to the next: no warm-up needed.
        const int warmup = s.engine == "pairwise" || s.engine == "paper" ? 0 : s.warmup;
        double total = 0.0; // over the timed frames, those after the warm-up
        double findTotal = 0.0;
        for (int f = 0; f < warmup + s.frames && !e.aborted; ++f)
        {
            c.Move();
            const int64_t t0 = NowNs();
            const int64_t touching = d->Frame(c);
            const double ms = double(NowNs() - t0) * 1e-6;
            e.aborted = ms > 5.0 * s.budgetMs;
            if (f >= warmup)
            {
                total += ms;
                findTotal += d->FindMs();
                e.touching = touching;
            }
        }
        if (e.aborted)
        {
            e.medianMs = 5.0 * s.budgetMs;
            return e;
        }
        perRepeat.push_back(total / s.frames);
        findPerRepeat.push_back(findTotal / s.frames);
    }
    // The repeat (or the two) whose frame time is the median, and its pair finding.
    std::vector<size_t> order(perRepeat.size());
    for (size_t i = 0; i < order.size(); ++i)
    {
        order[i] = i;
    }
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return perRepeat[a] < perRepeat[b]; });
    const size_t m = order.size();
    const size_t lower = order[(m - 1) / 2], upper = order[m / 2];
    e.medianMs = 0.5 * (perRepeat[lower] + perRepeat[upper]);
    e.findMs = 0.5 * (findPerRepeat[lower] + findPerRepeat[upper]);
    return e;
}

} // namespace

int main(int argc, char** argv)
{
    const Args args(argc, argv, "qp-circles",
                    {"engine", "threads", "depth", "budget-ms", "repeats", "frames", "warmup", "start",
                     "precision", "max-seconds", "max-n", "seed", "json", "label"});
    const Settings s{args};
    const bool knownEngine =
        s.engine == "pairwise" || s.engine == "paper" || s.engine == "stock" || s.engine == "quadtree";
    if (!knownEngine && args.Has("engine"))
    {
        std::fprintf(stderr, "qp-circles: unknown engine '%s'\n", s.engine.c_str());
    }
    args.Check(knownEngine,
               "usage: qp-circles --engine pairwise|paper|stock|quadtree [--threads T] [--depth D|auto]\n"
               "       [--budget-ms 20] [--repeats 3] [--frames 10] [--warmup 20] [--start 1000]\n"
               "       [--precision 0.03] [--max-seconds 60] [--max-n N] [--seed S] [--json FILE]\n");
    const double precision = args.GetDouble("precision", 0.03);
    const double maxSeconds = args.GetDouble("max-seconds", 60.0);
    const long maxN = args.GetInt("max-n", 4000000);
    if (s.repeats < 1 || s.frames < 1 || s.budgetMs <= 0 || precision <= 0 || s.threads < 0 ||
        (s.engine == "paper" && s.depth != -1 && (s.depth < 1 || s.depth > 9)))
    {
        Die(2, "qp-circles: bad option value (paper depth: 1..9 or auto)\n");
    }
    const std::string jsonPath = args.Get("json");
    // A JSON line's first fields, the same on every line.
    auto base = [&](const char* kind) {
        return JsonLine()
            .Str("tool", "qp-circles")
            .Str("kind", kind)
            .Str("label", args.Get("label"))
            .Str("engine", s.engine)
            .Int("threads", s.threads)
            .Int("depth", s.depth)
            .Num("budget_ms", s.budgetMs)
            .Int("repeats", s.repeats)
            .Int("frames", s.frames);
    };

    const int64_t start = NowNs();
    auto elapsed = [&] {
        return double(NowNs() - start) * 1e-9;
    };
    long lo = 0, hi = 0; // largest pass, smallest fail: each evaluation moves one of them
    long n = std::max(2L, args.GetInt("start", 1000));
    bool capped = false;
    int evaluations = 0;
    double findShare = std::nan(""); // pair finding's share of the frame at the largest size that passed
    auto evaluate = [&](long count) {
        const Evaluation e = Evaluate(s, int(count));
        ++evaluations;
        const bool pass = !e.aborted && e.medianMs < s.budgetMs;
        const JsonLine j = base("eval")
                               .Int("n", count)
                               .Num("ms", e.medianMs)
                               .Num("find_ms", e.findMs)
                               .Int("pass", pass ? 1 : 0)
                               .Int("aborted", e.aborted ? 1 : 0)
                               .Int("touching", e.touching)
                               .Num("elapsed_s", elapsed());
        AppendLine(jsonPath, j.Text());
        std::printf("  %s n=%ld: %.2f ms/frame (finding pairs %.2f)%s %s\n", s.engine.c_str(), count,
                    e.medianMs, e.findMs, e.aborted ? " (aborted)" : "", pass ? "pass" : "fail");
        std::fflush(stdout);
        (pass ? lo : hi) = count;
        if (pass) // the largest size that passed so far
        {
            findShare = e.findMs / e.medianMs;
        }
    };
    // Checked before each evaluation: past --max-seconds (or `over`: past --max-n), the search stops, capped.
    auto cap = [&](bool over) {
        capped = over || elapsed() > maxSeconds;
        return capped;
    };
    while (hi == 0 && !cap(n > maxN))
    {
        evaluate(n);
        n *= 2;
    }
    // The first size failed: halve until one passes (a noisy first evaluation must not end the search at 0).
    for (n = hi / 2; hi != 0 && lo == 0 && n >= 2 && !cap(false); n /= 2)
    {
        evaluate(n);
    }
    while (hi != 0 && lo != 0 && double(hi - lo) > precision * double(lo) && !cap(false))
    {
        evaluate((lo + hi) / 2);
    }
    const JsonLine j = base("result")
                           .Int("n_max", lo)
                           .Int("n_fail", hi)
                           .Int("capped", capped ? 1 : 0)
                           .Int("evaluations", evaluations)
                           .Num("seconds", elapsed())
                           .Num("find_share", findShare);
    AppendLine(jsonPath, j.Text());
    std::printf("%s threads=%d depth=%s: %ld circles under %.1f ms per frame%s (%d evaluations, %.0f s); "
                "finding pairs %.0f%% of the frame there\n",
                s.engine.c_str(), s.threads, s.depthArg.c_str(), lo, s.budgetMs, capped ? " (capped)" : "",
                evaluations, elapsed(), 100.0 * findShare);
    return 0;
}
