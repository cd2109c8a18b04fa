// SPDX-License-Identifier: MIT
// qp-record: builds a scene, steps it, and records every broadphase call of its world (quadphase::SetTrace) into a
// trace file, plus a ".steps" side file holding the op index of every world-step boundary (step_index.h).
//
//   qp-record --scene particles --size 50000 [--seed 1] [--warmup 60] [--steps 30] --out DIR/particles-50000.qptrace
//
// Also writes FILE.phases: the phase (phase.h) after every step, so that a replay can be split by phase.
//
// What the trace holds. A replay must start from the recorded world's broadphase state, bit for bit (fat boxes,
// which proxies are buffered), or its MoveProxy decisions and pair sets would differ. Fat boxes after a few steps
// cannot be recreated by CreateProxy calls, so the trace starts at the scene's creation:
//   1. one Create op per proxy the scene builder made (written here from the world's proxies, in id order, since
//      SetTrace can only be switched on once the world exists; checked bit for bit against the quadtree's fat
//      boxes, and the world has not run UpdatePairs yet, so every proxy is buffered as in a fresh Create);
//   2. the W warm-up steps, recorded (the replay runs them untimed);
//   3. the S steps the replay times.
// The world is built with the quadphase build of Box2D; the calls it makes do not depend on the broadphase beyond
// the order of new contacts (equally valid simulation).
#include <cinttypes>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

#include "box2d/box2d.h"
#include "box2d_internal.h"
#include "fat_policy.h"
#include "phase.h"
#include "quadphase/box2d.h"
#include "quadphase_scenes/scenes.h"
#include "step_index.h"
#include "tool_common.h"

