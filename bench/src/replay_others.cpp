// qp-replay-others: replays a trace (qp-record) through the broadphases quadphase is compared with, other
// than stock Box2D (qp-replay-stock) and the quadtree (qp-replay), with the same timing definition
// (replay_common.h).
//
//   qp-replay-others --trace FILE --engine NAME [--repeats R] [--check none|first] [--compare-hashes FILE]
//                    [--threads N] [--levels L|auto] [--max-proxies N] [--json FILE] [--label TEXT]
//
// Engines:
//   brute     quadphase::BruteForceBroadPhase (O(n) per buffered proxy; refused above --max-proxies, default
//   20000) paper     the paper's design (bench/baselines, PaperPairReport::Buffered); --levels (default auto:
//   leaves about
//             twice the mean fat box), --threads (1 = its sequential quadtree). APPROXIMATE: the checking run
//             compares every call with the quadtree core and reports missed, duplicate and extra pairs.
//   cp-hash   Chipmunk2D's cpSpaceHash (cell size = the mean fat box side at creation, 10 cells per proxy)
//   cp-tree   Chipmunk2D's cpBBTree (no velocity function)
//   bt-dbvt   Bullet's btDbvtBroadphase (deferred collide; queried with aabbTest)
//   floor     no broadphase: the time to read the AABBs the trace hands over in each timed step once, from
//   one
//             contiguous array (the memory floor); ns per proxy per step like the others
//
// Chipmunk and Bullet have neither Box2D's fat boxes nor its move buffer. They are used here as spatial
// indexes under Box2D's own protocol, exactly as b2BroadPhase uses its b2DynamicTree: this tool keeps the fat
// boxes (quadphase::FattenNew / Refatten, bit-identical to Box2D's) and the move buffer; a proxy whose fat
// box changed is re-indexed (cpSpatialIndexReindexObject, btDbvtBroadphase::setAabb) with its fat box;
// UpdatePairs queries the index with the fat box of every buffered proxy and keeps, from the callbacks, the
// proxies whose fat boxes overlap it (their own leaf volumes may be larger). The pairs are then, by
// definition, stock's pair set, and the checking run verifies it call by call against qp-replay-stock's
// hashes (--compare-hashes; exit 3 on a mismatch).
//
// Memory: heap bytes held by the engine after the whole trace (heap_bytes.h), per live proxy.
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "heap_bytes.h"
#include "paper_quadtree.h"
#include "quadphase/brute_force_broad_phase.h"
#include "quadphase/fat_policy.h"
#include "quadphase/quadtree_broad_phase.h"
#include "replay_common.h"

#if QP_HAVE_CHIPMUNK
#include <chipmunk/chipmunk.h>
#endif
#if QP_HAVE_BULLET
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#endif

