// SPDX-License-Identifier: MIT
// qp-moves-stock / qp-moves-quadtree: the caller-thread cost of b2BroadPhase::MoveProxy, one source and two builds
// (Box2D 2.4.1's dynamic tree in qp-moves-stock, the quadtree in qp-moves-quadtree). Box2D calls MoveProxy for
// every fixture of every awake body, one at a time on the game's thread, so its cost per call is serial whatever
// the thread count.
//
//   qp-moves-<variant> --trace FILE [--repeats R]
//
// Replays a recorded trace (qp-record) through b2BroadPhase itself: the creation and warm-up untimed, then the
// timed steps, where every run of consecutive MoveProxy calls (Box2D's b2Body::SynchronizeFixtures over the awake
// bodies) gets one clock-read pair; UpdatePairs calls are timed apart. Each box is written as Box2D writes it just
// before the call (WriteAsBox2D). Prints, per repeat (a fresh broadphase
// each) and as the median over the repeats: ns per MoveProxy (the replay loop's dispatch included, the same for
// both builds), the dispatch alone (the same runs of the same calls, timed the same way, into an empty function
// that is not inlined), MoveProxy net of it, and UpdatePairs ms per step. Under callgrind, count MoveProxy alone with
//   valgrind --tool=callgrind --toggle-collect='b2BroadPhase::MoveProxy*' qp-moves-<variant> --trace FILE
// and divide the total by the calls callgrind_annotate --inclusive=yes lists for it.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "box2d_variant.h"
#include "box_to_aabb.h"
#include "loaded_trace.h"
#include "tool_common.h"

