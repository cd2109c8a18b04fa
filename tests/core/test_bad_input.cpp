// SPDX-License-Identifier: MIT
// Bad input: unknown or destroyed ids, non-finite and inverted boxes. Each is reported through the error
// handler with the right code, and the other proxies keep exactly their pairs. A counting handler is
// installed for every test here (the default one prints to stderr) and restored afterwards. A bad box is reported
// once per proxy (its first), an unknown id at every call.
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "harness.h"

using namespace quadphase;
using namespace qptest;

namespace
{

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

/// What CheckBox should report for a tight box: -1 for a sane box.
int ExpectedCode(const Box& b)
{
    if (!IsFinite(b))
    {
        return int(ErrorCode::NonFiniteBox);
    }
    if (!IsOrdered(b))
    {
        return int(ErrorCode::InvertedBox);
    }
    return -1;
}

Box BadBox(Rng& rng, const Box& near)
{
    const float cx = 0.5f * (near.minX + near.maxX);
    const float cy = 0.5f * (near.minY + near.maxY);
    switch (UniformInt(rng, 0, 9))
    {
    case 0:
        return Box{kNaN, kNaN, kNaN, kNaN};
    case 1:
        return Box{cx, kNaN, cx + 1.0f, cy + 1.0f};
    case 2:
        return Box{cx, cy, kNaN, cy + 1.0f};
    case 3:
        return Box{-kInf, -kInf, kInf, kInf};
    case 4:
        return Box{cx, cy, kInf, cy + 1.0f};
    case 5:
        return Box{-kInf, cy, cx, cy};
    case 6:
        return Box{kInf, kInf, kInf, kInf};
    case 7: // inverted on x, far
        return Box{cx + 10.0f, cy, cx - 10.0f, cy + 1.0f};
    case 8: // inverted on y, slightly
        return Box{cx, cy + 0.05f, cx + 1.0f, cy};
    default: // inverted on both axes, inside its old fat box
        return Box{near.maxX, near.maxY, near.minX, near.minY};
    }
}

std::vector<Pair> Without(const std::vector<Pair>& pairs, const std::set<ProxyId>& bad)
{
    std::vector<Pair> kept;
    for (const Pair& p : pairs)
    {
        if (bad.count(p.a) == 0 && bad.count(p.b) == 0)
        {
            kept.push_back(p);
        }
    }
    return Sorted(kept);
}

/// Drives a quadtree and a brute force with the same calls, some of them with bad boxes.
class BadBoxRun
{
public:
    BadBoxRun(uint32_t seed, const Config& config)
        : m_seed(seed), m_rng(seed), m_source(m_rng, kAllDists[seed % 7], 40.0f), m_qt(FatPolicy{}, config)
    {
    }

    void Run(int steps)
    {
        for (int i = 0; i < 60; ++i)
        {
            Create(m_source.Next());
        }
        FindAndCompare();
        for (m_step = 0; m_step < steps; ++m_step)
        {
            const int roll = UniformInt(m_rng, 0, 99);
            const ProxyId any = m_ids[size_t(UniformInt(m_rng, 0, int(m_ids.size()) - 1))];
            if (roll < 10)
            {
                Create(m_source.Next());
            }
            else if (roll < 18)
            {
                Create(BadBox(m_rng, m_source.Next()));
            }
            else if (roll < 40)
            {
                Move(any, Translate(m_source.Next(), Vec2{0, 0}), m_source.Displacement());
            }
            else if (roll < 55)
            {
                // a small move: often stays inside the fat box
                const Vec2 d{Uniform(m_rng, -0.05f, 0.05f), Uniform(m_rng, -0.05f, 0.05f)};
                Move(any, IsSane(any) ? Translate(m_tight[size_t(any)], d) : m_source.Next(), d);
            }
            else if (roll < 67)
            {
                Move(any, BadBox(m_rng, m_tight[size_t(any)]), m_source.Displacement());
            }
            else if (roll < 72 && m_ids.size() > 10)
            {
                Destroy(any);
            }
            else if (roll < 77)
            {
                m_qt.TouchProxy(any);
                m_bf.TouchProxy(any);
            }
            else if (roll < 90)
            {
                FindAndCompare();
            }
            else
            {
                // queries with sane boxes: the sane proxies are found exactly
                const Box q = m_source.Next();
                IdCollector a, b;
                m_qt.Query(q, &IdCollector::Callback, &a);
                m_bf.Query(q, &IdCollector::Callback, &b);
                std::vector<ProxyId> sa, sb;
                for (ProxyId id : a.SortedIds())
                {
                    if (IsSane(id))
                    {
                        sa.push_back(id);
                    }
                }
                for (ProxyId id : b.SortedIds())
                {
                    if (IsSane(id))
                    {
                        sb.push_back(id);
                    }
                }
                QP_REQUIRE_MSG(sa == sb, Where() << "Query " << Str(q) << " differs on the sane proxies");
            }
            CheckErrors();
        }
        FindAndCompare();
    }