namespace
{

using namespace qpbench;
using quadphase::ProxyId;

// ---------------------------------------------------------------------------------------------------------------
// Engines over quadphase::BroadPhaseInterface (brute force, the paper's design, the quadtree as reference).
// ---------------------------------------------------------------------------------------------------------------
template <typename BP>
class InterfaceEngine
{
public:
    template <typename... A>
    explicit InterfaceEngine(A&&... a) : m_bp(std::forward<A>(a)...)
    {
    }
    int32_t Create(const Box& tight, int32_t recorded)
    {
        return m_bp.CreateProxy(tight, reinterpret_cast<void*>(intptr_t(recorded)));
    }
    void Destroy(int32_t id) { m_bp.DestroyProxy(id); }
    void Move(int32_t id, const Box& tight, Vec2 d) { m_bp.MoveProxy(id, tight, d); }
    void Touch(int32_t id) { m_bp.TouchProxy(id); }
    void UpdatePairs()
    {
        m_pairs.clear();
        m_bp.FindPairs(m_pairs);
    }
    void ShiftOrigin(Vec2 o) { m_bp.ShiftOrigin(o); }
    int32_t ProxyCount() const { return m_bp.GetProxyCount(); }
    size_t PairCount() const { return m_pairs.size(); }
    /// Every reported pair in recorded ids, duplicates kept.
    void PairKeys(std::vector<uint64_t>& keys) const
    {
        for (const quadphase::Pair& p : m_pairs)
        {
            keys.push_back(
                PairKey(int32_t(intptr_t(m_bp.GetUserData(p.a))), int32_t(intptr_t(m_bp.GetUserData(p.b)))));
        }
    }
    void BeginTimedSteps() {}
    BP& Get() { return m_bp; }

private:
    BP m_bp;
    std::vector<quadphase::Pair> m_pairs;
};

/// The paper's design next to the quadtree core (exact, checked against stock by qp-replay): counts, per
/// UpdatePairs call, the pairs the paper's design misses, reports twice, or reports without an overlap.
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
        if (size_t(id) >= m_refId.size())
        {
            m_refId.resize(size_t(id) + 1, -1);
        }
        m_refId[size_t(id)] = m_ref.Create(tight, recorded);
        return id;
    }
    void Destroy(int32_t id)
    {
        m_paper.Destroy(id);
        m_ref.Destroy(m_refId[size_t(id)]);
    }
    void Move(int32_t id, const Box& tight, Vec2 d)
    {
        m_paper.Move(id, tight, d);
        m_ref.Move(m_refId[size_t(id)], tight, d);
    }
    void Touch(int32_t id)
    {
        m_paper.Touch(id);
        m_ref.Touch(m_refId[size_t(id)]);
    }
    void UpdatePairs()
    {
        m_paper.UpdatePairs();
        m_ref.UpdatePairs();
        std::vector<uint64_t> mine, ref;
        m_paper.PairKeys(mine);
        m_ref.PairKeys(ref);
        std::sort(mine.begin(), mine.end());
        const size_t reported = mine.size();
        mine.erase(std::unique(mine.begin(), mine.end()), mine.end());
        std::sort(ref.begin(), ref.end());
        ref.erase(std::unique(ref.begin(), ref.end()), ref.end());
        std::vector<uint64_t> diff;
        std::set_difference(ref.begin(), ref.end(), mine.begin(), mine.end(), std::back_inserter(diff));
        missed += int64_t(diff.size());
        diff.clear();
        std::set_difference(mine.begin(), mine.end(), ref.begin(), ref.end(), std::back_inserter(diff));
        extra += int64_t(diff.size());
        duplicates += int64_t(reported - mine.size());
        exact += int64_t(ref.size());
    }
    void ShiftOrigin(Vec2 o)
    {
        m_paper.ShiftOrigin(o);
        m_ref.ShiftOrigin(o);
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

    InterfaceEngine<quadphase::bench::PaperQuadtreeBroadPhase> m_paper;
    InterfaceEngine<quadphase::QuadtreeBroadPhase> m_ref;
    std::vector<int32_t> m_refId;
};

