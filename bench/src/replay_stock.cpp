// qp-replay-stock: replays a trace (qp-record) through Box2D 2.4.1's own b2BroadPhase (stock build), with the same
// timing definition as qp-replay (replay_common.h). The reference line, and the reference pair sets.
//
//   qp-replay-stock --trace FILE [--repeats R] [--check none|first] [--hashes-out FILE] [--json FILE] [--label T]
//
// User data is (void*)(intptr_t)recordedId, so UpdatePairs reports pairs in recorded ids. The AddPair callback
// appends them to a vector (what qp-replay's FindPairs does), nothing more.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "box2d/b2_broad_phase.h"
#include "replay_common.h"

namespace
{

using namespace qpbench;

class StockEngine
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
    size_t PairCount() const { return m_pairs.size(); }
    void PairKeys(std::vector<uint64_t>& keys) const
    {
        for (const auto& p : m_pairs)
        {
            keys.push_back(PairKey(p.first, p.second));
        }
    }
    void BeginTimedSteps() {}

    // b2BroadPhase::UpdatePairs callback.
    void AddPair(void* a, void* b) { m_pairs.emplace_back(int32_t(intptr_t(a)), int32_t(intptr_t(b))); }

    const b2BroadPhase& Get() const { return m_bp; }

private:
    static b2AABB ToAabb(const Box& b)
    {
        b2AABB a;
        a.lowerBound.Set(b.minX, b.minY);
        a.upperBound.Set(b.maxX, b.maxY);
        return a;
    }

    b2BroadPhase m_bp;
    std::vector<std::pair<int32_t, int32_t>> m_pairs;
};

} // namespace

int main(int argc, char** argv)
{
    const Args args(argc, argv, {"help"});
    const std::vector<std::string> problems =
        args.Problems({"trace", "steps-file", "repeats", "check", "hashes-out", "json", "label", "help"});
    if (args.Has("help") || !problems.empty() || !args.Has("trace"))
    {
        for (const std::string& p : problems)
        {
            std::fprintf(stderr, "qp-replay-stock: %s\n", p.c_str());
        }
        std::fprintf(stderr, "usage: qp-replay-stock --trace FILE [--steps-file FILE] [--repeats R] [--check none|first]\n"
                             "                       [--hashes-out FILE] [--json FILE] [--label TEXT]\n");
        return args.Has("help") ? 0 : 2;
    }
    PrintMachine(stdout);
    LoadedTrace loaded;
    LoadOrDie(args.Get("trace"), args.Get("steps-file"), loaded);
    const StepIndex& index = loaded.steps;
    std::printf("trace %s: scene %s size %d, %zu ops, %d warm-up + %d timed steps\n", loaded.path.c_str(),
                index.scene.c_str(), index.size, loaded.trace.Ops().size(), index.warmup, index.steps);
    const std::string jsonPath = args.Get("json");
    const std::string label = args.Get("label");
    auto baseJson = [&](JsonLine& j, const char* kind) {
        j.Str("tool", "qp-replay-stock").Str("kind", kind).Str("label", label).Str("trace", loaded.name)
            .Str("scene", index.scene).Int("size", index.size).Int("warmup", index.warmup).Str("engine", "stock");
    };

    if (args.Get("check", "first") != "none")
    {
        StockEngine engine;
        std::vector<CallHash> hashes;
        Replay(loaded, engine, &hashes);
        if (args.Has("hashes-out") && !SaveHashes(args.Get("hashes-out"), hashes))
        {
            std::fprintf(stderr, "qp-replay-stock: cannot write %s\n", args.Get("hashes-out").c_str());
            return 1;
        }
        std::printf("check: %zu UpdatePairs calls hashed%s%s\n", hashes.size(),
                    args.Has("hashes-out") ? " into " : "", args.Get("hashes-out").c_str());
        JsonLine j;
        baseJson(j, "check");
        j.Int("calls_hashed", int64_t(hashes.size()));
        AppendLine(jsonPath, j.Text());
    }

    TimedRuns(loaded, "stock b2BroadPhase", int(args.GetInt("repeats", 5)), jsonPath,
              [] { return std::make_unique<StockEngine>(); }, baseJson,
              [](JsonLine& j, const StockEngine& e) { j.Int("tree_height", e.Get().GetTreeHeight()); });
    return 0;
}