    int BadCalls() const { return m_badCalls; }
    int BadProxiesSeen() const { return m_badProxiesSeen; }

private:
    bool IsSane(ProxyId id) const { return ExpectedCode(m_tight[size_t(id)]) < 0; }

    void Create(const Box& tight)
    {
        const ProxyId a = m_qt.CreateProxy(tight, nullptr);
        const ProxyId b = m_bf.CreateProxy(tight, nullptr);
        QP_REQUIRE_MSG(a == b, Where() << "ids differ: " << a << " vs " << b);
        if (size_t(a) >= m_tight.size())
        {
            m_tight.resize(size_t(a) + 1);
        }
        m_tight[size_t(a)] = tight;
        if (size_t(a) >= m_badReported.size())
        {
            m_badReported.resize(size_t(a) + 1, false);
        }
        m_badReported[size_t(a)] = false; // a new proxy: its first bad box is reported again
        m_ids.push_back(a);
        Expect(a, tight);
        m_badProxiesSeen += IsSane(a) ? 0 : 1;
        QP_REQUIRE_MSG(SameBox(m_qt.GetFatBox(a), m_bf.GetFatBox(a)),
                       Where() << "fat boxes of " << a << " differ");
    }

    void Move(ProxyId id, const Box& tight, Vec2 d)
    {
        const bool a = m_qt.MoveProxy(id, tight, d);
        const bool b = m_bf.MoveProxy(id, tight, d);
        QP_REQUIRE_MSG(a == b, Where() << "MoveProxy(" << id << ", " << Str(tight) << ") returned " << a
                                       << " vs " << b);
        QP_REQUIRE_MSG(SameBox(m_qt.GetFatBox(id), m_bf.GetFatBox(id)),
                       Where() << "fat boxes of " << id << " differ after MoveProxy to " << Str(tight));
        m_tight[size_t(id)] = tight;
        Expect(id, tight);
        m_badProxiesSeen += IsSane(id) ? 0 : 1;
    }

    void Destroy(ProxyId id)
    {
        m_qt.DestroyProxy(id);
        m_bf.DestroyProxy(id);
        m_ids.erase(std::find(m_ids.begin(), m_ids.end(), id));
    }

    // A bad box is reported once per proxy: the first one it gets.
    void Expect(ProxyId id, const Box& tight)
    {
        const int code = ExpectedCode(tight);
        if (code >= 0)
        {
            m_expected[code] += m_badReported[size_t(id)] ? 0 : 1;
            m_badReported[size_t(id)] = true;
            m_badCalls += 1;
        }
        m_lastBox = tight;
    }

    void CheckErrors()
    {
        for (int code = 0; code < 3; ++code) // the core's codes
        {
            QP_REQUIRE_MSG(m_errors.Count(ErrorCode(code)) == m_expected[code],
                           Where() << ErrorCodeName(ErrorCode(code)) << " reported "
                                   << m_errors.Count(ErrorCode(code)) << " times, expected "
                                   << m_expected[code] << " (last box " << Str(m_lastBox)
                                   << ", last message: " << m_errors.LastMessage() << ")");
        }
    }