// ---------------------------------------------------------------------------------------------------------------
// Box2D's protocol (fat boxes, move buffer, query per buffered proxy) over a foreign spatial index.
//   Index: Insert(id, fat), Update(id, fat), Remove(id), Query(fat, fn(int32_t id)), SetBoxes(&vector<Box>)
// ---------------------------------------------------------------------------------------------------------------
template <typename Index>
class ProtocolEngine
{
public:
    template <typename... A>
    explicit ProtocolEngine(A&&... a) : m_index(std::forward<A>(a)...)
    {
        m_index.SetBoxes(&m_fat);
    }
    int32_t Create(const Box& tight, int32_t recorded)
    {
        int32_t id;
        if (!m_free.empty())
        {
            id = m_free.back();
            m_free.pop_back();
        }
        else
        {
            id = int32_t(m_fat.size());
            m_fat.emplace_back();
            m_recorded.push_back(-1);
            m_live.push_back(0);
            m_buffered.push_back(0);
        }
        m_fat[size_t(id)] = quadphase::FattenNew(m_policy, tight);
        m_recorded[size_t(id)] = recorded;
        m_live[size_t(id)] = 1;
        ++m_count;
        m_index.Insert(id, m_fat[size_t(id)]);
        Buffer(id);
        return id;
    }
    void Destroy(int32_t id)
    {
        m_index.Remove(id);
        m_live[size_t(id)] = 0;
        --m_count;
        m_free.push_back(id);
    }
    void Move(int32_t id, const Box& tight, Vec2 d)
    {
        if (quadphase::Refatten(m_policy, m_fat[size_t(id)], tight, d))
        {
            m_index.Update(id, m_fat[size_t(id)]);
            Buffer(id);
        }
    }
    void Touch(int32_t id) { Buffer(id); }
    void UpdatePairs()
    {
        m_pairs.clear();
        for (int32_t q : m_moveBuffer)
        {
            if (!m_live[size_t(q)])
            {
                continue;
            }
            const Box qb = m_fat[size_t(q)];
            m_index.Query(qb,
                          [&](int32_t o)
                          {
                              // Box2D's rule: when both are buffered, only the query of the smaller id
                              // reports the pair.
                              if (o == q || !m_live[size_t(o)] || (m_buffered[size_t(o)] && o < q) ||
                                  !quadphase::Overlaps(m_fat[size_t(o)], qb))
                              {
                                  return;
                              }
                              m_pairs.emplace_back(m_recorded[size_t(q)], m_recorded[size_t(o)]);
                          });
        }
        for (int32_t q : m_moveBuffer)
        {
            m_buffered[size_t(q)] = 0;
        }
        m_moveBuffer.clear();
    }
    void ShiftOrigin(Vec2)
    {
        std::fprintf(stderr, "qp-replay-others: ShiftOrigin is not supported\n"), std::exit(1);
    }
    int32_t ProxyCount() const { return m_count; }
    size_t PairCount() const { return m_pairs.size(); }
    void PairKeys(std::vector<uint64_t>& keys) const
    {
        for (const auto& p : m_pairs)
        {
            keys.push_back(PairKey(p.first, p.second));
        }
    }
    void BeginTimedSteps() {}

private:
    void Buffer(int32_t id)
    {
        if (!m_buffered[size_t(id)])
        {
            m_buffered[size_t(id)] = 1;
            m_moveBuffer.push_back(id);
        }
    }

    quadphase::FatPolicy m_policy;
    std::vector<Box> m_fat;
    std::vector<int32_t> m_recorded;
    std::vector<uint8_t> m_live, m_buffered;
    std::vector<int32_t> m_free, m_moveBuffer;
    std::vector<std::pair<int32_t, int32_t>> m_pairs;
    int32_t m_count = 0;
    Index m_index;
};

#if QP_HAVE_CHIPMUNK
/// Chipmunk's callbacks carry no context for the bounding-box function: the current engine's boxes.
const std::vector<Box>* g_cpBoxes = nullptr;

cpBB ChipmunkBB(void* obj)
{
    const Box& b = (*g_cpBoxes)[size_t(uintptr_t(obj) - 1)];
    return cpBBNew(b.minX, b.minY, b.maxX, b.maxY);
}

cpCollisionID ChipmunkQuery(void*, void* obj2, cpCollisionID id, void* data)
{
    (*static_cast<std::function<void(int32_t)>*>(data))(int32_t(uintptr_t(obj2) - 1));
    return id;
}

class ChipmunkIndex
{
public:
    /// `hash`: cpSpaceHash with cells of `cellSize` and `cells` buckets; else cpBBTree.
    ChipmunkIndex(bool hash, double cellSize, int cells)
        : m_index(hash ? cpSpaceHashNew(cellSize, cells, ChipmunkBB, nullptr)
                       : cpBBTreeNew(ChipmunkBB, nullptr))
    {
    }
    ~ChipmunkIndex() { cpSpatialIndexFree(m_index); }
    ChipmunkIndex(const ChipmunkIndex&) = delete;
    ChipmunkIndex& operator=(const ChipmunkIndex&) = delete;