namespace
{

using qpbench::NowNs;
using qpbench::ToAabb;
using quadphase::TraceOp;

struct Counter
{
    int64_t pairs = 0;
    void AddPair(void*, void*) { ++pairs; }
};

struct RepeatResult
{
    int64_t moveNs = 0;
    int64_t dispatchNs = 0;
    int64_t moves = 0;
    int64_t updateNs = 0;
    int64_t pairs = 0;
};

// MoveProxy's signature, doing nothing, and kept out of line and opaque so that the compiler keeps the calls and
// their arguments: the replay loop's dispatch, measured alone.
__attribute__((noinline)) void EmptyMove(b2BroadPhase* bp, int32 proxyId, const b2AABB& aabb,
                                         const b2Vec2& displacement)
{
    __asm__ volatile("" : : "r"(bp), "r"(proxyId), "r"(&aabb), "r"(&displacement) : "memory");
}

// Writes a move's box as Box2D's b2Fixture::Synchronize writes b2FixtureProxy::aabb just before it calls MoveProxy
// (b2AABB::Combine: lowerBound, then upperBound, 8 bytes each), so that MoveProxy's reads of the fresh box cost what
// they cost in a b2World step: a 16-byte load of two 8-byte stores still in the store buffer waits for them to reach
// the cache (8 ns a call here). The barrier keeps the compiler from merging the two stores into one.
inline void WriteAsBox2D(b2AABB& aabb, const quadphase::Box& box)
{
    aabb.lowerBound = b2Vec2(box.minX, box.minY);
    __asm__ volatile("" : : "r"(&aabb) : "memory");
    aabb.upperBound = b2Vec2(box.maxX, box.maxY);
}

// The quadtree with the library's default Config (UpdatePairs parallel from Config::parallelMinProxies proxies).
RepeatResult ReplayOnce(const qpbench::LoadedTrace& loaded)
{
    b2BroadPhase bp;
    const std::vector<TraceOp>& ops = loaded.trace.Ops();
    std::vector<int32> map(size_t(loaded.idBound), -1);
    const size_t firstTimed = size_t(loaded.steps.boundary[size_t(loaded.steps.warmup)]);
    RepeatResult result;
    Counter counter;
    b2AABB aabb; // the moving proxy's box, as b2FixtureProxy::aabb
    size_t i = 0;
    while (i < ops.size())
    {
        const bool timed = i >= firstTimed;
        const TraceOp& op = ops[i];
        if (op.kind == TraceOp::Move)
        {
            // One run of consecutive moves, timed as a whole.
            const int64_t t0 = NowNs();
            size_t j = i;
            for (; j < ops.size() && ops[j].kind == TraceOp::Move; ++j)
            {
                const TraceOp& m = ops[j];
                WriteAsBox2D(aabb, m.box);
                bp.MoveProxy(map[size_t(m.id)], aabb, b2Vec2(m.displacement.x, m.displacement.y));
            }
            const int64_t t1 = NowNs();
            if (timed)
            {
                // The loop's own cost: the same calls, read and converted the same way, into EmptyMove.
                const int64_t e0 = NowNs();
                for (size_t k = i; k < j; ++k)
                {
                    const TraceOp& m = ops[k];
                    WriteAsBox2D(aabb, m.box);
                    EmptyMove(&bp, map[size_t(m.id)], aabb, b2Vec2(m.displacement.x, m.displacement.y));
                }
                result.dispatchNs += NowNs() - e0;
                result.moveNs += t1 - t0;
                result.moves += int64_t(j - i);
            }
            i = j;
            continue;
        }
        switch (op.kind)
        {
        case TraceOp::Create:
            map[size_t(op.id)] = bp.CreateProxy(ToAabb(op.box), reinterpret_cast<void*>(intptr_t(op.id)));
            break;
        case TraceOp::Destroy:
            bp.DestroyProxy(map[size_t(op.id)]);
            map[size_t(op.id)] = -1;
            break;
        case TraceOp::Touch:
            bp.TouchProxy(map[size_t(op.id)]);
            break;
        case TraceOp::ShiftOrigin:
            bp.ShiftOrigin(b2Vec2(op.displacement.x, op.displacement.y));
            break;
        case TraceOp::UpdatePairs:
        {
            const int64_t t0 = NowNs();
            bp.UpdatePairs(&counter);
            if (timed)
            {
                result.updateNs += NowNs() - t0;
            }
            break;
        }
        case TraceOp::Move:
            break; // above
        }
        ++i;
    }
    result.pairs = counter.pairs;
    return result;
}

double Median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace

int main(int argc, char** argv)
{
    const std::string tool = "qp-moves-" + std::string(kVariant);
    const qpbench::Args args(argc, argv, tool, {"trace", "repeats"});
    args.Check(args.Has("trace"), "usage: %s --trace FILE [--repeats R]\n", tool.c_str());
    const int repeats = int(args.GetIntIn("repeats", 5, 1, 1000));
    qpbench::LoadedTrace loaded;
    qpbench::LoadOrDie(args.Get("trace"), loaded);
    const double steps = double(loaded.steps.steps);

    std::printf("%s (%s build of b2BroadPhase): %s, %d timed steps, %d repeats\n", tool.c_str(), kVariant,
                loaded.name.c_str(), loaded.steps.steps, repeats);
    std::printf("%8s %12s %14s %12s %12s %18s %12s\n", "repeat", "moves/step", "ns/MoveProxy", "dispatch_ns",
                "net_ns", "UpdatePairs_ms/step", "pairs");
    std::vector<double> perMove, perDispatch, perNet, perStep;
    for (int r = 0; r < repeats; ++r)
    {
        const RepeatResult run = ReplayOnce(loaded);
        const double calls = run.moves > 0 ? double(run.moves) : 1.0;
        perMove.push_back(double(run.moveNs) / calls);
        perDispatch.push_back(double(run.dispatchNs) / calls);
        perNet.push_back(perMove.back() - perDispatch.back());
        perStep.push_back(double(run.updateNs) * 1e-6 / steps);
        std::printf("%8d %12.0f %14.2f %12.2f %12.2f %18.4f %12lld\n", r, double(run.moves) / steps, perMove.back(),
                    perDispatch.back(), perNet.back(), perStep.back(), static_cast<long long>(run.pairs));
    }
    std::printf("%8s %12s %14.2f %12.2f %12.2f %18.4f\n", "median", "", Median(perMove), Median(perDispatch),
                Median(perNet), Median(perStep));
    return 0;
}