    void FindAndCompare()
    {
        std::vector<Pair> qt, bf;
        m_qt.FindPairs(qt);
        m_bf.FindPairs(bf);
        std::set<ProxyId> bad;
        for (ProxyId id : m_ids)
        {
            if (!IsSane(id))
            {
                bad.insert(id);
            }
        }
        const std::vector<Pair> all = Sorted(qt);
        QP_REQUIRE_MSG(!HasDuplicates(all), Where() << "quadtree reported a pair twice");
        QP_REQUIRE_MSG(AllOrdered(all), Where() << "quadtree pair with a >= b");
        const std::vector<Pair> sq = Without(qt, bad);
        const std::vector<Pair> sb = Without(bf, bad);
        QP_REQUIRE_MSG(sq == sb, Where() << "sane pairs differ. Only quadtree: " << Str(Difference(sq, sb))
                                         << "\nonly brute force: " << Str(Difference(sb, sq)));
        // NaN proxies pair with nothing in either
        for (const Pair& p : all)
        {
            for (ProxyId id : {p.a, p.b})
            {
                const Box& f = m_qt.GetFatBox(id);
                QP_REQUIRE_MSG(
                    !(std::isnan(f.minX) || std::isnan(f.minY) || std::isnan(f.maxX) || std::isnan(f.maxY)),
                    Where() << "a NaN proxy " << id << " got a pair");
            }
        }
        const std::string problem = m_qt.Validate();
        QP_REQUIRE_MSG(problem.empty(), Where() << "Validate: " << problem);
        CheckErrors();
    }

    std::string Where() const
    {
        std::ostringstream os;
        os << "seed " << m_seed << " step " << m_step << " depth " << m_qt.GetConfig().depth << "\n  ";
        return os.str();
    }

    uint32_t m_seed;
    Rng m_rng;
    BoxSource m_source;
    ErrorCounter m_errors; // installed before any call below
    QuadtreeBroadPhase m_qt;
    BruteForceBroadPhase m_bf;
    std::vector<ProxyId> m_ids;
    std::vector<Box> m_tight;
    std::vector<bool> m_badReported; // per id: its bad box was reported
    int m_expected[4] = {0, 0, 0, 0};
    int m_badCalls = 0;
    int m_badProxiesSeen = 0;
    int m_step = -1;
    Box m_lastBox{};
};

} // namespace

TEST_CASE("Unknown and destroyed ids are reported and change nothing", "[errors]")
{
    ErrorCounter errors;
    for (int depth : {-1, 0, 4})
    {
        HarnessSettings s = RunSettings(50500u + uint32_t(depth + 1), Dist::Mixed, 60, 200);
        s.config.depth = depth;
        INFO("case: " << Describe(s));
        Harness h(s);
        h.Run();
        REQUIRE(errors.Total() == 0);

        // a destroyed id (not yet reused) and ids that were never handed out
        const ProxyId dead = h.Live().front();
        h.Destroy(dead);
        QuadtreeBroadPhase& qt = h.Quadtree();
        const ProxyId bound = qt.GetPool().IdBound();
        const ProxyId unknown[] = {dead, -1, -1000, bound, bound + 7, INT_MAX, INT_MIN};
        int expected = 0;
        for (ProxyId id : unknown)
        {
            CAPTURE(id);
            qt.DestroyProxy(id);
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == ++expected);
            REQUIRE(errors.LastMessage().find("DestroyProxy") != std::string::npos);
            REQUIRE_FALSE(qt.MoveProxy(id, Box{0.0f, 0.0f, 1.0f, 1.0f}, Vec2{1.0f, 0.0f}));
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == ++expected);
            REQUIRE(errors.LastMessage().find("MoveProxy") != std::string::npos);
            qt.TouchProxy(id);
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == ++expected);
            REQUIRE(errors.LastMessage().find("TouchProxy") != std::string::npos);
            const Box& fat = qt.GetFatBox(id);
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == ++expected);
            REQUIRE(SameBox(fat, Box{0.0f, 0.0f, 0.0f, 0.0f}));
            REQUIRE_FALSE(qt.TestOverlap(id, h.Live().front()));
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == ++expected);
            REQUIRE(qt.GetUserData(id) == nullptr); // documented: no report
            REQUIRE(errors.Count(ErrorCode::UnknownProxy) == expected);
            REQUIRE(errors.Total() == expected);
            REQUIRE(qt.Validate() == "");
            REQUIRE(qt.GetProxyCount() == int32_t(h.Live().size()));
        }
        // The brute force reports the same calls the same way.
        BruteForceBroadPhase& bf = h.Brute();
        bf.DestroyProxy(dead);
        REQUIRE_FALSE(bf.MoveProxy(-1, Box{0.0f, 0.0f, 1.0f, 1.0f}, Vec2{0.0f, 0.0f}));
        bf.TouchProxy(bound);
        REQUIRE(errors.Count(ErrorCode::UnknownProxy) == expected + 3);
        errors.Reset();

        // Nothing changed: the next FindPairs finds nothing new, and later calls keep both in step (ids
        // included: a double destroy must not put an id on the free list twice).
        REQUIRE(h.FindPairs().empty());
        h.Run();
        REQUIRE(errors.Total() == 0);
    }
}