    void SetBoxes(const std::vector<Box>* boxes) { g_cpBoxes = boxes; }
    void Insert(int32_t id, const Box&) { cpSpatialIndexInsert(m_index, Obj(id), cpHashValue(id)); }
    void Update(int32_t id, const Box&) { cpSpatialIndexReindexObject(m_index, Obj(id), cpHashValue(id)); }
    void Remove(int32_t id) { cpSpatialIndexRemove(m_index, Obj(id), cpHashValue(id)); }
    template <typename Fn>
    void Query(const Box& b, Fn&& fn)
    {
        std::function<void(int32_t)> f(fn);
        cpSpatialIndexQuery(m_index, nullptr, cpBBNew(b.minX, b.minY, b.maxX, b.maxY), ChipmunkQuery, &f);
    }

private:
    static void* Obj(int32_t id) { return reinterpret_cast<void*>(uintptr_t(id) + 1); }
    cpSpatialIndex* m_index;
};
#endif

#if QP_HAVE_BULLET
class BulletIndex
{
public:
    BulletIndex() { m_bp.m_deferedcollide = true; } // no pair cache work in createProxy/setAabb: queries only
    ~BulletIndex()
    {
        for (btBroadphaseProxy* p : m_proxies)
        {
            if (p != nullptr)
            {
                m_bp.destroyProxy(p, nullptr);
            }
        }
    }
    BulletIndex(const BulletIndex&) = delete;
    BulletIndex& operator=(const BulletIndex&) = delete;

    void SetBoxes(const std::vector<Box>*) {}
    void Insert(int32_t id, const Box& b)
    {
        if (size_t(id) >= m_proxies.size())
        {
            m_proxies.resize(size_t(id) + 1, nullptr);
        }
        m_proxies[size_t(id)] =
            m_bp.createProxy(Min(b), Max(b), 0, reinterpret_cast<void*>(intptr_t(id)), 1, -1, nullptr);
    }
    void Update(int32_t id, const Box& b) { m_bp.setAabb(m_proxies[size_t(id)], Min(b), Max(b), nullptr); }
    void Remove(int32_t id)
    {
        m_bp.destroyProxy(m_proxies[size_t(id)], nullptr);
        m_proxies[size_t(id)] = nullptr;
    }
    template <typename Fn>
    void Query(const Box& b, Fn&& fn)
    {
        struct Callback : btBroadphaseAabbCallback
        {
            explicit Callback(Fn& f) : fn(f) {}
            bool process(const btBroadphaseProxy* proxy) override
            {
                fn(int32_t(intptr_t(proxy->m_clientObject)));
                return true;
            }
            Fn& fn;
        } callback(fn);
        m_bp.aabbTest(Min(b), Max(b), callback);
    }

private:
    static btVector3 Min(const Box& b) { return btVector3(b.minX, b.minY, 0.0f); }
    static btVector3 Max(const Box& b) { return btVector3(b.maxX, b.maxY, 0.0f); }
    btDbvtBroadphase m_bp;
    std::vector<btBroadphaseProxy*> m_proxies;
};
#endif

// ---------------------------------------------------------------------------------------------------------------
// Trace geometry: bounds of every box, mean fat box side of the created proxies.
// ---------------------------------------------------------------------------------------------------------------
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
        if (op.kind != TraceOp::Create && op.kind != TraceOp::Move)
        {
            continue;
        }
        const Box& b = op.box;
        if (!(std::isfinite(b.minX) && std::isfinite(b.minY) && std::isfinite(b.maxX) &&
              std::isfinite(b.maxY)))
        {
            continue;
        }
        if (first)
        {
            g.bounds = b;
            first = false;
        }
        g.bounds.minX = std::min(g.bounds.minX, b.minX);
        g.bounds.minY = std::min(g.bounds.minY, b.minY);
        g.bounds.maxX = std::max(g.bounds.maxX, b.maxX);
        g.bounds.maxY = std::max(g.bounds.maxY, b.maxY);
        if (op.kind == TraceOp::Create)
        {
            sideSum += 0.5 * (double(b.maxX - b.minX) + double(b.maxY - b.minY)) + 0.2;
            ++created;
        }
    }
    g.meanSide = created > 0 ? sideSum / double(created) : 1.0;
    return g;
}

