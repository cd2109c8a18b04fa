// SPDX-License-Identifier: MIT
// qp-replay's engines other than the quadtree core (replay.cpp): stock Box2D 2.4.1's b2BroadPhase (the
// reference line and pair sets), brute force, the paper's design, Chipmunk2D, Bullet, the oracle floor and the
// null engine. Same replay and timing definition as the quadtree (replay_loop.h). Engine names (--engine):
//
//   stock       b2BroadPhase; --hashes-out writes its pair-set hashes (the exactness reference)
//   brute       quadphase::BruteForceBroadPhase (refused above --max-proxies, default 20000)
//   paper       the paper's design (bench/baselines), levels --levels (auto: leaves about twice the mean fat
//               box), --threads; APPROXIMATE: the check counts its missed, duplicate and extra pairs
//   cp-hash-xK  Chipmunk2D's cpSpaceHash, cell side K x the mean fat box side (K = 0.5, 1, 2, 4, 8, ...)
//   cp-tree     Chipmunk2D's cpBBTree
//   bt-dbvt     Bullet's btDbvtBroadphase
//   bt-sap      Bullet's bt32BitAxisSweep3 over the trace's bounds (native mode only, below)
//   oracle      the output alone: Box2D's protocol with the pairs of every query known in advance
//   null        nothing: the replay loop's own cost (op dispatch, id map, clock reads); timed runs only
//
// Two modes. Box2D's protocol (the names above): the engine keeps Box2D's fat boxes (FattenNew / Refatten,
// bit-identical to Box2D's) and move buffer, re-indexes a proxy when its fat box changes, and at UpdatePairs
// queries the index with every buffered proxy's fat box, keeping the ids whose fat boxes overlap it; its
// pairs are stock's by definition, checked call by call against stock's hashes (--compare-hashes; exit 3 on a
// mismatch). Native mode (suffix "-native", "-mM" for the displacement multiplier of the fat boxes, default
// Box2D's 4): the peer's own per-step loop, which cannot express Box2D's contract (the pairs of the moved
// proxies only): it hands over every overlapping pair each step (Chipmunk's cpSpatialIndexReindexQuery;
// Bullet's calculateOverlappingPairs and its pair cache), filtered by the fat-box test into a vector. Checked
// call by call against the set of all overlapping fat-box pairs at that call (a sort-and-sweep over the
// engine's boxes).
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "box_to_aabb.h"
#include "brute_force_broad_phase.h"
#include "core_engine.h"
#include "fat_policy.h"
#include "loaded_trace.h"
#include "pair_hash.h"
#include "paper_quadtree.h"
#include "peer_indexes.h"
#include "proxy_pool.h"
#include "replay_loop.h"
#include "timed_run.h"