TEST_CASE("Non-finite and inverted boxes are reported; the other proxies keep exactly their pairs",
          "[errors]")
{
    int badCalls = 0, badProxies = 0;
    for (uint32_t rep = 0; rep < 24; ++rep)
    {
        Config c;
        c.depth = int(rep % 8) - 1; // auto, 0..6
        c.autoBounds = (rep % 3) != 0;
        c.bounds = Box{-40.0f, -40.0f, 40.0f, 40.0f};
        BadBoxRun run(60000u + rep, c);
        run.Run(400);
        badCalls += run.BadCalls();
        badProxies += run.BadProxiesSeen();
    }
    CHECK(badCalls > 500);
    CHECK(badProxies > 500);
}

TEST_CASE("Each kind of bad box reports its code exactly once", "[errors]")
{
    ErrorCounter errors;
    QuadtreeBroadPhase qt;
    struct Case
    {
        Box box;
        ErrorCode code;
        Vec2 displacement;
    };
    const Case cases[] = {
        {Box{kNaN, 0.0f, 1.0f, 1.0f}, ErrorCode::NonFiniteBox, Vec2{0.0f, 0.0f}},
        {Box{0.0f, 0.0f, 1.0f, kNaN}, ErrorCode::NonFiniteBox, Vec2{0.0f, 0.0f}},
        {Box{-kInf, 0.0f, 1.0f, 1.0f}, ErrorCode::NonFiniteBox, Vec2{0.0f, 0.0f}},
        {Box{0.0f, 0.0f, kInf, 1.0f}, ErrorCode::NonFiniteBox, Vec2{0.0f, 0.0f}},
        {Box{-kInf, -kInf, kInf, kInf}, ErrorCode::NonFiniteBox, Vec2{0.0f, 0.0f}},
        {Box{1.0f, 0.0f, 0.0f, 1.0f}, ErrorCode::InvertedBox, Vec2{0.0f, 0.0f}},
        {Box{0.0f, 1.0f, 1.0f, 0.0f}, ErrorCode::InvertedBox, Vec2{0.0f, 0.0f}},
        {Box{0.6f, 0.6f, 0.4f, 0.4f}, ErrorCode::InvertedBox, Vec2{0.0f, 0.0f}},
        // inside the stored fat box (-0.1, -0.1)-(1.1, 1.1) of `sane`, which is not too large for it either:
        // MoveProxy keeps the stored box, and must still report the box
        {Box{0.35f, 0.35f, 0.25f, 0.25f}, ErrorCode::InvertedBox, Vec2{0.1f, 0.1f}},
    };
    for (const Case& k : cases)
    {
        INFO("box " << Str(k.box) << " displacement (" << k.displacement.x << ", " << k.displacement.y
                    << ")");
        errors.Reset();
        const ProxyId id = qt.CreateProxy(k.box, nullptr);
        REQUIRE(errors.Total() == 1);
        REQUIRE(errors.Count(k.code) == 1);
        REQUIRE(errors.LastMessage().find("CreateProxy") != std::string::npos);
        REQUIRE(qt.Validate() == "");
        qt.DestroyProxy(id);

        // MoveProxy with the bad box, whether or not the stored fat box would be replaced (a proxy of its own:
        // bad boxes are reported once per proxy)
        const ProxyId sane = qt.CreateProxy(Box{0.0f, 0.0f, 1.0f, 1.0f}, nullptr);
        errors.Reset();
        const Box before = qt.GetFatBox(sane);
        const bool moved = qt.MoveProxy(sane, k.box, k.displacement);
        REQUIRE(errors.Total() == 1);
        REQUIRE(errors.Count(k.code) == 1);
        REQUIRE(errors.LastMessage().find("MoveProxy") != std::string::npos);
        REQUIRE(qt.Validate() == "");
        // back to a sane box
        errors.Reset();
        qt.MoveProxy(sane, Box{0.0f, 0.0f, 1.0f, 1.0f}, Vec2{0.0f, 0.0f});
        REQUIRE(errors.Total() == 0);
        REQUIRE(qt.Validate() == "");
        qt.DestroyProxy(sane);
        (void)before;
        (void)moved;
    }
    std::vector<Pair> pairs;
    qt.FindPairs(pairs);
    REQUIRE(pairs.empty());
}