/// The paper's level whose leaves are closest to twice the mean fat box side (the paper chose by hand; this
/// is the choice its tables favour: leaves a little larger than the objects).
int AutoLevels(const Geometry& g)
{
    const double side =
        std::max(double(g.bounds.maxX - g.bounds.minX), double(g.bounds.maxY - g.bounds.minY));
    int best = 1;
    for (int levels = 1; levels <= quadphase::bench::PaperQuadtreeBroadPhase::kMaxLevels; ++levels)
    {
        const double leaf = side / double(1 << (levels - 1));
        if (leaf >= 2.0 * g.meanSide)
        {
            best = levels;
        }
    }
    return best;
}

/// The floor: per timed step, the boxes the step's Create/Move ops hand over, copied into one contiguous
/// array, read once (summed), timed; ns per live proxy at the start of the step.
void RunFloor(const LoadedTrace& loaded, int repeats, const std::string& jsonPath,
              const std::function<void(JsonLine&, const char*)>& baseJson)
{
    const std::vector<TraceOp>& ops = loaded.trace.Ops();
    const StepIndex& index = loaded.steps;
    std::vector<std::vector<Box>> perStep(size_t(index.steps));
    std::vector<int64_t> liveAtStart(size_t(index.steps), 0);
    int64_t live = 0;
    for (size_t i = 0; i < ops.size(); ++i)
    {
        for (int s = 0; s < index.steps; ++s)
        {
            if (i == size_t(index.boundary[size_t(index.warmup + s)]))
            {
                liveAtStart[size_t(s)] = live;
            }
        }
        live += ops[i].kind == TraceOp::Create ? 1 : (ops[i].kind == TraceOp::Destroy ? -1 : 0);
    }
    for (int s = 0; s < index.steps; ++s)
    {
        for (size_t i = size_t(index.boundary[size_t(index.warmup + s)]);
             i < size_t(index.boundary[size_t(index.warmup + s + 1)]); ++i)
        {
            if (ops[i].kind == TraceOp::Create || ops[i].kind == TraceOp::Move)
            {
                perStep[size_t(s)].push_back(ops[i].box);
            }
        }
    }
    volatile float sink = 0.0f;
    for (int r = 0; r < repeats; ++r)
    {
        std::vector<int64_t> ns;
        double total = 0.0, proxies = 0.0;
        for (int s = 0; s < index.steps; ++s)
        {
            const std::vector<Box>& boxes = perStep[size_t(s)];
            const int64_t t0 = NowNs();
            float acc = 0.0f;
            for (const Box& b : boxes)
            {
                acc += b.minX + b.minY + b.maxX + b.maxY;
            }
            sink = sink + acc;
            ns.push_back(NowNs() - t0);
            total += double(ns.back());
            proxies += double(liveAtStart[size_t(s)]);
        }
        JsonLine j;
        baseJson(j, "run");
        j.Int("rep", r)
            .Int("steps", index.steps)
            .Num("mean_proxies", proxies / index.steps)
            .Num("step_ns", total / index.steps)
            .Num("ns_per_proxy_step", proxies > 0 ? total / proxies : 0.0)
            .Array("steps_ns", ns);
        AppendLine(jsonPath, j.Text());
        std::printf("floor rep %d: %.4f ms/step, %.2f ns/proxy/step\n", r, total / index.steps * 1e-6,
                    proxies > 0 ? total / proxies : 0.0);
    }
}