namespace qpbench
{
namespace
{

using quadphase::bench::PaperQuadtreeBroadPhase;
using PairList = std::vector<std::pair<int32_t, int32_t>>;

/// The last UpdatePairs call's pairs, in recorded ids, for the engines that collect them so.
struct RecordedPairs
{
    size_t PairCount() const { return m_pairs.size(); }
    void PairKeys(std::vector<uint64_t>& keys) const
    {
        for (const auto& p : m_pairs)
        {
            keys.push_back(PairKey(p.first, p.second));
        }
    }
    void BeginTimedSteps() {}

protected:
    PairList m_pairs;
};

/// The sorted unique pair keys of `engine`'s last call; returns how many pairs it reported more than once.
template <typename Engine>
int64_t UniqueKeys(const Engine& engine, std::vector<uint64_t>& keys)
{
    engine.PairKeys(keys);
    const size_t reported = keys.size();
    HashPairKeys(keys);
    return int64_t(reported - keys.size());
}

/// Does nothing: measures the replay loop's own cost (op dispatch, id map, clock reads).
class NullEngine : public RecordedPairs
{
public:
    int32_t Create(const Box&, int32_t recorded)
    {
        ++m_live;
        return recorded;
    }
    void Destroy(int32_t) { --m_live; }
    void Move(int32_t, const Box&, Vec2) {}
    void Touch(int32_t) {}
    void UpdatePairs() {}
    void ShiftOrigin(Vec2) {}
    int32_t ProxyCount() const { return m_live; }

private:
    int32_t m_live = 0;
};

class StockEngine : public RecordedPairs
{
public:
    int32_t Create(const Box& tight, int32_t recorded)
    {
        return m_bp.CreateProxy(ToAabb(tight), reinterpret_cast<void*>(intptr_t(recorded)));
    }
    void Destroy(int32_t id) { m_bp.DestroyProxy(id); }
    void Move(int32_t id, const Box& tight, Vec2 d) { m_bp.MoveProxy(id, ToAabb(tight), b2Vec2(d.x, d.y)); }
    void Touch(int32_t id) { m_bp.TouchProxy(id); }
    void UpdatePairs()
    {
        m_pairs.clear();
        m_bp.UpdatePairs(this);
    }
    void ShiftOrigin(Vec2 o) { m_bp.ShiftOrigin(b2Vec2(o.x, o.y)); }
    int32_t ProxyCount() const { return m_bp.GetProxyCount(); }
    void AddPair(void* a, void* b) { m_pairs.emplace_back(int32_t(intptr_t(a)), int32_t(intptr_t(b))); }

private:
    b2BroadPhase m_bp;
};

/// The paper's design beside the quadtree core (exact): counts, per call, the pairs it misses, repeats or
/// adds.
class PaperChecked
{
public:
    PaperChecked(int levels, const Box& bounds, int threads)
        : m_paper(levels, bounds, threads, quadphase::Schedule::Static,
                  quadphase::bench::PaperPairReport::Buffered),
          m_ref(quadphase::FatPolicy{}, SerialConfig())
    {
    }
    int32_t Create(const Box& tight, int32_t recorded)
    {
        const int32_t id = m_paper.Create(tight, recorded);
        m_refId.resize(std::max(m_refId.size(), size_t(id) + 1), -1);
        m_refId[size_t(id)] = m_ref.Create(tight, recorded);
        return id;
    }
    void Destroy(int32_t id) { m_paper.Destroy(id), m_ref.Destroy(m_refId[size_t(id)]); }
    void Move(int32_t id, const Box& tight, Vec2 d)
    {
        m_paper.Move(id, tight, d), m_ref.Move(m_refId[size_t(id)], tight, d);
    }
    void Touch(int32_t id) { m_paper.Touch(id), m_ref.Touch(m_refId[size_t(id)]); }
    void ShiftOrigin(Vec2 o) { m_paper.ShiftOrigin(o), m_ref.ShiftOrigin(o); }
    void UpdatePairs()
    {
        m_paper.UpdatePairs();
        m_ref.UpdatePairs();
        std::vector<uint64_t> mine, ref, diff;
        duplicates += UniqueKeys(m_paper, mine);
        UniqueKeys(m_ref, ref);
        std::set_difference(ref.begin(), ref.end(), mine.begin(), mine.end(), std::back_inserter(diff));
        missed += int64_t(diff.size());
        diff.clear();
        std::set_difference(mine.begin(), mine.end(), ref.begin(), ref.end(), std::back_inserter(diff));
        extra += int64_t(diff.size());
        exact += int64_t(ref.size());
    }
    int32_t ProxyCount() const { return m_paper.ProxyCount(); }
    size_t PairCount() const { return m_paper.PairCount(); }
    void PairKeys(std::vector<uint64_t>& keys) const { m_paper.PairKeys(keys); }
    void BeginTimedSteps() {}