TEST_CASE("A runaway proxy is reported once, not once per call; a new proxy on its id is reported again",
          "[errors]")
{
    ErrorCounter errors;
    QuadtreeBroadPhase qt;
    const ProxyId other = qt.CreateProxy(Box{5.0f, 5.0f, 6.0f, 6.0f}, nullptr);
    const ProxyId runaway = qt.CreateProxy(Box{0.0f, 0.0f, 1.0f, 1.0f}, nullptr);
    std::vector<Pair> pairs;
    for (int step = 0; step < 50; ++step)
    {
        // what a body with a NaN position gives Box2D's MoveProxy every step, through every entry point
        const Box bad{kNaN, kNaN, kNaN, kNaN};
        if (step % 3 == 0)
        {
            qt.QueueMove(runaway, bad, Vec2{kNaN, kNaN});
        }
        else if (step % 3 == 1)
        {
            // the Box2D adapter's way: the test on the fat box it keeps, and the outcome queued
            Box fat = qt.GetFatBox(runaway);
            REQUIRE(RefattenSimd(FatPolicy{}, fat, bad, Vec2{kNaN, kNaN}));
            qt.QueueFatMove(runaway, bad, fat);
        }
        else
        {
            qt.MoveProxy(runaway, bad, Vec2{kNaN, kNaN});
        }
        qt.FindPairs(pairs);
    }
    REQUIRE(errors.Count(ErrorCode::NonFiniteBox) == 1);
    REQUIRE(errors.Total() == 1);
    REQUIRE(errors.LastMessage().find("proxy " + std::to_string(runaway)) != std::string::npos);
    // an inverted box for the same proxy is not reported either: one report per proxy
    qt.MoveProxy(runaway, Box{1.0f, 1.0f, 0.0f, 0.0f}, Vec2{0.0f, 0.0f});
    REQUIRE(errors.Total() == 1);
    // another proxy's first bad box is reported
    qt.MoveProxy(other, Box{kInf, 5.0f, 6.0f, 6.0f}, Vec2{0.0f, 0.0f});
    REQUIRE(errors.Count(ErrorCode::NonFiniteBox) == 2);
    // the id reused by a new proxy: reported again
    qt.DestroyProxy(runaway);
    const ProxyId reused = qt.CreateProxy(Box{kNaN, 0.0f, 1.0f, 1.0f}, nullptr);
    REQUIRE(reused == runaway);
    REQUIRE(errors.Count(ErrorCode::NonFiniteBox) == 3);
    REQUIRE(qt.Validate() == "");
}

TEST_CASE("SetErrorHandler returns the previous handler and ErrorCodeName names every code", "[errors]")
{
    struct Local
    {
        static void A(ErrorCode, const char*, void*) {}
        static void B(ErrorCode, const char*, void*) {}
    };
    const ErrorHandler original = SetErrorHandler(&Local::A);
    REQUIRE(SetErrorHandler(&Local::B) == &Local::A);
    REQUIRE(SetErrorHandler(original) == &Local::B);

    // the context reaches the handler
    {
        ErrorCounter errors;
        ReportError(ErrorCode::FirstAdapterCode, "value %d", 42); // an adapter's code takes the same path
        REQUIRE(errors.Count(ErrorCode::FirstAdapterCode) == 1);
        REQUIRE(errors.LastMessage() == "value 42");
    }
    std::set<std::string> names;
    for (ErrorCode c : {ErrorCode::NonFiniteBox, ErrorCode::InvertedBox, ErrorCode::UnknownProxy,
                        ErrorCode::TaskSystemMisuse, ErrorCode::FirstAdapterCode})
    {
        names.insert(ErrorCodeName(c));
    }
    REQUIRE(names.size() == 5u);
}