template <typename Engine, typename Make>
int RunEngine(const LoadedTrace& loaded, const char* name, Make make, int repeats, const std::string& check,
              const std::vector<CallHash>& reference, const std::string& jsonPath,
              const std::function<void(JsonLine&, const char*)>& baseJson)
{
    int64_t mismatches = 0;
    if (check != "none")
    {
        std::unique_ptr<Engine> engine = make();
        std::vector<CallHash> hashes;
        Replay(loaded, *engine, &hashes);
        int64_t bad = 0;
        if (!reference.empty())
        {
            bad = CompareHashes(hashes, reference, name, "stock");
        }
        mismatches += bad;
        std::printf("check %s: %zu calls hashed, %s\n", name, hashes.size(),
                    reference.empty() ? "not compared" : (bad ? "MISMATCH" : "identical to stock"));
        JsonLine j;
        baseJson(j, "check");
        j.Int("calls_hashed", int64_t(hashes.size()))
            .Int("mismatches", bad)
            .Int("compared_file", reference.empty() ? 0 : 1);
        AppendLine(jsonPath, j.Text());
    }
    TimedRuns(loaded, name, repeats, jsonPath, make, baseJson, [](JsonLine&, const Engine&) {});
    return mismatches != 0 ? 3 : 0;
}

} // namespace