    int64_t missed = 0, duplicates = 0, extra = 0, exact = 0;

private:
    static quadphase::Config SerialConfig()
    {
        quadphase::Config c;
        c.threads = 1; // the reference need not be fast; one thread keeps it off a busy machine's other core
        return c;
    }
    CoreEngine<PaperQuadtreeBroadPhase> m_paper;
    CoreEngine<quadphase::QuadtreeBroadPhase> m_ref;
    std::vector<int32_t> m_refId;
};

/// A foreign index beside the proxies it holds (the core's ProxyPool: fat boxes, recorded ids as user data and
/// Box2D's move buffer), in either mode (see the file comment): Box2D's protocol (with OracleIndex, over no
/// index at all), or with kNativeMode the peer's own loop, every overlapping fat-box pair each step.
/// `multiplier` is the fat boxes' displacement multiplier (native mode's -mM; else Box2D's).
template <typename Index, bool kNativeMode>
class PeerEngine : public RecordedPairs
{
public:
    template <typename... A>
    explicit PeerEngine(float multiplier, A&&... a) : m_index(&m_pool, std::forward<A>(a)...)
    {
        m_policy.multiplier = multiplier;
    }
    int32_t Create(const Box& tight, int32_t recorded)
    {
        const int32_t id = m_pool.Allocate(quadphase::FattenNew(m_policy, tight),
                                           reinterpret_cast<void*>(intptr_t(recorded)));
        m_index.Insert(id, m_pool.Fat(id));
        Buffer(id);
        return id;
    }
    void Destroy(int32_t id) { m_index.Remove(id), m_pool.Free(id); }
    void Move(int32_t id, const Box& tight, Vec2 d)
    {
        // Box2D's fat-box test; the index is updated (and the proxy buffered) only when the fat box changed.
        if (quadphase::Refatten(m_policy, m_pool.Fat(id), tight, d))
        {
            m_index.Update(id, m_pool.Fat(id));
            Buffer(id);
        }
    }
    void Touch(int32_t id) { Buffer(id); }
    void UpdatePairs()
    {
        m_pairs.clear();
        if constexpr (kNativeMode)
        {
            m_index.AllPairs([&](int32_t a, int32_t b) {
                if (quadphase::Overlaps(m_pool.Fat(a), m_pool.Fat(b)))
                {
                    m_pairs.emplace_back(Recorded(a), Recorded(b));
                }
            });
            return;
        }
        m_pool.LendBuffer(m_work); // the live buffered proxies, in call order, each flagged "in work"
        for (int32_t q : m_work)
        {
            const size_t before = m_pairs.size();
            if constexpr (std::is_same_v<Index, OracleIndex>)
            {
                m_index.Append(m_pairs);
            }
            else
            {
                const Box qb = m_pool.Fat(q);
                m_index.Query(qb, [&](int32_t o) {
                    // Box2D's rule: when both are buffered, only the query of the smaller id reports the pair.
                    if (o != q && m_pool.IsLive(o) && !(m_pool.InWork(o) && o < q) &&
                        quadphase::Overlaps(m_pool.Fat(o), qb))
                    {
                        m_pairs.emplace_back(Recorded(q), Recorded(o));
                    }
                });
            }
            if (perQuery != nullptr)
            {
                perQuery->push_back(int32_t(m_pairs.size() - before));
            }
        }
        if (allPairs != nullptr)
        {
            allPairs->insert(allPairs->end(), m_pairs.begin(), m_pairs.end());
        }
        m_pool.ReturnBuffer(m_work);
    }
    void ShiftOrigin(Vec2)
    {
        std::fprintf(stderr, "qp-replay: ShiftOrigin is not supported here\n"), std::exit(1);
    }
    int32_t ProxyCount() const { return m_pool.LiveCount(); }

    /// Every pair of live proxies whose fat boxes overlap, in recorded ids (sort and sweep on minX; untimed).
    void AllOverlapKeys(std::vector<uint64_t>& keys) const
    {
        std::vector<int32_t> order;
        for (int32_t id = 0; id < m_pool.IdBound(); ++id)
        {
            if (m_pool.IsLive(id))
            {
                order.push_back(id);
            }
        }
        std::sort(order.begin(), order.end(),
                  [&](int32_t a, int32_t b) { return m_pool.Fat(a).minX < m_pool.Fat(b).minX; });
        for (size_t i = 0; i < order.size(); ++i)
        {
            const Box& a = m_pool.Fat(order[i]);
            for (size_t j = i + 1; j < order.size() && m_pool.Fat(order[j]).minX <= a.maxX; ++j)
            {
                if (quadphase::Overlaps(a, m_pool.Fat(order[j])))
                {
                    keys.push_back(PairKey(Recorded(order[i]), Recorded(order[j])));
                }
            }
        }
    }

