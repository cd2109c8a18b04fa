#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""quadphase's side-by-side benchmark. Run it through bench/run.sh, which builds the tools.

One machine, one run, one Box2D source and set of flags per optimisation level (--builds O2=DIR,O3=DIR):
  step     in-engine: qp-step-stock and qp-step-quadtree (one source, two Box2D builds) step every scene at
           Box2D's defaults (continuous collision on; quadtree at OMP_NUM_THREADS=1 and 2), in a random order per
           round; b2Profile, contacts, pairs, peak memory; medians over rounds;
  phases   the same tools from the first step of rain: the falling, piling and resting phases apart;
  replay   one recorded trace per scene and size through stock b2BroadPhase, quadphase (1 and 2 threads), brute
           force (small traces), the paper's design, the tuned Chipmunk2D and Bullet peers in both modes, the
           oracle floor and the replay loop alone, a triad per round (memory floor); pair sets checked on every
           UpdatePairs call; rain phase traces replayed by phase;
  queries  qp-query-stock and qp-query-quadtree: QueryAABB, short and long rays, a mass SetTransform then
           queries, through b2World; hits checked equal;
  circles  the paper's protocol: the most circles under 20 ms per frame (qp-circles).
--frames runs only the frames section: every in-engine scene from its first step as a game runs it,
stock and quadphase (1 and 2 threads, its defaults, a job system), each also beside a busy thread; per-step
b2Profile broadphase and step p50/p99/max/total and the process's CPU time -> bench/results/frames.{md,csv,png}.
The first level runs every part; further levels run step, phases and the replay's headline engines. Writes
bench/results/{step,phases,replay,replay_phases,peers,queries,circles}.csv, bench.json, the PNG plots and bench/RESULTS.md.
See bench/README.md for what each number means.
"""

import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from qpbench import circles, frames, outputs, phases, queries, replay, report, run, step  # noqa: E402
from qpbench.bench_common import HEADLINE_ENGINES, PARTS  # noqa: E402
from quadphase_tools import machine  # noqa: E402

TOOLS = ("qp-record", "qp-replay", "qp-step-stock", "qp-step-quadtree",
         "qp-query-stock", "qp-query-quadtree", "qp-circles")

# Options whose default depends on the profile: (option, quick, full, help).
PROFILE_OPTIONS = [("rounds", 3, 4, "timed rounds"), ("wait-quiet", 3.0, 20.0, run.WAIT_HELP + " (0: never)"),
                   ("circles-seconds", 10.0, 40.0,
                    "time cap per circles search at automatic depth (fixed depths get 0.4x)")]


def parse_args():
    def more(ap):
        ap.add_argument("--builds", default=None, help="optimisation levels and their build directories, "
                        "LEVEL=DIR,LEVEL=DIR (bench/run.sh --opt sets it); default: --build-dir alone")
        ap.add_argument("--summary", default=os.path.join(HERE, "RESULTS.md"),
                        help="markdown summary (bench/RESULTS.md)")
        ap.add_argument("--parts", default=",".join(PARTS), help="subset of " + ",".join(PARTS))
        ap.add_argument("--replay-engines", default=None, metavar="LIST",
                        help="replay only these engines, e.g. stock,quadtree-1t,quadtree-2t to recheck the headline "
                        "in minutes rather than the hour the peers take (default: every engine built)")
        ap.add_argument("--ccd", default="scene", choices=("scene", "on", "off"),
                        help="continuous collision in step and phases (default: as the scene has it, Box2D's on)")
        ap.add_argument("--scale", type=float, default=1.0,
                        help="multiply every scene size by this (development: 0.1 for a smoke test)")
        ap.add_argument("--frames", action="store_true",
                        help="only the frames section (about 18 min on 2 cores; --full runs it too): results/frames.*")
        ap.add_argument("--frame-steps", type=int, default=600, help="--frames: steps per run from the first (600)")

    a = run.parse_args(__doc__, "full profile (-O2 and -O3: about 90 min on 2 cores)", PROFILE_OPTIONS, more)
    a.profile = "full" if a.full else "quick"
    a.parts = [p for p in PARTS if p in a.parts.split(",")]
    if a.builds:
        a.levels = [tuple(x.split("=", 1)) for x in a.builds.split(",") if x]
    else:
        flags = machine.cmake_cache(a.build_dir).get("CMAKE_CXX_FLAGS_RELEASE", "")
        a.levels = [(next((w[1:] for w in flags.split() if w.startswith("-O")), "O2"), a.build_dir)]
    a.work = a.work or os.path.join(a.levels[0][1], "tmp", "bench")
    return a



def level_runner(args, level, build_dir, append=False):
    return run.Runner("bench.py", os.path.join(build_dir, "bench"), os.path.join(args.work, level), "bench",
                      tools=TOOLS, append=append, traces=os.path.join(args.work, "traces"), seed=args.seed,
                      rerecord=args.rerecord, wait_quiet=args.wait_quiet, quiet_cpus=args.quiet_cpus)


def plan(args, runners, traces, available):
    """(level, runner, part, units), one unit = one tool run per round; queries (each build and thread count of
    step) and circles at the first level only, the replay's headline engines only at the others."""
    plans = []
    for i, (lv, _, runner) in enumerate(runners):
        for part in args.parts:
            if part == "step":
                plans.append((lv, runner, part, step.step_units(runner, args)))
            elif part == "phases":
                plans.append((lv, runner, part, phases.phase_units(args)))
            elif part == "replay":
                plans.append((lv, runner, part, replay.replay_units(
                    traces, available if i == 0 else set(HEADLINE_ENGINES))))
            elif i == 0:
                units = step.STEP_ENGINES if part == "queries" else circles.CIRCLES[args.profile]
                plans.append((lv, runner, part, units))
    return plans


