// SPDX-License-Identifier: MIT
// The differential harness: drives a QuadtreeBroadPhase and a BruteForceBroadPhase with the same random calls
// and checks after each one that they agree, and that both agree with an oracle computed here from the fat
// boxes.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "brute_force_broad_phase.h"
#include "quadtree_broad_phase.h"
#include "ray.h"
#include "row_major.h"

#include "segment_entry.h"
#include "test_support.h"

namespace qptest
{

using quadphase::BoxMirror;
using quadphase::BruteForceBroadPhase;
using quadphase::Config;
using quadphase::FatPolicy;
using quadphase::QuadtreeBroadPhase;
using quadphase::RayInput;
using quadphase::SegmentTest;

/// Stops the current test case with `message` when `cond` is false. The message is only built on failure.
#define QP_REQUIRE_MSG(cond, message)                                                                        \
    do                                                                                                       \
    {                                                                                                        \
        if (!(cond))                                                                                         \
        {                                                                                                    \
            FAIL(#cond << "\n" << message);                                                                  \
        }                                                                                                    \
    } while (false)

struct RayCollector
{
    enum class Mode
    {
        NoClip, // return -1: see every candidate
        Clip,   // return the entry fraction of a hit: find the closest
        Stop,   // return 0 on the first call
    };
    Mode mode = Mode::NoClip;
    const quadphase::BroadPhaseInterface* bp = nullptr;
    std::vector<ProxyId> ids;
    int calls = 0;
    float closest = 2.0f; // no hit
    bool inputChanged = false;
    RayInput original{};

    static float Callback(void* context, const RayInput& input, ProxyId id)
    {
        RayCollector* self = static_cast<RayCollector*>(context);
        self->calls += 1;
        self->ids.push_back(id);
        if (!SameFloat(input.p1.x, self->original.p1.x) || !SameFloat(input.p1.y, self->original.p1.y) ||
            !SameFloat(input.p2.x, self->original.p2.x) || !SameFloat(input.p2.y, self->original.p2.y))
        {
            self->inputChanged = true;
        }
        switch (self->mode)
        {
        case Mode::NoClip:
            if (!SameFloat(input.maxFraction, self->original.maxFraction))
            {
                self->inputChanged = true;
            }
            return -1.0f;
        case Mode::Stop:
            return 0.0f;
        case Mode::Clip:
        {
            const double t = EntryFraction(input, self->bp->GetFatBox(id));
            if (t < 0.0)
            {
                return -1.0f;
            }
            const float tf = float(t);
            self->closest = std::min(self->closest, tf);
            return tf;
        }
        }
        return -1.0f;
    }
};

struct HarnessSettings
{
    uint32_t seed = 1;
    Dist dist = Dist::Uniform;
    FatPolicy policy{};
    Config config{};
    float world = 50.0f;
    int targetProxies = 150;
    int operations = 600;
    bool shifts = false;     // include ShiftOrigin calls
    bool queries = true;     // include Query and RayCast checks
    bool timing = false;     // QuadtreeBroadPhase::SetTiming
    int validateEvery = 8;   // Validate() after every n-th operation (and after every FindPairs)
    bool queueMoves = false; // move the quadtree's proxies with QueueMove, applied later
    // with queueMoves: run the fat-box test on a copy of every fat box kept beside the quadtree (its mirror), and
    // queue the changed ones with QueueFatMove, as the Box2D adapter does
    bool fatMoves = false;
};

/// Settings for `operations` random operations on about `targetProxies` proxies drawn from `dist`; the rest
/// default.
inline HarnessSettings RunSettings(uint32_t seed, Dist dist, int targetProxies, int operations)
{
    HarnessSettings s;
    s.seed = seed;
    s.dist = dist;
    s.targetProxies = targetProxies;
    s.operations = operations;
    return s;
}

/// One case of a sweep over distributions and depths: RunSettings at depth `depth`, seed base + 10 dist + depth + 1.
inline HarnessSettings SweepSettings(uint32_t base, Dist dist, int depth, int targetProxies, int operations)
{
    HarnessSettings s =
        RunSettings(base + uint32_t(int(dist)) * 10u + uint32_t(depth + 1), dist, targetProxies, operations);
    s.config.depth = depth;
    return s;
}

inline std::string Describe(const HarnessSettings& s)
{
    std::ostringstream os;
    os << "seed=" << s.seed << " dist=" << DistName(s.dist) << " depth=" << s.config.depth
       << " autoBounds=" << s.config.autoBounds << " bounds=" << Str(s.config.bounds)
       << " extension=" << s.policy.extension << " multiplier=" << s.policy.multiplier << " world=" << s.world
       << " target=" << s.targetProxies << " ops=" << s.operations << " shifts=" << s.shifts
       << " queueMoves=" << s.queueMoves << " fatMoves=" << s.fatMoves;
    return os.str();
}

struct HarnessTotals
{
    int64_t findPairs = 0;
    int64_t pairs = 0;
    int64_t creates = 0;
    int64_t moves = 0;
    int64_t refattens = 0;
    int64_t destroys = 0;
    int64_t touches = 0;
    int64_t queries = 0;
    int64_t rays = 0;
    int64_t shifts = 0;

    HarnessTotals& operator+=(const HarnessTotals& o)
    {
        findPairs += o.findPairs;
        pairs += o.pairs;
        creates += o.creates;
        moves += o.moves;
        refattens += o.refattens;
        destroys += o.destroys;
        touches += o.touches;
        queries += o.queries;
        rays += o.rays;
        shifts += o.shifts;
        return *this;
    }
};

class Harness
{
public:
    explicit Harness(const HarnessSettings& settings)
        : m_settings(settings), m_rng(settings.seed), m_source(m_rng, settings.dist, settings.world),
          m_qt(settings.policy, settings.config), m_bf(settings.policy)
    {
        m_qt.SetTiming(settings.timing);
    }

    QuadtreeBroadPhase& Quadtree() { return m_qt; }
    BruteForceBroadPhase& Brute() { return m_bf; }
    Rng& Random() { return m_rng; }
    BoxSource& Source() { return m_source; }
    const std::vector<ProxyId>& Live() const { return m_live; }
    const Box& Tight(ProxyId id) const { return m_tight[size_t(id)]; }
    const HarnessTotals& Totals() const { return m_totals; }

    /// When recording, every FindPairs result of the quadtree (in its order) is kept in History().
    void Record(bool on) { m_record = on; }
    const std::vector<std::vector<Pair>>& History() const { return m_history; }

    /// Runs the configured number of random operations, then a final FindPairs.
    void Run()
    {
        for (int step = 0; step < m_settings.operations; ++step)
        {
            m_step = step;
            RandomOperation();
            if (m_settings.validateEvery > 0 && step % m_settings.validateEvery == 0)
            {
                CheckValid();
            }
        }
        FindPairs();
    }

    void RandomOperation()
    {
        const int n = int(m_live.size());
        const bool growing = n < m_settings.targetProxies;
        const int roll = UniformInt(m_rng, 0, 999);
        if (n == 0 || (growing && roll < 350))
        {
            Create(m_source.Next());
        }
        else if (roll < 420)
        {
            Destroy(m_live[size_t(UniformInt(m_rng, 0, n - 1))]);
        }
        else if (roll < 450)
        {
            Touch(m_live[size_t(UniformInt(m_rng, 0, n - 1))]);
        }
        else if (roll < 520)
        {
            // move a batch, as a physics step does
            const int k = UniformInt(m_rng, 1, std::max(1, n / 3));
            for (int i = 0; i < k; ++i)
            {
                RandomMove(m_live[size_t(UniformInt(m_rng, 0, n - 1))]);
            }
        }
        else if (roll < 580)
        {
            FindPairs();
        }
        else if (roll < 610 && m_settings.queries)
        {
            RandomQuery();
        }
        else if (roll < 640 && m_settings.queries)
        {
            RandomRay();
        }
        else if (roll < 645 && m_settings.shifts)
        {
            RandomShift();
        }
        else if (!growing && roll < 700)
        {
            Create(m_source.Next());
        }
        else
        {
            RandomMove(m_live[size_t(UniformInt(m_rng, 0, n - 1))]);
        }
    }

    // -----------------------------------------------------------------------------------------------------------
    // Operations, each checked

    ProxyId Create(const Box& tight)
    {
        void* user = reinterpret_cast<void*>(uintptr_t(0x1000 + m_totals.creates));
        const ProxyId a = m_qt.CreateProxy(tight, user);
        const ProxyId b = m_bf.CreateProxy(tight, user);
        QP_REQUIRE_MSG(a == b, Where() << "CreateProxy ids differ: quadtree " << a << ", brute force " << b);
        QP_REQUIRE_MSG(!IsLive(a), Where() << "CreateProxy returned live id " << a);
        Grow(a);
        if (m_settings.fatMoves)
        {
            m_records[size_t(a)] =
                m_qt.GetPool().Fat(a); // the quadtree copies no new proxy's box to its mirror
        }
        m_tight[size_t(a)] = tight;
        m_buffered[size_t(a)] = 1;
        m_liveFlag[size_t(a)] = 1;
        m_user[size_t(a)] = user;
        m_live.push_back(a);
        m_totals.creates += 1;
        CheckFat(a, "CreateProxy");
        QP_REQUIRE_MSG(m_qt.GetUserData(a) == user && m_bf.GetUserData(a) == user,
                       Where() << "user data of " << a);
        return a;
    }

    void Destroy(ProxyId id)
    {
        m_qt.DestroyProxy(id);
        m_bf.DestroyProxy(id);
        m_liveFlag[size_t(id)] = 0;
        m_buffered[size_t(id)] = 0;
        m_live.erase(std::find(m_live.begin(), m_live.end(), id));
        m_totals.destroys += 1;
        QP_REQUIRE_MSG(m_qt.GetProxyCount() == int32_t(m_live.size()) &&
                           m_bf.GetProxyCount() == int32_t(m_live.size()),
                       Where() << "proxy counts " << m_qt.GetProxyCount() << " / " << m_bf.GetProxyCount()
                               << " vs " << m_live.size());
    }

    void Touch(ProxyId id)
    {
        m_qt.TouchProxy(id);
        m_bf.TouchProxy(id);
        m_buffered[size_t(id)] = 1;
        m_totals.touches += 1;
    }

    bool Move(ProxyId id, const Box& tight, Vec2 displacement)
    {
        if (m_settings.queueMoves)
        {
            // No answer to compare: the quadtree applies the move later (at FindPairs, or when something reads a
            // fat box first). Its fat box is compared after the next FindPairs, its pairs at that FindPairs.
            QueueMove(id, tight, displacement);
            const bool b = m_bf.MoveProxy(id, tight, displacement);
            m_queued.push_back(id);
            m_tight[size_t(id)] = tight;
            m_buffered[size_t(id)] |= b ? 1 : 0;
            m_totals.moves += 1;
            m_totals.refattens += b ? 1 : 0;
            return b;
        }
        const Box before = m_bf.GetFatBox(id);
        const bool a = m_qt.MoveProxy(id, tight, displacement);
        const bool b = m_bf.MoveProxy(id, tight, displacement);
        QP_REQUIRE_MSG(a == b, Where() << "MoveProxy(" << id << ", " << Str(tight) << ") returned " << a
                                       << " (quadtree) and " << b << " (brute force)");
        CheckFat(id, "MoveProxy");
        if (!a)
        {
            QP_REQUIRE_MSG(SameBox(before, m_bf.GetFatBox(id)), Where()
                                                                    << "fat box changed without refattening");
        }
        m_tight[size_t(id)] = tight;
        m_buffered[size_t(id)] |= a ? 1 : 0;
        m_totals.moves += 1;
        m_totals.refattens += a ? 1 : 0;
        return a;
    }

    void RandomMove(ProxyId id)
    {
        const Vec2 d = m_source.Displacement();
        Box tight = Translate(m_tight[size_t(id)], d);
        if (Chance(m_rng, 0.1))
        {
            // the shape changes size too (Box2D passes the swept box: union of the start and end boxes)
            const Box old = m_tight[size_t(id)];
            tight = Box{std::min(old.minX, tight.minX), std::min(old.minY, tight.minY),
                        std::max(old.maxX, tight.maxX), std::max(old.maxY, tight.maxY)};
        }
        else if (Chance(m_rng, 0.05))
        {
            tight = m_source.Next(); // teleport (SetTransform)
        }
        Move(id, tight, d);
    }

    /// FindPairs on both; checks them against each other and against the oracle. Returns the quadtree's pairs
    /// in its order.
    std::vector<Pair> FindPairs()
    {
        std::vector<Pair> expected = OraclePairs();
        std::vector<Pair> qt;
        std::vector<Pair> bf;
        m_qt.FindPairs(qt);
        m_bf.FindPairs(bf);
        QP_REQUIRE_MSG(m_qt.QueuedMoveCount() == 0, Where() << "FindPairs left queued moves");
        for (ProxyId id : m_queued)
        {
            if (IsLive(id))
            {
                CheckFat(id, "QueueMove");
            }
        }
        m_queued.clear();
        std::fill(m_buffered.begin(), m_buffered.end(), uint8_t(0));
        if (m_record)
        {
            m_history.push_back(qt);
        }
        m_totals.findPairs += 1;
        m_totals.pairs += int64_t(qt.size());

        QP_REQUIRE_MSG(AllOrdered(qt), Where() << "quadtree pair with a >= b: " << Str(qt));
        QP_REQUIRE_MSG(AllOrdered(bf), Where() << "brute-force pair with a >= b: " << Str(bf));
        const std::vector<Pair> sq = Sorted(qt);
        const std::vector<Pair> sb = Sorted(bf);
        QP_REQUIRE_MSG(!HasDuplicates(sq), Where() << "quadtree reported a pair twice: " << Str(sq));
        QP_REQUIRE_MSG(!HasDuplicates(sb), Where() << "brute force reported a pair twice: " << Str(sb));
        QP_REQUIRE_MSG(sq == sb, Where()
                                     << "pair lists differ. Only quadtree: " << Str(Difference(sq, sb))
                                     << "\nonly brute force: " << Str(Difference(sb, sq)) << Detail(sq, sb));
        QP_REQUIRE_MSG(sb == expected, Where() << "brute force differs from the oracle. Only brute force: "
                                               << Str(Difference(sb, expected))
                                               << "\nonly oracle: " << Str(Difference(expected, sb)));
        CheckValid();
        return qt;
    }

    void RandomQuery()
    {
        Box q = m_source.Next();
        if (Chance(m_rng, 0.1))
        {
            q = CentredBox(Uniform(m_rng, -m_settings.world, m_settings.world),
                           Uniform(m_rng, -m_settings.world, m_settings.world), LogUniform(m_rng, 0.0f, 3.0f),
                           LogUniform(m_rng, 0.0f, 3.0f));
        }
        CheckQuery(q);
    }

    void CheckQuery(const Box& q)
    {
        m_totals.queries += 1;
        std::vector<ProxyId> expected;
        for (ProxyId id : m_live)
        {
            if (quadphase::Overlaps(m_bf.GetFatBox(id), q))
            {
                expected.push_back(id);
            }
        }
        std::sort(expected.begin(), expected.end());

        IdCollector a, b;
        m_qt.Query(q, &IdCollector::Callback, &a);
        m_bf.Query(q, &IdCollector::Callback, &b);
        const std::vector<ProxyId> sa = a.SortedIds();
        QP_REQUIRE_MSG(std::adjacent_find(sa.begin(), sa.end()) == sa.end(),
                       Where() << "Query " << Str(q) << " reported an id twice");
        QP_REQUIRE_MSG(sa == expected, Where() << "quadtree Query " << Str(q) << " found " << sa.size()
                                               << " ids, expected " << expected.size());
        QP_REQUIRE_MSG(b.SortedIds() == expected, Where() << "brute-force Query " << Str(q) << " differs");

        // early exit: the first `false` ends the query
        IdCollector c, d;
        c.stopAfter = 1;
        d.stopAfter = 1;
        m_qt.Query(q, &IdCollector::Callback, &c);
        m_bf.Query(q, &IdCollector::Callback, &d);
        const int want = expected.empty() ? 0 : 1;
        QP_REQUIRE_MSG(c.calls == want && d.calls == want,
                       Where() << "Query stopping after the first hit made " << c.calls << " (quadtree) and "
                               << d.calls << " (brute force) calls; expected " << want);
    }

    void RandomRay()
    {
        const float w = m_settings.world * 1.2f;
        RayInput in{};
        do
        {
            in.p1 = Vec2{Uniform(m_rng, -w, w), Uniform(m_rng, -w, w)};
            if (Chance(m_rng, 0.2))
            {
                // axis-aligned rays
                in.p2 = Chance(m_rng, 0.5) ? Vec2{in.p1.x, Uniform(m_rng, -w, w)}
                                           : Vec2{Uniform(m_rng, -w, w), in.p1.y};
            }
            else if (Chance(m_rng, 0.2))
            {
                // short rays
                in.p2 = Vec2{in.p1.x + Uniform(m_rng, -1.0f, 1.0f), in.p1.y + Uniform(m_rng, -1.0f, 1.0f)};
            }
            else
            {
                in.p2 = Vec2{Uniform(m_rng, -w, w), Uniform(m_rng, -w, w)};
            }
        } while (in.p1.x == in.p2.x && in.p1.y == in.p2.y);
        in.maxFraction = Chance(m_rng, 0.5) ? 1.0f : Uniform(m_rng, 0.05f, 1.0f);
        CheckRay(in);
    }

    void CheckRay(const RayInput& in)
    {
        m_totals.rays += 1;
        const SegmentTest segment(in);
        std::vector<ProxyId> expected;
        double closest = 2.0;
        for (ProxyId id : m_live)
        {
            if (segment.MayCross(m_bf.GetFatBox(id)))
            {
                expected.push_back(id);
                const double t = EntryFraction(in, m_bf.GetFatBox(id));
                if (t >= 0.0)
                {
                    closest = std::min(closest, double(float(t)));
                }
            }
        }
        std::sort(expected.begin(), expected.end());
        std::ostringstream ray;
        ray.precision(9);
        ray << "ray (" << in.p1.x << ", " << in.p1.y << ") -> (" << in.p2.x << ", " << in.p2.y
            << ") maxFraction " << in.maxFraction;

        // no clipping: the same candidates as the oracle
        RayCollector a, b;
        a.original = b.original = in;
        a.bp = &m_qt;
        b.bp = &m_bf;
        m_qt.RayCast(in, &RayCollector::Callback, &a);
        m_bf.RayCast(in, &RayCollector::Callback, &b);
        std::vector<ProxyId> sa = a.ids;
        std::sort(sa.begin(), sa.end());
        std::vector<ProxyId> sb = b.ids;
        std::sort(sb.begin(), sb.end());
        QP_REQUIRE_MSG(!a.inputChanged && !b.inputChanged, Where()
                                                               << ray.str() << ": callback input changed");
        QP_REQUIRE_MSG(std::adjacent_find(sa.begin(), sa.end()) == sa.end(),
                       Where() << ray.str() << ": quadtree reported an id twice");
        QP_REQUIRE_MSG(sa == expected, Where() << ray.str() << ": quadtree found " << sa.size()
                                               << " ids, expected " << expected.size());
        QP_REQUIRE_MSG(sb == expected, Where() << ray.str() << ": brute force found " << sb.size()
                                               << " ids, expected " << expected.size());

        // clipping: the closest hit is the same
        RayCollector c, d;
        c.mode = d.mode = RayCollector::Mode::Clip;
        c.original = d.original = in;
        c.bp = &m_qt;
        d.bp = &m_bf;
        m_qt.RayCast(in, &RayCollector::Callback, &c);
        m_bf.RayCast(in, &RayCollector::Callback, &d);
        QP_REQUIRE_MSG(!c.inputChanged && !d.inputChanged, Where()
                                                               << ray.str() << ": callback p1/p2 changed");
        QP_REQUIRE_MSG(SameFloat(c.closest, d.closest) && double(c.closest) == closest,
                       Where() << ray.str() << ": closest fraction " << c.closest << " (quadtree), "
                               << d.closest << " (brute force), " << closest << " (oracle)");
        QP_REQUIRE_MSG(c.calls <= a.calls,
                       Where() << ray.str() << ": clipping made more callbacks than not clipping");

        // stop at the first candidate
        RayCollector e, f;
        e.mode = f.mode = RayCollector::Mode::Stop;
        e.original = f.original = in;
        m_qt.RayCast(in, &RayCollector::Callback, &e);
        m_bf.RayCast(in, &RayCollector::Callback, &f);
        const int want = expected.empty() ? 0 : 1;
        QP_REQUIRE_MSG(e.calls == want && f.calls == want,
                       Where() << ray.str() << ": stopping ray cast made " << e.calls << " (quadtree) and "
                               << f.calls << " (brute force) calls; expected " << want);
    }

    void RandomShift()
    {
        Vec2 origin{0.0f, 0.0f};
        switch (UniformInt(m_rng, 0, 3))
        {
        case 0:
            break; // a zero shift
        case 1:
            origin = Vec2{Uniform(m_rng, -m_settings.world, m_settings.world),
                          Uniform(m_rng, -m_settings.world, m_settings.world)};
            break;
        case 2:
            origin = Vec2{float(UniformInt(m_rng, -64, 64)), float(UniformInt(m_rng, -64, 64))};
            break;
        default:
            origin = Vec2{Uniform(m_rng, -2000.0f, 2000.0f), Uniform(m_rng, -2000.0f, 2000.0f)};
            break;
        }
        Shift(origin);
    }

    void Shift(Vec2 origin)
    {
        std::vector<Box> before(m_liveFlag.size());
        for (ProxyId id : m_live)
        {
            before[size_t(id)] = m_bf.GetFatBox(id);
        }
        m_qt.ShiftOrigin(origin);
        m_bf.ShiftOrigin(origin);
        m_totals.shifts += 1;
        for (ProxyId id : m_live)
        {
            const Box& b = before[size_t(id)];
            const Box want{b.minX - origin.x, b.minY - origin.y, b.maxX - origin.x, b.maxY - origin.y};
            CheckFat(id, "ShiftOrigin");
            QP_REQUIRE_MSG(SameBox(m_bf.GetFatBox(id), want), Where() << "ShiftOrigin(" << origin.x << ", "
                                                                      << origin.y << ") moved proxy " << id
                                                                      << " to " << Str(m_bf.GetFatBox(id)));
            m_tight[size_t(id)] = Translate(m_tight[size_t(id)], Vec2{-origin.x, -origin.y});
        }
        CheckValid();
    }

    void CheckValid()
    {
        const std::string problem = m_qt.Validate();
        QP_REQUIRE_MSG(problem.empty(), Where() << "Validate: " << problem);
    }

    /// Every pair of live proxies whose fat boxes overlap and one of which is buffered, sorted.
    std::vector<Pair> OraclePairs() const
    {
        std::vector<ProxyId> ids = m_live;
        std::sort(ids.begin(), ids.end());
        std::vector<Pair> pairs;
        for (size_t i = 0; i < ids.size(); ++i)
        {
            const Box& a = m_bf.GetFatBox(ids[i]);
            const bool ba = m_buffered[size_t(ids[i])] != 0;
            for (size_t j = i + 1; j < ids.size(); ++j)
            {
                if ((ba || m_buffered[size_t(ids[j])] != 0) && quadphase::Overlaps(a, m_bf.GetFatBox(ids[j])))
                {
                    pairs.push_back(Pair{ids[i], ids[j]});
                }
            }
        }
        return pairs;
    }

    std::string Where() const
    {
        std::ostringstream os;
        os << Describe(m_settings) << " step=" << m_step << " proxies=" << m_live.size() << "\n  ";
        return os.str();
    }

private:
    bool IsLive(ProxyId id) const
    {
        return id >= 0 && size_t(id) < m_liveFlag.size() && m_liveFlag[size_t(id)];
    }

    void Grow(ProxyId id)
    {
        if (size_t(id) >= m_liveFlag.size())
        {
            m_liveFlag.resize(size_t(id) + 1, 0);
            m_buffered.resize(size_t(id) + 1, 0);
            m_tight.resize(size_t(id) + 1, Box{0, 0, 0, 0});
            m_user.resize(size_t(id) + 1, nullptr);
        }
        if (m_settings.fatMoves && size_t(id) >= m_records.size())
        {
            // The records move: the quadtree copies the boxes it changes itself (ShiftOrigin) to the new ones.
            m_records.resize(std::max<size_t>(16, 2 * (size_t(id) + 1)), Box{0, 0, 0, 0});
            BoxMirror mirror;
            mirror.base = reinterpret_cast<unsigned char*>(m_records.data());
            mirror.stride = sizeof(Box);
            mirror.capacity = int32_t(m_records.size());
            m_qt.SetBoxMirror(mirror);
        }
    }

    // QueueMove, or with fatMoves the Box2D adapter's way (NodeRecords::Move): the test on the kept fat box, and
    // QueueFatMove when it changed; Validate() then checks that the kept boxes are the quadtree's, bit for bit.
    void QueueMove(ProxyId id, const Box& tight, Vec2 displacement)
    {
        if (!m_settings.fatMoves)
        {
            m_qt.QueueMove(id, tight, displacement);
            return;
        }
        Box fat = m_records[size_t(id)];
        if (RefattenSimd(m_settings.policy, fat, tight, displacement))
        {
            m_qt.QueueFatMove(id, tight, fat);
            m_records[size_t(id)] = fat;
        }
        else if (!IsSaneSimd(tight))
        {
            m_qt.QueueMove(id, tight, displacement);
        }
    }

    void CheckFat(ProxyId id, const char* call)
    {
        const Box a = m_qt.GetFatBox(id);
        const Box b = m_bf.GetFatBox(id);
        QP_REQUIRE_MSG(SameBox(a, b), Where() << call << ": fat boxes of " << id << " differ: " << Str(a)
                                              << " vs " << Str(b));
    }

    std::string Detail(const std::vector<Pair>& sq, const std::vector<Pair>& sb) const
    {
        std::ostringstream os;
        std::vector<Pair> diff = Difference(sb, sq);
        std::vector<Pair> extra = Difference(sq, sb);
        diff.insert(diff.end(), extra.begin(), extra.end());
        const quadphase::Stats s = m_qt.GetStats();
        os << "\n  pyramid depth " << s.depth << " bounds " << Str(s.bounds) << " leaf " << s.leafSize;
        for (size_t i = 0; i < diff.size() && i < 5; ++i)
        {
            for (ProxyId id : {diff[i].a, diff[i].b})
            {
                int level;
                int32_t index;
                m_qt.GetPyramid().Place(m_qt.GetFatBox(id), level, index);
                os << "\n  proxy " << id << " fat " << Str(m_qt.GetFatBox(id)) << " level " << level
                   << " cell " << index << " buffered " << int(m_buffered[size_t(id)]);
            }
        }
        return os.str();
    }

    HarnessSettings m_settings;
    Rng m_rng;
    BoxSource m_source;
    QuadtreeBroadPhase m_qt;
    BruteForceBroadPhase m_bf;
    std::vector<ProxyId> m_live;
    std::vector<uint8_t> m_liveFlag;
    std::vector<uint8_t> m_buffered; // oracle: created, refattened or touched since the last FindPairs
    std::vector<ProxyId> m_queued;   // ids moved with QueueMove since the last FindPairs (may repeat)
    std::vector<Box> m_tight;
    std::vector<Box> m_records; // with fatMoves: every fat box, kept beside the quadtree (its mirror)
    std::vector<void*> m_user;
    HarnessTotals m_totals;
    int m_step = -1;
    bool m_record = false;
    std::vector<std::vector<Pair>> m_history;
};

} // namespace qptest