    std::vector<int32_t>* perQuery = nullptr; // preparing the oracle: pairs per query, and all pairs in order
    PairList* allPairs = nullptr;

private:
    int32_t Recorded(int32_t id) const { return int32_t(intptr_t(m_pool.UserData(id))); }
    /// Into Box2D's move buffer (native mode has none: it reports every pair anyway).
    void Buffer(int32_t id)
    {
        if (!kNativeMode)
        {
            m_pool.Buffer(id);
        }
    }
    quadphase::FatPolicy m_policy;
    quadphase::ProxyPool m_pool; // before m_index, which keeps its address
    Index m_index;
    std::vector<int32_t> m_work;
};

/// Checks a native engine after every UpdatePairs: its unique pair set against all overlapping fat-box pairs.
struct NativeCheck : NoObserver
{
    int64_t calls = 0, mismatches = 0, duplicates = 0;
    template <typename Engine>
    void AfterUpdatePairs(Engine& engine, bool)
    {
        std::vector<uint64_t> mine, ref;
        duplicates += UniqueKeys(engine, mine);
        engine.AllOverlapKeys(ref);
        HashPairKeys(ref);
        if (mine != ref && mismatches++ < 5)
        {
            std::fprintf(stderr, "MISMATCH at UpdatePairs call %lld: %zu pairs, %zu overlapping\n",
                         static_cast<long long>(calls), mine.size(), ref.size());
        }
        ++calls;
    }
};

/// Trace geometry: bounds of every finite box, mean fat box side of the created proxies.
struct Geometry
{
    Box bounds{0, 0, 0, 0};
    double meanSide = 1.0;
};

Geometry Measure(const LoadedTrace& loaded)
{
    Geometry g;
    bool first = true;
    double sideSum = 0.0;
    int64_t created = 0;
    for (const TraceOp& op : loaded.trace.Ops())
    {
        const Box& b = op.box;
        if ((op.kind != TraceOp::Create && op.kind != TraceOp::Move) || !quadphase::IsFinite(b))
        {
            continue;
        }
        g.bounds = first ? b
                         : Box{std::min(g.bounds.minX, b.minX), std::min(g.bounds.minY, b.minY),
                               std::max(g.bounds.maxX, b.maxX), std::max(g.bounds.maxY, b.maxY)};
        first = false;
        if (op.kind == TraceOp::Create)
        {
            sideSum += 0.5 * (double(b.maxX - b.minX) + double(b.maxY - b.minY)) + 0.2;
            ++created;
        }
    }
    g.meanSide = created > 0 ? sideSum / double(created) : 1.0;
    return g;
}

template <typename Engine>
constexpr bool kNative = false;
template <typename Index>
constexpr bool kNative<PeerEngine<Index, true>> = true;

/// An engine built from `a` as a contender. Its check: Box2D's protocol, hashes against --compare-hashes, or written to
/// --hashes-out; native mode: NativeCheck.
template <typename Engine, typename... A>
Contender Contend(const PeerRun& run, const A&... a)
{
    const auto make = [=] {
        return std::make_unique<Engine>(a...);
    };
    const auto check = [&run, make] {
        std::unique_ptr<Engine> engine = make();
        JsonLine j = run.base("check");
        int64_t calls = 0, bad = 0;
        if constexpr (kNative<Engine>)
        {
            NativeCheck nc;
            Replay(run.loaded, *engine, nullptr, &nc);
            bad = nc.mismatches, calls = nc.calls;
            j.Int("duplicates", nc.duplicates).Str("checked_against", "all overlapping fat-box pairs");
        }
        else
        {
            std::vector<CallHash> hashes;
            Replay(run.loaded, *engine, &hashes);
            calls = int64_t(hashes.size());
            if (!run.args.Get("hashes-out").empty())
            {
                SaveHashesOrDie(run.args.Get("hashes-out"), hashes);
            }
            const std::vector<CallHash> reference = LoadHashesOrDie(run.args.Get("compare-hashes"));
            bad = reference.empty() ? 0 : CompareHashes(hashes, reference, run.engine.c_str(), "stock");
            j.Str("checked_against", reference.empty() ? "" : "stock")
                .Int("compared_file", reference.empty() ? 0 : 1);
        }
        std::printf("check %s: %lld calls, %s\n", run.engine.c_str(), static_cast<long long>(calls),
                    bad ? "MISMATCH" : "exact");
        j.Int("calls_hashed", calls).Int("mismatches", bad);
        AppendLine(run.args.Get("json"), j.Text());
        return bad;
    };
    return Contender{{run.engine, {}, {}}, check, [&run, make](Timings& t) {
                         TimedRun(run.loaded, run.args.Get("json"), run.base("run"), t, make,
                                  [](auto&&...) {});
                     }};
}

/// Contend over PeerEngine<Index> in native mode or Box2D's protocol; `a` are the engine's arguments.
template <typename Index, typename... A>
Contender ContendIndex(const PeerRun& run, bool native, const A&... a)
{
    return native ? Contend<PeerEngine<Index, true>>(run, a...)
                  : Contend<PeerEngine<Index, false>>(run, a...);
}

} // namespace

Contender PeerContender(const PeerRun& run)
{
    const std::string& e = run.engine;
    const LoadedTrace& loaded = run.loaded;
    const Geometry g = Measure(loaded);
    const bool native = e.find("-native") != std::string::npos;
    const size_t x = e.find("-x"), m = e.find("-m");
    // Unused in a build without Chipmunk2D (the peers below are compiled only with it).
    [[maybe_unused]] const double cellScale = x == std::string::npos ? 1.0 : std::atof(e.c_str() + x + 2);
    // Box2D's protocol keeps Box2D's fat boxes whatever the name says.
    const float multiplier = native && m != std::string::npos ? float(std::atof(e.c_str() + m + 2))
                                                              : quadphase::FatPolicy{}.multiplier;
    const std::string base = e.substr(0, std::min({e.find("-native"), x, m}));
    if (base == "null")
    {
        Contender c = Contend<NullEngine>(run);
        c.check = nullptr;
        return c;
    }
    if (base == "stock")
    {
        return Contend<StockEngine>(run);
    }
    if (base == "brute")
    {
        RefuseLargeBrute(run.args, loaded);
        using E = CoreEngine<quadphase::BruteForceBroadPhase>;
        return Contend<E>(run);
    }
    if (base == "paper")
    {
        const std::string l = run.args.Get("levels", "auto");
        // auto: leaves about twice the mean fat box side (the paper's tables favour leaves a little larger
        // than the objects).
        const double side = std::max(g.bounds.maxX - g.bounds.minX, g.bounds.maxY - g.bounds.minY);
        const int levels =
            l == "auto" ? PaperQuadtreeBroadPhase::LevelsFor(side, 2.0 * g.meanSide) : std::atoi(l.c_str());
        const int threads = int(run.args.GetInt("threads", 1));
        if (levels < PaperQuadtreeBroadPhase::kMinLevels || levels > PaperQuadtreeBroadPhase::kMaxLevels)
        {
            Die(2, "qp-replay: --levels must be auto or 1..9\n");
        }
        using E = CoreEngine<PaperQuadtreeBroadPhase>;
        Contender c = Contend<E>(run, levels, g.bounds, threads, quadphase::Schedule::Static,
                                 quadphase::bench::PaperPairReport::Buffered);
        c.check = [&run, levels, g, threads] {
            PaperChecked checked(levels, g.bounds, threads);
            Replay(run.loaded, checked);
            std::printf("check paper: %lld exact pairs; missed %lld, duplicates %lld, extra %lld\n",
                        static_cast<long long>(checked.exact), static_cast<long long>(checked.missed),
                        static_cast<long long>(checked.duplicates), static_cast<long long>(checked.extra));
            JsonLine j = run.base("paper_check");
            j.Int("exact_pairs", checked.exact)
                .Int("missed", checked.missed)
                .Int("duplicates", checked.duplicates)
                .Int("extra", checked.extra)
                .Int("levels", levels);
            AppendLine(run.args.Get("json"), j.Text());
            return int64_t(0); // approximate by design: its misses are counted, not failed
        };
        return c;
    }
    if (base == "oracle")
    {
        // Untimed: an exact index's pairs, query by query, in the order the oracle's own move buffer asks.
        auto prep = std::make_unique<PeerEngine<QuadIndex, false>>(multiplier);
        std::vector<int32_t> perQuery;
        PairList pairs;
        prep->perQuery = &perQuery;
        prep->allPairs = &pairs;
        Replay(loaded, *prep);
        prep.reset();
        using E = PeerEngine<OracleIndex, false>;
        return Contend<E>(run, multiplier, pairs, perQuery);
    }
#if QP_HAVE_CHIPMUNK
    if (base == "cp-hash" || base == "cp-tree")
    {
        const bool hash = base == "cp-hash";
        const double cell = cellScale * g.meanSide;
        const int cells = int(std::max<int64_t>(1000, 10 * loaded.steps.proxies));
        return ContendIndex<ChipmunkIndex>(run, native, multiplier, hash, cell, cells);
    }
#endif
#if QP_HAVE_BULLET
    if (base == "bt-dbvt" || base == "bt-sap")
    {
        const bool sap = base == "bt-sap";
        // The SAP's world: the trace's bounds and a margin for the fat boxes (a box beyond it is clamped:
        // more candidates, never fewer).
        const float pad =
            0.1f * std::max(g.bounds.maxX - g.bounds.minX, g.bounds.maxY - g.bounds.minY) + 1.0f;
        const Box world{g.bounds.minX - pad, g.bounds.minY - pad, g.bounds.maxX + pad, g.bounds.maxY + pad};
        const int maxProxies = loaded.idBound;
        if (sap && !native)
        {
            Die(2, "qp-replay: bt-sap runs in native mode only (its aabbTest is a linear scan)\n");
        }
        return ContendIndex<BulletIndex>(run, native, multiplier, native, sap, world, maxProxies);
    }
#endif
    Die(2, "qp-replay: engine '%s' is unknown or not built here (Chipmunk %s, Bullet %s)\n", e.c_str(),
        QP_HAVE_CHIPMUNK ? "found" : "not found", QP_HAVE_BULLET ? "found" : "not found");
}

} // namespace qpbench