def run_one(runner, args, part, u, rnd):
    if part in ("step", "phases"):
        step.run_step(runner, args, part, u, rnd)
    elif part == "replay":
        replay.run_replay(runner, u, rnd)
    elif part == "queries":
        queries.run_queries(runner, args, u, rnd)


def main():
    args = parse_args()
    os.makedirs(args.results, exist_ok=True)
    if args.frames:
        return frames.run_frames(args)
    if args.report_only:
        info = report.read_json(os.path.join(args.work, "machine.json"))
        info["levels"] = [tuple(x) for x in info["levels"]]
        return outputs.write_outputs(args, info, {lv: level_runner(args, lv, d, True).results()
                                                  for lv, d in info["levels"]},
                                     frames.run_frames(args) if args.full else [])
    t_start = time.time()
    runners = [(lv, d, level_runner(args, lv, d)) for lv, d in args.levels]
    print(f"bench.py: {args.profile} profile, {args.rounds} rounds, levels "
          f"{', '.join(lv for lv, _ in args.levels)}; work directory {args.work}", flush=True)
    info = dict(machine.describe(args.levels[0][1]), profile=args.profile, rounds=args.rounds, scale=args.scale,
                ccd=args.ccd, levels=args.levels, timing={}, parts=args.parts, replay_engines=args.replay_engines)
    info["level_flags"] = {lv: machine.cmake_cache(d).get("CMAKE_CXX_FLAGS_RELEASE", "?") for lv, d in args.levels}
    print(f"machine: {info['cpu']}, {info['cores']} CPUs; Box2D source: {info['box2d']['sha256'][:16]}... "
          f"({info['box2d']['kind']})", flush=True)
    first = runners[0][2]
    info["tools"] = first.run("qp-replay", "--print-config")[1].strip().replace("default_config ", "defaults: ")
    available = replay.available_engines(first)
    info["engines_missing"] = sorted(set(replay.REPLAY_ENGINES) - available)
    if info["engines_missing"]:
        print(f"bench.py: not built here (Chipmunk2D / Bullet not found at configure time): "
              f"{', '.join(info['engines_missing'])}")
    if args.replay_engines:
        wanted = set(args.replay_engines.split(","))
        unknown = wanted - set(replay.REPLAY_ENGINES)
        if unknown:
            sys.exit(f"bench.py: --replay-engines: unknown {', '.join(sorted(unknown))} "
                     f"(known: {', '.join(replay.REPLAY_ENGINES)})")
        info["engines_left_out"] = sorted(available - wanted)
        available &= wanted
    traces = replay.record_traces(first, args) if "replay" in args.parts else []
    info["traces"] = [{k: v for k, v in t.items() if k != "path"} for t in traces]

    plans = plan(args, runners, traces, available)
    bar = run.Progress(sum(len(u) * (1 if p == "circles" else args.rounds + (p == "replay")) for _, _, p, u in plans))
    for seed, (lv, runner, part, units) in enumerate(plans):
        t0 = time.time()
        if part == "replay":
            replay.check_replays(runner, units, bar)
        if part == "circles":
            circles.run_circles(runner, args, units, bar)
        else:
            for rnd in range(args.rounds):
                runner.wait_quiet() if args.wait_quiet > 0 else None
                for u in run.shuffled(units, args.seed + 100 * seed + rnd):
                    run_one(runner, args, part, u, rnd)
                    what = u[1:] if part != "replay" else ((u[0] or {}).get("name"), u[1])
                    bar.step(f"{lv} {part} r{rnd + 1} " + " ".join(str(x) for x in what))
        info["timing"][f"{lv} {part}"] = time.time() - t0
    bar.end()
    info["timing"]["total_s"] = time.time() - t_start
    info["quiet_samples"] = [q for _, _, r in runners for q in r.quiet_samples]
    info["loadavg_end"] = open("/proc/loadavg").read().split()[:3]
    report.write_json(os.path.join(args.work, "machine.json"), info)
    # The full run also reports frames, on the first level's build, and RESULTS.md quotes their goals.
    goals = frames.run_frames(args) if args.full else []
    info["frame_steps"] = args.frame_steps
    outputs.write_outputs(args, info, {lv: r.results() for lv, _, r in runners}, goals)
    print(f"bench.py: done in {time.time() - t_start:.0f} s; wrote {args.summary} and {args.results}/", flush=True)


if __name__ == "__main__":
    main()