int main(int argc, char** argv)
{
    const Args args(argc, argv, {"help"});
    const std::vector<std::string> problems =
        args.Problems({"trace", "steps-file", "engine", "repeats", "check", "compare-hashes", "threads",
                       "levels", "max-proxies", "json", "label", "help"});
    if (args.Has("help") || !problems.empty() || !args.Has("trace") || !args.Has("engine"))
    {
        for (const std::string& p : problems)
        {
            std::fprintf(stderr, "qp-replay-others: %s\n", p.c_str());
        }
        std::fprintf(
            stderr,
            "usage: qp-replay-others --trace FILE --engine brute|paper|cp-hash|cp-tree|bt-dbvt|floor\n"
            "                        [--repeats R] [--check none|first] [--compare-hashes FILE]\n"
            "                        [--threads N] [--levels L|auto] [--max-proxies N] [--json FILE] "
            "[--label T]\n"
            "available here:%s%s\n",
            QP_HAVE_CHIPMUNK ? " cp-hash cp-tree" : "", QP_HAVE_BULLET ? " bt-dbvt" : "");
        return args.Has("help") ? 0 : 2;
    }
    PrintMachine(stdout);
    LoadedTrace loaded;
    LoadOrDie(args.Get("trace"), args.Get("steps-file"), loaded);
    const StepIndex& index = loaded.steps;
    const std::string engine = args.Get("engine");
    const std::string jsonPath = args.Get("json");
    const std::string label = args.Get("label");
    const std::string check = args.Get("check", "first");
    const int repeats = int(args.GetInt("repeats", 5));
    const int threads = int(args.GetInt("threads", 1));
    std::printf("trace %s: scene %s size %d, %zu ops, %d warm-up + %d timed steps\n", loaded.path.c_str(),
                index.scene.c_str(), index.size, loaded.trace.Ops().size(), index.warmup, index.steps);

    std::vector<CallHash> reference;
    if (args.Has("compare-hashes") && !LoadHashes(args.Get("compare-hashes"), reference))
    {
        std::fprintf(stderr, "qp-replay-others: cannot read hashes from %s\n",
                     args.Get("compare-hashes").c_str());
        return 1;
    }
    const Geometry geometry = Measure(loaded);
    int levels = 0;
    if (engine == "paper")
    {
        const std::string l = args.Get("levels", "auto");
        levels = l == "auto" ? AutoLevels(geometry) : std::atoi(l.c_str());
        if (levels < quadphase::bench::PaperQuadtreeBroadPhase::kMinLevels ||
            levels > quadphase::bench::PaperQuadtreeBroadPhase::kMaxLevels)
        {
            std::fprintf(stderr, "qp-replay-others: --levels must be auto or 1..9\n");
            return 2;
        }
    }
    auto baseJson = [&](JsonLine& j, const char* kind)
    {
        j.Str("tool", "qp-replay-others")
            .Str("kind", kind)
            .Str("label", label)
            .Str("trace", loaded.name)
            .Str("scene", index.scene)
            .Int("size", index.size)
            .Int("warmup", index.warmup)
            .Str("engine", engine)
            .Int("threads", threads)
            .Int("levels", levels);
    };

    if (engine == "floor")
    {
        RunFloor(loaded, repeats, jsonPath, baseJson);
        return 0;
    }
    if (engine == "brute")
    {
        const long maxProxies = args.GetInt("max-proxies", 20000);
        if (index.proxies > maxProxies)
        {
            std::fprintf(stderr,
                         "qp-replay-others: brute force on %lld proxies (> --max-proxies %ld) refused\n",
                         static_cast<long long>(index.proxies), maxProxies);
            return 2;
        }
        using E = InterfaceEngine<quadphase::BruteForceBroadPhase>;
        return RunEngine<E>(
            loaded, "brute", [] { return std::make_unique<E>(); }, repeats, check, reference, jsonPath,
            baseJson);
    }
    if (engine == "paper")
    {
        const Box bounds = geometry.bounds;
        std::printf("paper's design: %d levels (%d x %d leaves) over [%g %g] x [%g %g], %d thread(s)\n",
                    levels, 1 << (levels - 1), 1 << (levels - 1), double(bounds.minX), double(bounds.maxX),
                    double(bounds.minY), double(bounds.maxY), threads);
        if (check != "none")
        {
            // Not exact by design: count what it misses against the quadtree core (itself checked against
            // stock).
            PaperChecked checked(levels, bounds, threads);
            Replay(loaded, checked);
            std::printf("check paper: %lld exact pairs over all UpdatePairs calls; missed %lld (%.3f%%), "
                        "duplicates %lld, "
                        "extra %lld\n",
                        static_cast<long long>(checked.exact), static_cast<long long>(checked.missed),
                        100.0 * double(checked.missed) / double(std::max<int64_t>(1, checked.exact)),
                        static_cast<long long>(checked.duplicates), static_cast<long long>(checked.extra));
            JsonLine j;
            baseJson(j, "paper_check");
            j.Int("exact_pairs", checked.exact)
                .Int("missed", checked.missed)
                .Int("duplicates", checked.duplicates)
                .Int("extra", checked.extra);
            AppendLine(jsonPath, j.Text());
        }
        using E = InterfaceEngine<quadphase::bench::PaperQuadtreeBroadPhase>;
        return RunEngine<E>(
            loaded, "paper",
            [&]
            {
                return std::make_unique<E>(levels, bounds, threads, quadphase::Schedule::Static,
                                           quadphase::bench::PaperPairReport::Buffered);
            },
            repeats, "none", reference, jsonPath, baseJson);
    }
#if QP_HAVE_CHIPMUNK
    if (engine == "cp-hash" || engine == "cp-tree")
    {
        const bool hash = engine == "cp-hash";
        const int cells = int(std::max<int64_t>(1000, 10 * index.proxies));
        if (hash)
        {
            std::printf("cpSpaceHash: cell %.3g, %d cells\n", geometry.meanSide, cells);
        }
        using E = ProtocolEngine<ChipmunkIndex>;
        return RunEngine<E>(
            loaded, engine.c_str(), [&] { return std::make_unique<E>(hash, geometry.meanSide, cells); },
            repeats, check, reference, jsonPath, baseJson);
    }
#endif
#if QP_HAVE_BULLET
    if (engine == "bt-dbvt")
    {
        using E = ProtocolEngine<BulletIndex>;
        return RunEngine<E>(
            loaded, "bt-dbvt", [] { return std::make_unique<E>(); }, repeats, check, reference, jsonPath,
            baseJson);
    }
#endif
    std::fprintf(
        stderr, "qp-replay-others: engine '%s' is unknown or not built here (Chipmunk %s, Bullet %s)\n",
        engine.c_str(), QP_HAVE_CHIPMUNK ? "found" : "not found", QP_HAVE_BULLET ? "found" : "not found");
    return 2;
}