int main(int argc, char** argv)
{
    using namespace quadphase;
    const qpbench::Args args(argc, argv, "qp-record", {"scene", "size", "seed", "warmup", "steps", "out"});
    args.Check(args.Has("scene") && args.Has("out"),
               "usage: qp-record --scene NAME --size N [--seed S] [--warmup W] [--steps S] --out FILE\n"
               "  scenes: %s\n"
               "  Records scene creation + W warm-up steps + S steps into FILE and FILE.steps.\n",
               quadphase::scenes::SceneNameList().c_str());
    const std::optional<scenes::SceneId> sceneId = scenes::ParseSceneName(args.Get("scene"));
    if (!sceneId)
    {
        qpbench::Die(2, "qp-record: unknown scene '%s' (%s)\n", args.Get("scene").c_str(),
                     scenes::SceneNameList().c_str());
    }
    const scenes::SceneInfo& info = scenes::GetSceneInfo(*sceneId);
    const int size = int(args.GetInt("size", info.defaultSize));
    const uint32_t seed = uint32_t(args.GetInt("seed", 1));
    const int warmup = int(args.GetInt("warmup", 60));
    const int steps = int(args.GetInt("steps", 30));
    const std::string out = args.Get("out");
    if (warmup < 0 || steps <= 0)
    {
        qpbench::Die(2, "qp-record: need --warmup >= 0 and --steps > 0\n");
    }

    qpbench::PrintMachine(stdout);
    const int64_t buildStart = qpbench::NowNs();
    scenes::Scene scene;
    try
    {
        scene = scenes::BuildScene(*sceneId, size, seed);
    }
    catch (const std::exception& e) // a size outside the scene's range
    {
        qpbench::Die(2, "qp-record: %s\n", e.what());
    }
    b2World& world = *scene.world;
    const double buildSeconds = double(qpbench::NowNs() - buildStart) * 1e-9;

    // 1. The creation prefix, from the world's proxies.
    Trace trace;
    const QuadtreeBroadPhase& quadtree = GetQuadtree(world);
    const ProxyPool& pool = quadtree.GetPool();
    if (quadtree.GetStats().updatePairsCalls != 0)
    {
        qpbench::Die(
            1, "qp-record: the scene builder already ran UpdatePairs; cannot write a creation prefix\n");
    }
    const FatPolicy policy{};
    for (ProxyId id = 0; id < pool.IdBound(); ++id)
    {
        if (!pool.IsLive(id))
        {
            continue;
        }
        const b2FixtureProxy* proxy = static_cast<const b2FixtureProxy*>(pool.UserData(id));
        const Box tight{proxy->aabb.lowerBound.x, proxy->aabb.lowerBound.y, proxy->aabb.upperBound.x,
                        proxy->aabb.upperBound.y};
        if (!SameBits(FattenNew(policy, tight), pool.Fat(id)))
        {
            qpbench::Die(1,
                         "qp-record: proxy %d's fat box is not its creation box fattened (the scene builder "
                         "moved it); cannot write an exact creation prefix\n",
                         int(id));
        }
        trace.Add(TraceOp{TraceOp::Create, id, tight, Vec2{0.0f, 0.0f}});
    }

    // 2-3. Warm-up and timed steps, recorded, with the op index of every step boundary.
    qpbench::StepIndex index;
    index.scene = info.name;
    index.size = size;
    index.seed = seed;
    index.warmup = warmup;
    index.steps = steps;
    SetTrace(world, &trace);
    index.boundary.push_back(trace.Ops().size());
    int64_t warmupNs = 0, recordNs = 0;
    qpbench::Phase phase = qpbench::Falling;
    std::string phases =
        "# qp-phases 1: the phase after each step (phase.h), one line per step from step 0\n";
    for (int s = 0; s < warmup + steps; ++s)
    {
        const int64_t t0 = qpbench::NowNs();
        scenes::StepScene(scene);
        (s < warmup ? warmupNs : recordNs) += qpbench::NowNs() - t0;
        index.boundary.push_back(trace.Ops().size());
        phase = qpbench::Classify(world, phase); // untimed
        phases += std::string(qpbench::kPhaseName[phase]) + "\n";
    }
    SetTrace(world, nullptr);
    index.bodies = scenes::CountBodies(world);
    index.proxies = quadtree.GetProxyCount();

    std::string error;
    std::ofstream phaseFile(out + ".phases");
    phaseFile << phases;
    if (!trace.Save(out, error) || !index.Save(out + ".steps", error) || !phaseFile)
    {
        qpbench::Die(1, "qp-record: %s\n", error.c_str());
    }

    // Counts: whole trace, and the S timed steps.
    const std::vector<TraceOp>& ops = trace.Ops();
    const size_t firstTimed = size_t(index.boundary[size_t(warmup)]);
    const int64_t timedOps = int64_t(ops.size() - firstTimed);
    int64_t timedCalls = 0, timedMoves = 0;
    for (size_t i = firstTimed; i < ops.size(); ++i)
    {
        timedCalls += ops[i].kind == TraceOp::UpdatePairs ? 1 : 0;
        timedMoves += ops[i].kind == TraceOp::Move ? 1 : 0;
    }
    std::printf(
        "scene %s size %d seed %u: built in %.2f s; %d warm-up steps in %.2f s, %d recorded steps in %.2f s "
        "(Box2D, quadphase build, trace recording on)\n",
        info.name, size, seed, buildSeconds, warmup, double(warmupNs) * 1e-9, steps, double(recordNs) * 1e-9);
    std::printf("bodies %" PRId64 ", proxies %" PRId64 "\n", index.bodies, index.proxies);
    std::printf("ops %zu (%" PRId64 " in the %d timed steps: %" PRId64
                " MoveProxy), UpdatePairs calls %" PRId64 " (%" PRId64 " in the timed steps)\n",
                ops.size(), timedOps, steps, timedMoves, trace.UpdatePairsCount(), timedCalls);
    std::printf("wrote %s (%.1f MB) and %s.steps\n", out.c_str(),
                double(ops.size() * sizeof(TraceOp)) / (1024.0 * 1024.0), out.c_str());
    return 0;
}
