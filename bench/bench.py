#!/usr/bin/python3
"""quadphase's side-by-side benchmark (issues 4, 16, 19). Run it through bench/run.sh, which builds the tools.

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
--frames runs only the frames section (issue 31): every in-engine scene from its first step as a game runs it,
stock and quadphase (1 and 2 threads, its defaults, a job system), each also beside a busy thread; per-step
b2Profile broadphase and step p50/p99/max/total -> bench/results/frames.{md,csv,png}.
The first level runs every part; further levels run step, phases and the replay's headline engines. Writes
bench/results/{step,phases,replay,replay_phases,peers,queries,circles}.csv, bench.json, the PNG plots and bench/RESULTS.md.
See bench/README.md for what each number means.
"""

import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from qpbench import paper, plot, report, run  # noqa: E402
from qpbench.report import num as fmt, table  # noqa: E402
from quadphase_tools import machine  # noqa: E402
from quadphase_tools.stats import med, ratio  # noqa: E402

PARTS = ("step", "phases", "replay", "queries", "circles")
# Step benchmark sizes per scene (scenes not listed here: their default size, and in the full profile also 4x it).
STEP_SIZES = {
    "quick": {"pyramid": [20], "rain": [4000], "tumbler": [400], "tiles": [4000], "particles": [10000],
              "bullets": [500], "sparse": [4000]},
    "full": {"pyramid": [20, 60], "rain": [4000, 16000, 32000], "tumbler": [400, 800], "tiles": [4000, 20000],
             "particles": [2000, 10000, 20000, 50000], "bullets": [500, 2000], "sparse": [4000, 20000]},
}
STEP_ENGINES = [("stock", 1), ("quadtree", 1), ("quadtree", 2)]  # (build, OMP_NUM_THREADS)
# Phase runs from the first step: (scene, size, steps). Rain 16k's first 200 steps are issue 16's case.
PHASE_RUNS = {"quick": [("rain", 4000, 900), ("rain", 16000, 200)],
              "full": [("rain", 4000, 1500), ("rain", 16000, 200), ("rain", 16000, 1000)]}
PHASES = ("falling", "piling", "resting")
# Replay traces: (scene, size, warm-up steps, timed steps). A trace with warm-up 0 and many steps is a phase trace:
# every step timed, its steps split by phase (qp-record's .phases file); it is replayed by PHASE_ENGINES only.
# The headline traces (particles 50k, 100k, rain 64k) time 30 steps: with 10 (15 ms of quadphase's work per run)
# one stall of this shared VM moved a 2-thread ratio by up to 40% between runs.
REPLAY_TRACES = {
    "quick": [("particles", 2000, 30, 10), ("particles", 10000, 30, 10), ("rain", 16000, 60, 10),
              ("bullets", 500, 60, 10), ("rain", 4000, 0, 900)],
    "full": [("particles", 2000, 60, 20), ("particles", 10000, 60, 20), ("particles", 50000, 30, 30),
             ("particles", 100000, 30, 30), ("rain", 4000, 120, 20), ("rain", 16000, 120, 20),
             ("rain", 65536, 60, 30), ("bullets", 1000, 120, 20), ("sparse", 20000, 60, 20),
             ("tiles", 20000, 60, 200), ("pyramid", 60, 60, 20), ("rain", 4000, 0, 1200), ("rain", 16000, 0, 1000)],
}
CELL_SCALES = ("0.5", "1", "2", "4", "8")  # cpSpaceHash's cell side, x the mean fat box side
# Peers (replay_peers.cpp): Box2D's protocol (pairs of the moved proxies, checked against stock's), and native mode
# (every overlapping pair each step, checked against all overlapping fat-box pairs; -mM: displacement multiplier).
PROTOCOL_PEERS = [f"cp-hash-x{k}" for k in CELL_SCALES] + ["cp-tree", "bt-dbvt"]
NATIVE_PEERS = ["cp-hash-native-x2", "cp-hash-native-x4", "cp-tree-native", "bt-dbvt-native-m0",
                "bt-dbvt-native-m4", "bt-sap-native"]
PEERS = PROTOCOL_PEERS + NATIVE_PEERS
REPLAY_ENGINES = ["stock", "quadtree-1t", "quadtree-2t", "oracle", "paper"] + PEERS + ["brute", "null"]
HEADLINE_ENGINES = ["stock", "quadtree-1t", "quadtree-2t"]  # what further optimisation levels replay
QUADTREES = HEADLINE_ENGINES[1:]  # quadphase at 1 and 2 threads
PHASE_ENGINES = HEADLINE_ENGINES + ["oracle"]
EXACT_ENGINES = ["quadtree-1t", "quadtree-2t", "oracle", "brute"] + PEERS
OPTIONAL = {"cp-": "cp-hash", "bt-": "bt-dbvt"}  # engine prefix -> the word qp-replay --help lists when built
BRUTE_MAX_PROXIES = 5000
SLOW_MAX_PROXIES = 60000  # left out of bigger traces: the paper's design (approximate, 3-6x stock) and Bullet's SAP
SLOW = ("paper", "bt-sap-native")  # (particles 50k: check + 2 replays of bt-sap took over 5 min on a loaded machine)
ENGINE_LABEL = dict({
    "stock": "Box2D b2DynamicTree (stock)", "quadtree-1t": "quadphase, 1 thread", "quadtree-2t": "quadphase, 2 threads",
    "oracle": "oracle floor: known pairs", "paper": "paper's design (approximate)", "cp-tree": "Chipmunk2D cpBBTree",
    "bt-dbvt": "Bullet btDbvtBroadphase", "cp-tree-native": "Chipmunk2D cpBBTree, native",
    "cp-hash-native-x2": "Chipmunk2D cpSpaceHash 2x, native", "cp-hash-native-x4": "Chipmunk2D cpSpaceHash 4x, native",
    "bt-dbvt-native-m0": "Bullet btDbvt, native, no prediction", "bt-dbvt-native-m4": "Bullet btDbvt, native, 4x",
    "bt-sap-native": "Bullet bt32BitAxisSweep3, native", "brute": "brute force O(n^2)", "null": "replay loop alone"},
    **{f"cp-hash-x{k}": f"Chipmunk2D cpSpaceHash, cell {k}x" for k in CELL_SCALES})
# Query workload of issue 19 (qp-query-*): sizes of its reproductions; workloads in report order.
QUERY_ARGS = {"bodies": 50000, "world": 1000, "queries": 2000, "short-rays": 2000, "long-rays": 200,
              "teleport": 37500, "teleport-queries": 2000}
QUERY_WORKLOADS = [("aabb_small", "small QueryAABB (2 m squares)"), ("ray_short_all", "short rays (10 m), all hits"),
                   ("ray_short_closest", "short rays (10 m), closest hit"),
                   ("ray_axis_all", "long rays, axis-aligned, all hits"),
                   ("ray_axis_closest", "long rays, axis-aligned, closest hit"),
                   ("ray_diag_all", "long rays, corner to corner, all hits"),
                   ("ray_diag_closest", "long rays, corner to corner, closest hit"),
                   ("teleport", "SetTransform of {teleported:,} bodies, then {queries:,} small QueryAABBs, together"),
                   ("teleport_step", "the b2World::Step after the teleport")]
QUERY_GOALS = {"ray_diag_all": 2.0, "ray_diag_closest": 2.0, "teleport": 2.0}  # issue 19; every other: >= 1
# Workloads with a floor (qp-query's <workload>_floor: b2World's and the callback's work on the recorded candidates).
QUERY_FLOORS = ("aabb_small", "ray_short_all", "ray_axis_all", "ray_diag_all")
# The paper's protocol configurations: (engine, threads, depth); depth None = automatic.
CIRCLES = {
    "quick": [("pairwise", 1, None), ("paper", 1, None), ("stock", 1, None), ("quadtree", 1, None),
              ("quadtree", 2, None)],
    "full": [("pairwise", 1, None), ("stock", 1, None)] + [(e, t, d) for e in ("paper", "quadtree") for t in (1, 2)
                                                          for d in (4, 5, 6, 7, 8, 9, None)],
}
REFERENCE = {"circles_stock": 52000, "circles_brute": 6200, "replay_stock_particles50k": 490,
             "replay_stock_rain64k": 510, "step_bp_stock_particles10k": 3.3, "step_bp_stock_particles50k": 43.9}
# Frames (--frames, issue 31): (name, build, qp-step options), each also with --busy; small scenes count (item 5).
FRAME_ENGINES = [("stock", "stock", []), ("1 thread", "quadtree", ["--threads", 1]),
                 ("2 threads", "quadtree", ["--threads", 2]), ("defaults", "quadtree", ["--threads", "default"]),
                 ("job system", "quadtree", ["--threads", "default", "--jobs", 2])]
# else the quick step sizes; particles 20,000 is above Config::parallelMinProxies, where the defaults go parallel
FRAME_SIZES = {"pyramid": [10, 20, 50], "terrain": [40, 1000], "mixed": [1000], "particles": [10000, 20000]}
FRAME_PLOTS = [("pyramid", 10), ("tumbler", 400), ("rain", 4000)]
FRAME_STATS = ("p50", "p99", "max", "total")
TICK = {True: " ✓", False: " **✗**"}
TOOLS = ("qp-record", "qp-replay", "qp-step-stock", "qp-step-quadtree",
         "qp-query-stock", "qp-query-quadtree", "qp-circles")
TEXT = report.prose(os.path.join(HERE, "prose", "bench.md"))  # the report's prose


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


def scaled(size, args, lo=1):
    return max(lo, int(round(size * args.scale)))


# ----------------------------------------------------------------------------------------------------------------
# Plans: one unit = one tool run per round
# ----------------------------------------------------------------------------------------------------------------
def step_units(runner, args):
    units = []
    scene_list = runner.run("qp-step-stock", "--list")[1].splitlines()
    for scene, lo, hi, default in (line.split("\t")[0].split() for line in scene_list):
        lo, hi, default = int(lo), int(hi), int(default)
        for size in STEP_SIZES[args.profile].get(scene) or [default] + ([4 * default] if args.full else []):
            units += [("step", scene, min(hi, max(lo, scaled(size, args, lo))), b, t) for b, t in STEP_ENGINES]
    return list(dict.fromkeys(units))


def phase_units(args):
    return [("phases", s, scaled(n, args, 2), b, t, steps) for s, n, steps in PHASE_RUNS[args.profile]
            for b, t in STEP_ENGINES]


def replay_argv(engine, trace, extra):
    if engine.startswith("quadtree"):
        return ["--trace", trace, "--threads", 1 if engine == "quadtree-1t" else 2] + extra
    return (["--trace", trace, "--engine", engine] + extra
            + (["--max-proxies", BRUTE_MAX_PROXIES] if engine == "brute" else []))


def replay_engines(trace, available):
    n = trace["proxies"]
    return [e for e in (PHASE_ENGINES if trace["warmup"] == 0 else REPLAY_ENGINES) if e in available
            and not (e == "brute" and n > BRUTE_MAX_PROXIES) and not (e in SLOW and n > SLOW_MAX_PROXIES)]


def query_argv(args, runner, label):
    q = dict({k: scaled(v, args) for k, v in QUERY_ARGS.items()}, world=QUERY_ARGS["world"])  # the world unscaled
    return [x for k, v in q.items() for x in (f"--{k}", v)] + ["--seed", args.seed, "--repeats", 5, "--threads",
                                                              "default", "--json", runner.jsonl, "--label", label]


# ----------------------------------------------------------------------------------------------------------------
# Main
# ----------------------------------------------------------------------------------------------------------------
def level_runner(args, level, build_dir, append=False):
    return run.Runner("bench.py", os.path.join(build_dir, "bench"), os.path.join(args.work, level), "bench",
                      tools=TOOLS, append=append, traces=os.path.join(args.work, "traces"), seed=args.seed,
                      rerecord=args.rerecord, wait_quiet=args.wait_quiet, quiet_cpus=args.quiet_cpus)


def main():
    args = parse_args()
    os.makedirs(args.results, exist_ok=True)
    if args.frames:
        return frames(args)
    if args.report_only:
        info = report.read_json(os.path.join(args.work, "machine.json"))
        info["levels"] = [tuple(x) for x in info["levels"]]
        return write_outputs(args, info, {lv: level_runner(args, lv, d, True).results() for lv, d in info["levels"]},
                             frames(args) if args.full else [])
    t_start = time.time()
    runners = [(lv, d, level_runner(args, lv, d)) for lv, d in args.levels]
    print(f"bench.py: {args.profile} profile, {args.rounds} rounds, levels "
          f"{', '.join(lv for lv, _ in args.levels)}; work directory {args.work}", flush=True)
    info = dict(machine.describe(args.levels[0][1]), profile=args.profile, rounds=args.rounds, scale=args.scale,
                ccd=args.ccd, levels=args.levels, timing={})
    info["level_flags"] = {lv: machine.cmake_cache(d).get("CMAKE_CXX_FLAGS_RELEASE", "?") for lv, d in args.levels}
    print(f"machine: {info['cpu']}, {info['cores']} CPUs; Box2D source: {info['box2d']['sha256'][:16]}... "
          f"({info['box2d']['kind']})", flush=True)
    first = runners[0][2]
    info["tools"] = first.run("qp-replay", "--print-config")[1].strip().replace("default_config ", "defaults: ")
    usage = first.run("qp-replay", "--help")[1]
    built = {w for l in usage.splitlines() if l.startswith("available here:") for w in l.split(":", 1)[1].split()}
    available = {e for e in REPLAY_ENGINES if not any(e.startswith(p) and w not in built for p, w in OPTIONAL.items())}
    info["engines_missing"] = sorted(set(REPLAY_ENGINES) - available)
    if info["engines_missing"]:
        print(f"bench.py: not built here (Chipmunk2D / Bullet not found at configure time): "
              f"{', '.join(info['engines_missing'])}")

    traces = []
    if "replay" in args.parts:
        for scene, size, w, s in REPLAY_TRACES[args.profile]:
            path = first.record(scene, scaled(size, args, 2), w, s)
            traces.append(dict(scene=scene, size=scaled(size, args, 2), warmup=w, steps=s, path=path,
                               name=os.path.basename(path).split(".")[0], proxies=run.trace_proxies(path),
                               phases=[l.strip() for l in open(path + ".phases") if not l.startswith("#")][w:]))
    info["traces"] = [{k: v for k, v in t.items() if k != "path"} for t in traces]

    # (level, runner, part, units); queries (each build and thread count of step) and circles at the first level only
    plans = []
    for i, (lv, _, runner) in enumerate(runners):
        for part in args.parts:
            if part == "step":
                plans.append((lv, runner, part, step_units(runner, args)))
            elif part == "phases":
                plans.append((lv, runner, part, phase_units(args)))
            elif part == "replay":
                plans.append((lv, runner, part, [(t, e) for t in traces for e in replay_engines(
                    t, available if i == 0 else set(HEADLINE_ENGINES))] + [(None, "triad")]))
            elif i == 0:
                plans.append((lv, runner, part, STEP_ENGINES if part == "queries" else CIRCLES[args.profile]))
    bar = run.Progress(sum(len(u) * (1 if p == "circles" else args.rounds + (p == "replay")) for _, _, p, u in plans))
    for seed, (lv, runner, part, units) in enumerate(plans):
        t0 = time.time()
        if part == "replay":
            check_replays(runner, units, bar)
        if part == "circles":
            run_circles(runner, args, units, bar)
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
    # The full run also reports frames (issue 31), on the first level's build, and RESULTS.md quotes their goals.
    goals = frames(args) if args.full else []
    info["frame_steps"] = args.frame_steps
    write_outputs(args, info, {lv: r.results() for lv, _, r in runners}, goals)
    print(f"bench.py: done in {time.time() - t_start:.0f} s; wrote {args.summary} and {args.results}/", flush=True)


def frames(args):
    """--frames: every frame engine on every scene (also with --busy) for --rounds rounds, then frames.{md,csv,png}."""
    lv, d = args.levels[0]
    runner = run.Runner("bench.py", os.path.join(d, "bench"), os.path.join(args.work, "frames"), "frames",
                        tools=TOOLS[2:4], append=args.report_only, wait_quiet=args.wait_quiet, quiet_cpus=args.quiet_cpus)
    info = report.read_json(runner.jsonl + ".json") if args.report_only else dict(machine.describe(d), t0=time.time())
    units = [] if args.report_only else [
        (s, n, e, busy) for s, lo, hi, dflt in (l.split("\t")[0].split() for l in runner.run(
            "qp-step-stock", "--list")[1].splitlines()) for n in FRAME_SIZES.get(s) or STEP_SIZES["quick"].get(s)
        or [int(dflt)] for e in FRAME_ENGINES for busy in (0, 1)]
    bar = run.Progress(len(units) * args.rounds)
    for rnd in range(args.rounds if units else 0):
        runner.wait_quiet() if args.wait_quiet > 0 else None
        for s, n, (name, build, opts), busy in run.shuffled(units, args.seed + rnd):
            runner.run(f"qp-step-{build}", "--scene", s, "--size", n, "--seed", args.seed, "--warmup", 0, "--steps",
                       args.frame_steps, *opts, *(["--busy"] if busy else []), "--per-step", "--json", runner.jsonl,
                       "--label", f"frames|{name}|round={rnd}", env={"OMP_NUM_THREADS": None})
            bar.step(f"r{rnd + 1} {s} {n} {name}{' busy' if busy else ''}")
    bar.end()
    if units:
        info.update(minutes=(time.time() - info.pop("t0")) / 60, rounds=args.rounds, steps=args.frame_steps,
                    quiet_samples=runner.quiet_samples, loadavg_end=open("/proc/loadavg").read().split()[:3])
        report.write_json(runner.jsonl + ".json", info)
    groups = {}
    for r in runner.results():
        groups.setdefault((r["scene"], r["size"], r["busy"], r["label"].split("|")[1]), []).append(r)
    # Per-step table: medians over rounds. Goals: each engine's best round (bp_*_best), see the prose.
    rows = [dict(scene=s, size=n, busy=b, engine=e, rounds=len(rs), proxies=rs[0]["proxies"], **{
        f"{m}_{st}": med([r[f"{f}_ms_{st}"] for r in rs]) for m, f in (("bp", "broadphase"), ("step", "step"))
        for st in FRAME_STATS}, **{f"bp_{st}_best": min(r[f"broadphase_ms_{st}"] for r in rs) for st in ("max", "total")})
        for (s, n, b, e), rs in sorted(groups.items())]
    report.write_csv(os.path.join(args.results, "frames.csv"), rows)
    by = {(r["scene"], r["size"], r["busy"], r["engine"]): r for r in rows}
    head, misses = [], set()
    for s, n, b in sorted({k[:3] for k in by}):
        a, one = (by.get((s, n, b, e)) or {} for e in ("stock", "1 thread"))
        cells = [f"{s} {n}", "yes" if b else "no", fmt(a.get("proxies"), 0)]
        for e in ("defaults", "job system"):
            q = by.get((s, n, b, e)) or {}
            total = [ratio(x.get("bp_total_best"), q.get("bp_total_best")) for x in (a, one)]
            ok = [(total[0] or 0) >= 1.0, (total[1] or 0) >= 0.95,
                  q.get("bp_max_best", 1e9) <= 1.5 * a.get("bp_max_best", 0) + 0.5]
            misses.update(f"{s} {n}{' busy' if b else ''} ({e})" for o in ok if not o)
            cells += [f"{fmt(total[0])}{TICK[ok[0]]}", f"{fmt(total[1])}{TICK[ok[1]]}",
                      f"{fmt(q.get('bp_max_best'), 3)} / {fmt(a.get('bp_max_best'), 3)}{TICK[ok[2]]}"]
        head.append(cells)
    L = ["# Frames: per-step broadphase and step, as a game runs the library (issue 31)", "",
         TEXT["frames"].format(steps=info.get("steps"), rounds=info.get("rounds"), minutes=info.get("minutes", 0)), ""]
    if frames_plot(args, groups):
        L += ["![ms per step over the run, stock against quadphase's defaults](frames.png)", ""]
    goals = ["## Goals", ""] + table(
        ["scene", "busy", "proxies at the end", "bp total stock ÷ defaults (≥1)", "1 thread ÷ defaults (≥0.95)",
         "worst bp step ms: defaults / stock (≤1.5×+0.5)", "stock ÷ job system", "1 thread ÷ job system",
         "worst: job system / stock"], head) + ["", "Misses: " + (", ".join(sorted(misses)) or "none") + "."]
    L += goals + ["", "## Per step, ms", ""]
    L += table(["scene", "busy", "engine"] + [f"{m} {st}" for m in ("bp", "step") for st in FRAME_STATS], [
        [f"{r['scene']} {r['size']}", "yes" if r["busy"] else "no", r["engine"]]
        + [fmt(r[f"{m}_{st}"], 3) for m in ("bp", "step") for st in FRAME_STATS] for r in rows])
    report.write_lines(os.path.join(args.results, "frames.md"), L + [""] + report.machine_section(info))
    print(f"bench.py: wrote {args.results}/frames.md, frames.csv", flush=True)
    return goals


def frames_plot(args, groups):
    """ms per step over the run (round 0), stock against the defaults, not busy: whole step and broadphase."""
    plt = plot.pyplot("bench.py")
    cases = [c for c in FRAME_PLOTS if (c[0], c[1], 0, "stock") in groups]
    if plt is None or not cases:
        return None
    fig, axes = plt.subplots(2, len(cases), figsize=(5 * len(cases), 6), squeeze=False)
    for col, (s, n) in enumerate(cases):
        for row, (key, what) in enumerate((("steps_step_ms", "whole step"), ("steps_bp_ms", "broadphase"))):
            for e in ("stock", "defaults"):
                r = min(groups.get((s, n, 0, e), []), key=lambda r: r.get("rep_round", 0), default=None)
                if r:
                    axes[row][col].plot(r[key], label=f"{'quadphase, ' if e != 'stock' else ''}{e}", lw=0.8)
            axes[row][col].set(title=f"{s} {n}: {what}", xlabel="step", ylabel="ms")
            axes[row][col].legend()
    return plot.save(plt, fig, os.path.join(args.results, "frames.png"), 90)


def run_one(runner, args, part, u, rnd):
    if part in ("step", "phases"):
        _, scene, size, build, omp = u[:5]
        warmup, steps = (0, u[5]) if part == "phases" else ((40, 40) if args.full else (20, 20))
        runner.run(f"qp-step-{build}", "--scene", scene, "--size", size, "--seed", args.seed, "--warmup", warmup,
                   "--steps", steps, "--threads", "default", "--ccd", args.ccd, "--json", runner.jsonl,
                   "--label", f"{part} r{rnd}", *(["--per-step"] if part == "phases" else []),
                   env={"OMP_NUM_THREADS": str(omp)})
    elif part == "replay":
        t, e = u
        extra = ["--repeats", 1, "--json", runner.jsonl, "--label", f"replay r{rnd}"]
        runner.run("qp-replay", *(["--triad"] + extra if e == "triad" else replay_argv(e, t["path"], extra + [
            "--check", "none"])))
    elif part == "queries":
        build, omp = u
        runner.run(f"qp-query-{build}", *query_argv(args, runner, f"queries|round={rnd}"),
                   env={"OMP_NUM_THREADS": str(omp)})


def check_replays(runner, units, bar):
    """Untimed: stock's pair-set hashes of every trace, and every exact engine's compared with them."""
    for t, e in sorted(units, key=lambda u: u[1] != "stock"):  # stock's hashes first
        if e not in ("triad", "null"):
            hashes = t["path"] + ".stock.hash"
            extra = ["--repeats", 0, "--check", "first", "--json", runner.jsonl, "--label", "check"]
            extra += ["--hashes-out", hashes] if e == "stock" else ["--compare-hashes", hashes]
            if runner.run("qp-replay", *replay_argv(e, t["path"], extra), ok_codes=(0, 3))[0] == 3:
                print(f"\nbench.py: MISMATCH: {e} on {t['name']} (see {runner.log.name})", flush=True)
        bar.step(f"check {(t or {}).get('name')} {e}")


def run_circles(runner, args, configs, bar):
    """One search per configuration, in random order."""
    for engine, threads, depth in run.shuffled(configs, args.seed + 2):
        runner.wait_quiet(min(args.wait_quiet, 5.0)) if args.wait_quiet > 0 else None
        cap = args.circles_seconds if depth is None or engine in ("pairwise", "stock") else args.circles_seconds * 0.4
        # Quick: fewer frames per repeat (still 3 repeats, the paper's rule). Broadphases start at 4,000 circles.
        frames = ["--frames", 10, "--warmup", 20] if args.full else ["--frames", 5, "--warmup", 10]
        runner.run("qp-circles", "--engine", engine, "--threads", threads, "--depth",
                   "auto" if depth is None else depth, "--max-seconds", cap, *frames,
                   "--start", 1000 if engine == "pairwise" else 4000,
                   "--precision", 0.05 if args.full else 0.1, "--json", runner.jsonl, "--label", "circles")
        bar.step(f"circles {engine} {threads}t depth {depth or 'auto'}")


# ----------------------------------------------------------------------------------------------------------------
# Aggregation: medians over rounds, one row per (scene, size, engine)
# ----------------------------------------------------------------------------------------------------------------
STEP_CSV = ["step_ms", "collide_ms", "solve_ms", "broadphase_ms", "toi_ms", "contacts_mean", "new_pairs_per_step",
            "pairs_reported_per_step", "qt_find_ms_per_step", "peak_rss_bytes", "bp_bytes_per_proxy"]
STEP_FIELDS = STEP_CSV + ["proxies", "bodies", "continuous", "qt_parallel_calls_per_step"]
PHASE_FIELDS = [f"{p}_{k}" for p in PHASES for k in ("first", "steps", "step_ms", "broadphase_ms")]
# The CSVs of every level (with an "opt" column) and their columns (None: every field, in the order first seen);
# queries.csv and circles.csv are the first level's.
LEVEL_CSVS = {
    "step": ["opt", "scene", "size", "engine", "rounds", "bodies", "proxies", "continuous"] + STEP_CSV,
    "phases": ["opt", "scene", "size", "steps", "engine", "rounds", "continuous"] + PHASE_FIELDS
              + [k.format(p) for p in PHASES for k in ("fair_{}_steps", "fair_{}_stock_bp_ms", "fair_{}_bp_ms",
                                                       "{}_stock_us_per_awake", "{}_qt_us_per_awake")],
    "replay_phases": None, "peers": None,
    "replay": ["opt", "scene", "size", "trace", "engine", "mode", "rounds", "mean_proxies", "ms_per_step",
               "ns_per_proxy_step", "pairs_per_step", "bytes_per_proxy", "exact", "missed_pct", "duplicates_pct",
               "levels"],
}


def engine_name(r):
    """stock, or quadtree-Nt with N = OMP_NUM_THREADS of the run (the tools print it)."""
    return "stock" if r["variant"] == "stock" else f"quadtree-{r.get('omp_num_threads') or r.get('threads')}t"


def aggregate(rows):
    groups, replay, checks, paper_checks, circles, queries, triads = {}, {}, {}, {}, {}, {}, []
    for r in rows:
        tool, kind = r.get("tool"), r.get("kind")
        if tool == "qp-step":
            part = r["label"].split()[0] if r.get("label", "").startswith("phases") else "step"
            groups.setdefault((part, r["scene"], r["size"], r["steps"], engine_name(r)), []).append(r)
        elif tool == "qp-query":
            queries.setdefault(engine_name(r), []).append(r)
        elif tool == "qp-replay" and kind == "triad":
            triads.append(r["bytes_per_s"])
        elif tool == "qp-replay" and kind in ("run", "check", "paper_check"):
            e = r.get("engine", "quadtree")
            key = (r["trace"], f"quadtree-{r.get('threads')}t" if e == "quadtree" else e)
            if kind == "run":
                replay.setdefault(key, []).append(r)
            elif kind == "check":
                checks[key] = r
            else:
                paper_checks[r["trace"]] = r
        elif tool == "qp-circles" and kind == "result":
            circles[(r["engine"], r["threads"], r["depth"])] = r
    return groups, replay, checks, paper_checks, circles, queries, triads


def per_step(runs, key):
    """The median over the runs (rounds) of each step's value."""
    return [med(list(v)) for v in zip(*[r[key] for r in runs])]


def fair_phases(groups):
    """In-engine phases compared over the same steps (the builds' simulations drift apart, see README): a step's
    phase is the stock run's, and "resting" counts only the steps where both builds rest. Also each build's
    broadphase time per awake body over its own phases. (scene, size, steps, engine) -> fields."""
    out = {}
    for s, n, st in {k[1:4] for k in groups if k[0] == "phases"}:
        runs = {e: groups.get(("phases", s, n, st, e)) for e in HEADLINE_ENGINES}
        if not runs["stock"] or "steps_phase" not in runs["stock"][0]:
            continue
        sp, sbp = runs["stock"][0]["steps_phase"], per_step(runs["stock"], "steps_bp_ms")
        for e in QUADTREES:
            if not runs[e] or "steps_phase" not in runs[e][0]:
                continue
            qp, qbp, row = runs[e][0]["steps_phase"], per_step(runs[e], "steps_bp_ms"), {}
            for i, p in enumerate(PHASES):
                ks = [k for k in range(min(len(sp), len(qp))) if sp[k] == i and (p != "resting" or qp[k] == i)]
                row.update({f"fair_{p}_steps": len(ks), f"fair_{p}_stock_bp_ms": med([sbp[k] for k in ks]),
                            f"fair_{p}_bp_ms": med([qbp[k] for k in ks])})
                for who, ph, bp, rs in (("stock", sp, sbp, runs["stock"]), ("qt", qp, qbp, runs[e])):
                    aw, ks = per_step(rs, "steps_awake"), [k for k in range(len(ph)) if ph[k] == i]
                    a = sum(aw[k] for k in ks)
                    row[f"{p}_{who}_us_per_awake"] = 1e3 * sum(bp[k] for k in ks) / a if a else None
            out[(s, n, st, e)] = row
    return out


def replay_phase_rows(replay, traces):
    """Phase traces: each engine's mean ms per step over each phase's steps (qp-record's phases), median over
    rounds; stock ÷ engine."""
    out = []
    for t in (t for t in traces if t["warmup"] == 0):
        for e in (e for e in PHASE_ENGINES if replay.get((t["name"], e))):
            for p in PHASES:
                ks = [k for k, x in enumerate(t["phases"]) if x == p]
                if ks:
                    ms = med([sum(r["steps_ns"][k] for k in ks) / len(ks) * 1e-6 for r in replay[(t["name"], e)]])
                    out.append({"trace": t["name"], "scene": t["scene"], "size": t["size"], "engine": e, "phase": p,
                                "first": ks[0], "steps": len(ks), "ms_per_step": ms})
    ref = {(r["trace"], r["phase"]): r["ms_per_step"] for r in out if r["engine"] == "stock"}
    return [dict(r, x_stock=ratio(ref.get((r["trace"], r["phase"])), r["ms_per_step"])) for r in out]


def peers_floors(rows, checks, triads, traces):
    """Per trace: the fastest exact peer (either mode), quadphase's ratio over it, the oracle and memory floors."""
    out, bw, by, meta = [], med(triads), {}, {t["name"]: t for t in traces}
    for r in rows:
        by.setdefault((r["scene"], r["size"]), {})[r["engine"]] = r
    for (s, n), es in sorted(by.items()):
        q1, o = es.get("quadtree-1t"), es.get("oracle") or {}
        if not q1:
            continue
        exact = [(r["ms_per_step"], e) for e, r in es.items() if e in PEERS and r.get("exact") == "yes"]
        best = min(exact) if exact else (None, None)
        c = checks.get((q1["trace"], "quadtree-1t")) or {}
        steps = c.get("timed_steps") or meta.get(q1["trace"], {}).get("steps")
        mem = c["floor_bytes"] / steps / bw * 1e3 if c.get("floor_bytes") and bw and steps else None
        out.append({"scene": s, "size": n, "qt1_ms": q1["ms_per_step"],
                    "qt2_ms": (es.get("quadtree-2t") or {}).get("ms_per_step"), "peer": best[1], "peer_ms": best[0],
                    "peer_x": ratio(best[0], q1["ms_per_step"]), "oracle_ms": o.get("ms_per_step"),
                    "oracle_exact": o.get("exact"), "qt_over_oracle": ratio(q1["ms_per_step"], o.get("ms_per_step")),
                    "memory_floor_ms": mem, "qt_over_memory": ratio(q1["ms_per_step"], mem),
                    "floor_mb_per_step": steps and c.get("floor_bytes", 0) / steps / 1e6,
                    "triad_gb_s": bw and bw * 1e-9})
    return out


def step_rows(groups, part, fields):
    out = [dict({"scene": scene, "size": size, "steps": steps, "engine": name, "rounds": len(runs)},
                **{k: med([x.get(k) for x in runs]) for k in fields})
           for (p, scene, size, steps, name), runs in groups.items() if p == part]
    return sorted(out, key=lambda r: (r["scene"], r["size"], r["steps"], r["engine"]))


def replay_table(replay, checks, paper_checks, traces):
    out, meta = [], {t["name"]: t for t in traces}
    for (trace, e), runs in replay.items():
        if meta.get(trace, {}).get("warmup") == 0:
            continue  # phase traces: replay_phase_rows
        mode = "native" if "-native" in e else ("protocol" if e in PEERS + ["oracle"] else "")
        row = {"trace": trace, "mode": mode, "scene": runs[0]["scene"], "size": runs[0]["size"], "engine": e,
               "rounds": len(runs), "ms_per_step": med([x["step_ns"] * 1e-6 for x in runs]),
               "proxies_end": meta.get(trace, {}).get("proxies")}
        row.update({k: med([x.get(k) for x in runs]) for k in ("ns_per_proxy_step", "pairs_per_step",
                                                               "bytes_per_proxy", "mean_proxies")})
        c, p = checks.get((trace, e)), paper_checks.get(trace)
        if e in EXACT_ENGINES:
            # Checked: protocol mode against stock's hash file (compared_file); native mode against every
            # overlapping fat-box pair, computed in the tool (checked_against, no file).
            checked = c and (c.get("compared_file") == 1 or ("compared_file" not in c and c.get("checked_against")))
            row["exact"] = ("yes" if checked and c.get("mismatches") == 0
                            else ("MISMATCH" if c and c.get("mismatches") else "not checked"))
        elif e == "paper" and p:
            row.update(exact="no (by design)", missed_pct=100.0 * p["missed"] / max(1, p["exact_pairs"]),
                       duplicates_pct=100.0 * p["duplicates"] / max(1, p["exact_pairs"]), extra=p["extra"],
                       levels=p.get("levels"))
        else:
            row["exact"] = "reference" if e == "stock" else "-"
        out.append(row)
    return sorted(out, key=lambda r: (r["scene"], r["size"], REPLAY_ENGINES.index(r["engine"])))


def query_rows(queries):
    out = []
    names = [w for w, _ in QUERY_WORKLOADS] + [w + "_floor" for w in QUERY_FLOORS]
    ref = {w: queries.get("stock", [{}])[0].get(w + "_hash") for w in names}
    for name, runs in sorted(queries.items()):
        for w in (w for w in names if any(w + "_ns" in r for r in runs)):  # runs before floors existed: none
            hashes = {r.get(w + "_hash") for r in runs}
            out.append({"workload": w, "engine": name, "rounds": len(runs),
                        "ms": med([r[w + "_ns"] * 1e-6 for r in runs if w + "_ns" in r]),
                        "queries": runs[0].get(w + "_queries"), "hits": runs[0].get(w + "_hits"),
                        "hash": ",".join(sorted(h for h in hashes if h)), "same_hits_as_stock": hashes == {ref[w]},
                        "bodies": runs[0]["bodies"], "teleported": runs[0]["teleported"]})
    return out


def level_data(rows, traces):
    """One level's raw rows as the rows of its CSVs."""
    groups, replay, checks, paper_checks, circles, queries, triads = aggregate(rows)
    fair = fair_phases(groups)
    replay_rows = replay_table(replay, checks, paper_checks, traces)
    return dict(step=step_rows(groups, "step", STEP_FIELDS),
                phases=[dict(r, **fair.get((r["scene"], r["size"], r["steps"], r["engine"]), {}))
                        for r in step_rows(groups, "phases", PHASE_FIELDS + ["continuous", "bodies"])],
                replay=replay_rows, replay_phases=replay_phase_rows(replay, traces),
                peers=peers_floors(replay_rows, checks, triads, traces), queries=query_rows(queries),
                circles=[dict(engine=e, threads=t, depth="auto" if d < 0 else d,
                              **{k: r[k] for k in ("n_max", "capped", "evaluations", "seconds")})
                         for (e, t, d), r in sorted(circles.items())])


def keyed(rows, fields=("scene", "size", "engine")):
    return {tuple(r[f] for f in fields): r for r in rows}


def x_stock(by, case, engine, field):
    """Stock's `field` ÷ the engine's on a case (a key of `by` without its engine): > 1 when the engine is faster."""
    return ratio((by.get(case + ("stock",)) or {}).get(field), (by.get(case + (engine,)) or {}).get(field))


def threads(engine):
    return engine.replace("quadtree-", "")


# ----------------------------------------------------------------------------------------------------------------
# Outputs
# ----------------------------------------------------------------------------------------------------------------
def write_outputs(args, info, rows_by_level, frame_goals=()):
    res, levels = args.results, [lv for lv, _ in info["levels"]]
    data = {lv: level_data(rows_by_level[lv], info.get("traces", [])) for lv in levels}
    for name, fields in LEVEL_CSVS.items():
        report.write_csv(os.path.join(res, name + ".csv"), [dict(r, opt=lv) for lv in levels for r in data[lv][name]],
                         fields)
    for name in ("queries", "circles"):
        report.write_csv(os.path.join(res, name + ".csv"), data[levels[0]][name])
    report.write_json(os.path.join(res, "bench.json"), {
        "machine": info, "levels": data, "paper_published": paper.TABLES, "reference_this_machine": REFERENCE})
    report.write_lines(args.summary, markdown(info, data, levels, figures(res, data[levels[0]]), frame_goals))


def figures(res, d):
    plt = plot.pyplot("bench.py")
    if plt is None:
        return {}
    from matplotlib.ticker import FuncFormatter
    plots = {}
    by, cases = keyed(d["step"]), sorted({(r["scene"], r["size"]) for r in d["step"]})
    if cases:  # 1. ratio bars per scene: stock / quadtree, whole step and b2Profile::broadphase
        fig, axes = plt.subplots(2, 1, figsize=(max(8, 0.55 * len(cases) + 2), 7.5), sharex=True)
        for ax, metric, title in ((axes[0], "step_ms", "whole step (b2Profile::step)"),
                                  (axes[1], "broadphase_ms", "broadphase (b2Profile::broadphase)")):
            for k, (eng, color) in enumerate(zip(QUADTREES, ("#4c72b0", "#dd8452"))):
                ax.bar([x + (k - 0.5) * 0.4 for x in range(len(cases))],
                       [x_stock(by, c, eng, metric) or 0 for c in cases], 0.4, color=color, label=ENGINE_LABEL[eng])
            ax.axhline(1.0, color="black", lw=0.8)
            # The scale before the formatters: setting it resets them.
            ax.set(yscale="log", ylabel="stock time / quadtree time", title=title + ": > 1 means quadphase is faster")
            ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:g}×"))
            ax.yaxis.set_minor_formatter(FuncFormatter(
                lambda y, _: f"{y:g}×" if y > 0 and round(y / 10 ** math.floor(math.log10(y))) in (2, 5) else ""))
            ax.legend(fontsize=8)
            ax.grid(axis="y", alpha=0.3, which="both")
        axes[1].set_xticks(range(len(cases)), [f"{s} {n}" for s, n in cases], rotation=60, ha="right", fontsize=8)
        plots["step"] = "results/step_ratios.png"
        plot.save(plt, fig, os.path.join(res, "step_ratios.png"), 90)
    rows = d["replay"]
    scenes = sorted({r["scene"] for r in rows if len({x["size"] for x in rows if x["scene"] == r["scene"]}) > 1})
    scenes = scenes or sorted({r["scene"] for r in rows})
    if scenes:  # 2. time vs N, log-log, every broadphase of the replay, per scene
        fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.6), squeeze=False)
        for ax, scene in zip(axes[0], scenes):
            for e in REPLAY_ENGINES:
                pts = sorted((r["mean_proxies"], r["ms_per_step"]) for r in rows
                             if r["scene"] == scene and r["engine"] == e and r["ms_per_step"])
                if pts:
                    ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3,
                            ls="--" if e in ("oracle", "null", "paper") else "-", label=ENGINE_LABEL[e])
            ax.set(xscale="log", yscale="log", xlabel="live proxies", ylabel="broadphase work, ms per step",
                   title=f"replay: {scene}")
            ax.grid(alpha=0.3, which="both")
        axes[0][0].legend(fontsize=7)
        plots["replay"] = "results/replay_scaling.png"
        plot.save(plt, fig, os.path.join(res, "replay_scaling.png"), 90)
    if d["circles"]:  # 3. the paper's table: circles under 20 ms by depth, here and in the paper
        fig, ax = plt.subplots(figsize=(8.5, 4.8))
        labels = ["4", "5", "6", "7", "8", "9", "auto"]
        series = {}
        for r in (r for r in d["circles"] if r["engine"] in ("paper", "quadtree")):
            name = ("paper's design" if r["engine"] == "paper" else "quadphase") + \
                   (", sequential" if r["threads"] == 1 else f", {r['threads']} threads (static)")
            series.setdefault(name, {})[str(r["depth"])] = r["n_max"]
        for k, (name, vals) in enumerate(sorted(series.items())):
            xs = [i for i, l in enumerate(labels) if l in vals]
            # A small sideways offset per series, so that equal results stay visible.
            ax.plot([x + 0.06 * (k - 1.5) for x in xs], [vals[labels[i]] for i in xs], marker="o",
                    label=name + " (here)")
        for r in (r for r in d["circles"] if r["engine"] in ("pairwise", "stock")):
            ax.axhline(r["n_max"], ls=":", color="gray" if r["engine"] == "pairwise" else "green")
            ax.text(6.1, r["n_max"], ("brute force" if r["engine"] == "pairwise" else "stock tree") + " (here)",
                    fontsize=7, va="bottom")
        for k, ls in (("Seq.", "--"), ("Static", "-.")):
            ax.plot(range(6), paper.TABLES["i7-7500U (2 cores / 4 threads)"][k], ls=ls, color="black", alpha=0.5,
                    lw=1, label=f"paper, i7-7500U, {k} (published)")
        ax.axhline(1360, ls="--", color="red", alpha=0.4, lw=1)
        ax.text(0, 1360, "paper brute force 1,360 (i7)", fontsize=7, va="bottom")
        # The scale before the formatter: setting it resets it.
        ax.set(yscale="log", xlabel="depth (paper: its level; quadphase: pyramid depth)",
               ylabel="circles under 20 ms per frame",
               title="the paper's protocol: broadphase + circle test under 20 ms")
        ax.yaxis.set_major_formatter(FuncFormatter(lambda y, _: f"{y:,.0f}"))
        ax.set_xticks(range(len(labels)), labels)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
        plots["circles"] = "results/paper_table.png"
        plot.save(plt, fig, os.path.join(res, "paper_table.png"), 90)
    return plots


def section(title, intro, plots=(), key=None, alt=None):
    """A section's title, its plot (when drawn) and its introduction."""
    return [title, ""] + ([f"![{alt}]({plots[key]})", ""] if key in plots else []) + [intro, ""]


def met(ok):
    return "met" if ok else ("not met" if ok is False else "n/a")


def markdown(info, data, levels, plots, frame_goals=()):
    d = data[levels[0]]
    by, rp = keyed(d["step"]), keyed(d["replay"])
    command = (" --full" if info["profile"] == "full" else "") + (" --opt both" if len(levels) > 1 else "")
    L = ["# quadphase benchmark results", "", TEXT["header"].format(
        profile=info["profile"], command=command, rounds=info["rounds"], minutes=info["timing"].get("total_s", 0) / 60)]
    if info.get("scale", 1.0) != 1.0:
        L += ["", f"**Scaled run (--scale {info['scale']}): sizes are not the profile's; for development only.**"]
    L += [""] + report.machine_section(info)[:-1]
    L.append("- optimisation levels (each a stock and a quadphase build from the same source and flags): "
             + "; ".join(f"{lv} `{info['level_flags'][lv]}`" for lv in levels) + f"; tables below at {levels[0]} "
             "unless a column says otherwise.")
    if info.get("engines_missing"):
        L.append(f"- not built (Chipmunk2D / Bullet missing at configure time): {', '.join(info['engines_missing'])}")
    L += [""] + headline(d, by, rp, levels[0])
    if frame_goals:  # "## Goals" becomes this report's frames section, with the per-step tables in frames.md
        L += ["## Frames: worst step and total at the defaults (issue 31)", "",
              f"Issue 31's goals from this run's frames section: {info.get('frame_steps', 600)} steps from the first, "
              "as a game runs the library, "
              "alone and beside a busy thread; [results/frames.md](results/frames.md) explains the columns and the "
              "best-round rule and has the per-step tables.", ""] + frame_goals[2:] + [""]
    L += step_section(d, by, plots) + phase_section(data, levels)
    L += replay_section(d, rp, plots) + levels_section(data, levels) + query_section(d) + circles_section(d, plots)
    L += ["## Notes", "", TEXT["notes"],
          "- Run time: " + ", ".join(f"{k} {v:.0f} s" for k, v in info["timing"].items() if k != "total_s") + ".", ""]
    return L


def goal_row(target, vals, goal, in_profile=True, note=""):
    """A headline row: the (measured, ratio) pairs; met when every ratio reaches the goal, n/a (and `note`) when
    the profile has none of the target's cases."""
    if not vals:
        return []
    return [f"| {target} | {', '.join(t for t, _ in vals)}{'' if in_profile else note} | "
            f"{met(all(v >= goal for _, v in vals) if in_profile else None)} |"]


def headline(d, by, rp, level):
    L = [f"## Headline: measured against the targets of issues 4, 16 and 19 ({level})", "",
         "| target | measured here | |", "|---|---|---|"]
    replay_cases = sorted({(r["scene"], r["size"]) for r in d["replay"]})
    big = [(s, n) for s, n in replay_cases if (s == "particles" and n >= 50000) or (s == "rain" and n >= 60000)]
    for eng, goal in (("quadtree-1t", 8), ("quadtree-2t", 14)):
        vals = [(f"{s} {n}: {v:.1f}×", v) for s, n in big or [c for c in replay_cases if c[0] in ("particles", "rain")]
                for v in [x_stock(rp, (s, n), eng, "ms_per_step")] if v]
        L += goal_row(f"replay, {threads(eng)}: ≥{goal}× stock on particles 50k–100k, rain 64k", vals, goal, big,
                      " (smaller traces: this profile has no 50k+ trace)")
    slower = [f"{s} {n} ({e})" for s, n in replay_cases for e in QUADTREES
              if (x_stock(rp, (s, n), e, "ms_per_step") or 2) < 1.0]
    L.append(f"| replay: never slower than stock on any trace | "
             f"{'slower on: ' + ', '.join(slower) if slower else 'faster on every trace'} | {met(not slower)} |")
    for scene, size, key in (("particles", 50000, "replay_stock_particles50k"),
                             ("rain", 65536, "replay_stock_rain64k")):
        if rp.get((scene, size, "stock")):
            L.append(f"| stock replay ≈{REFERENCE[key]} ns/proxy/step on {scene} {size} (reference) | "
                     f"{rp[(scene, size, 'stock')]['ns_per_proxy_step']:.0f} ns | context |")
    step_cases = sorted({(r["scene"], r["size"]) for r in d["step"]})
    for size, key in ((10000, "step_bp_stock_particles10k"), (50000, "step_bp_stock_particles50k")):
        if by.get(("particles", size, "stock")):
            L.append(f"| stock b2Profile::broadphase {REFERENCE[key]} ms/step on particles {size} (reference) | "
                     f"{by[('particles', size, 'stock')]['broadphase_ms']:.2f} ms | context |")
    p20 = [c for c in step_cases if c[0] == "particles" and c[1] >= 20000]
    for eng, goal in (("quadtree-1t", 3), ("quadtree-2t", 4)):
        vals = [(f"particles {n}: {v:.1f}×", v) for s, n in p20 or [c for c in step_cases if c[0] == "particles"]
                for v in [x_stock(by, (s, n), eng, "broadphase_ms")] if v]
        L += goal_row(f"in-engine broadphase, {threads(eng)}: ≥{goal}× on particles 20k+", vals, goal, p20,
                      " (no 20k+ size in this profile)")
    for metric, what in (("broadphase_ms", "in-engine broadphase"), ("step_ms", "whole step")):
        worst = sorted((v, f"{s} {n} {threads(e)}") for s, n in step_cases for e in QUADTREES
                       for v in [x_stock(by, (s, n), e, metric)] if v is not None)
        below = [w for w in worst if w[0] < 0.95]
        if worst:
            L.append(f"| {what}: never slower on any scene{' (within noise, 5%)' if metric == 'step_ms' else ''} | "
                     f"lowest ratio {worst[0][0]:.2f}× ({worst[0][1]})"
                     + (f"; below 0.95×: {', '.join(w[1] for w in below)}" if below else "")
                     + f" | {met(not below)} |")
    ccd = "CCD on" if all(r.get("continuous") for r in d["phases"]) else "CCD not on everywhere"
    for low, how in ((phase_lows(d["phases"], True), "the same steps: stock's phases, resting where both rest"),
                     (phase_lows(d["phases"]), "raw: each build's own phases")):
        if low:
            L.append(f"| in-engine broadphase, every phase, 1 and 2 threads ({ccd}): never below 1.0× ({how}) | "
                     f"lowest {low[0][0]:.2f}× ({low[0][1]})"
                     + (f"; below 1.0×: {', '.join(f'{w[1]} {w[0]:.2f}×' for w in low if w[0] < 1.0)}"
                        if low[0][0] < 1.0 else "") + f" | {met(low[0][0] >= 1.0)} |")
    # The oracle replays the known pairs on one thread: where even n times its speed is under the goal (rain resting:
    # almost every call is a MoveProxy that keeps its fat box, and stock's own cost of such a call is little more
    # than the replay loop's), no broadphase on n threads can reach the goal, and the row says so.
    oracle = {(r["scene"], r["size"], r["phase"]): r["x_stock"] for r in d["replay_phases"] if r["engine"] == "oracle"}
    for eng, goal, n in (("quadtree-1t", 8, 1), ("quadtree-2t", 14, 2)):
        def phase_text(r, goal=goal, n=n):
            o = oracle.get((r["scene"], r["size"], r["phase"]))
            bound = (f" (unreachable: the oracle floor is {o:.1f}×" + (f", {n} × that {n * o:.1f}×" if n > 1 else "")
                     + ")") if o and n * o < goal else ""
            return f"{r['scene']} {r['size']} {r['phase']}: {r['x_stock']:.1f}×{bound}"
        L += goal_row(f"replay, {threads(eng)}: ≥{goal}× stock in every phase of rain",
                      [(phase_text(r), r["x_stock"])
                       for r in d["replay_phases"] if r["engine"] == eng and r["x_stock"]], goal)
    pf = keyed(d["peers"], ("scene", "size"))
    cases = [c for c in big if c in pf and pf[c]["peer_x"]] or [c for c, r in pf.items() if r["peer_x"]]
    L += goal_row("replay, 1 thread: ≥4× the fastest tuned exact peer on particles 50k–100k, rain 64k",
                  [(f"{s} {n}: {pf[(s, n)]['peer_x']:.1f}× ({pf[(s, n)]['peer']})", pf[(s, n)]["peer_x"])
                   for s, n in cases], 4, big, " (smaller traces: no 50k+ trace in this profile)")
    o50 = (pf.get(("particles", 50000)) or {}).get("qt_over_oracle")
    others = ", ".join(f"{s} {n}: {r['qt_over_oracle']:.1f}×" for (s, n), r in sorted(pf.items())
                       if r["qt_over_oracle"])
    L.append("| replay, 1 thread: within 4× of the oracle floor on particles 50k | "
             + (f"{o50:.1f}×" if o50 else "particles 50k not in this profile")
             + f" (every trace: {others}) | {met(o50 <= 4) if o50 else 'n/a'} |")
    mem = ", ".join(f"{s} {n}: {r['qt_over_memory']:.0f}×" for (s, n), r in sorted(pf.items()) if r["qt_over_memory"])
    if mem:
        L.append(f"| replay, 1 thread ÷ memory floor (bytes touched ÷ triad bandwidth) | {mem} | context |")
    s50 = x_stock(by, ("particles", 50000), "quadtree-2t", "step_ms")
    L.append(f"| whole step ≥1.5× on particles 50k, 2 threads | "
             f"{f'{s50:.2f}×' if s50 else 'not measured in this profile'} | {met(s50 >= 1.5) if s50 else 'n/a'} |")
    q = keyed(d["queries"], ("workload", "engine"))
    if q:
        worst = sorted((x_stock(q, (w,), e, "ms"), w, e) for w, _ in QUERY_WORKLOADS for e in QUADTREES
                       if (w, e) in q and (w, "stock") in q)
        L.append(f"| queries: no workload slower than stock | lowest {worst[0][0]:.2f}× ({worst[0][1]}, "
                 f"{threads(worst[0][2])}) | {met(worst[0][0] >= 1.0)} |")
        for w, goal in QUERY_GOALS.items():
            v, bound = x_stock(q, (w,), "quadtree-1t", "ms"), ratio(q.get((w, "stock"), {}).get("ms"), floor_ms(q, w))
            if v:
                L.append(f"| queries: {w} ≥{goal:g}× stock (1 thread) | {v:.2f}×"
                         + (f" (stock ÷ the floor: {bound:.1f}×, the most any broadphase can gain"
                            + ("; unreachable" if bound < goal else "") + ")" if bound else "")
                         + f" | {met(v >= goal)} |")
        bad = sorted({r["workload"] for r in d["queries"] if not r["same_hits_as_stock"]})
        L.append(f"| queries: the same hits as stock (hash of sorted fixture ids; closest hit and fraction) | "
                 f"{'DIFFERENT on ' + ', '.join(bad) if bad else 'identical on every workload'} | {met(not bad)} |")
    cz = {(r["engine"], r["threads"], str(r["depth"])): r["n_max"] for r in d["circles"]}
    best_q = max([v for (e, t, dd), v in cz.items() if e == "quadtree"] or [0])
    for target, n, goal, digits, ref in (("the stock tree's circles", cz.get(("stock", 1, "auto")), 8, 1, "stock"),
                                         ("brute force", cz.get(("pairwise", 1, "auto")), 80, 0, "brute")):
        if best_q and n:
            L.append(f"| paper's protocol: quadphase ≥{goal}× {target} | {best_q:,} vs {n:,} = "
                     f"{best_q / n:.{digits}f}× (reference here: {ref} ≈{REFERENCE['circles_' + ref]:,}) | "
                     f"{met(best_q >= goal * n)} |")
    mem = [(q_["bytes_per_proxy"] / a["bytes_per_proxy"], s, n, q_["bytes_per_proxy"], a["bytes_per_proxy"])
           for s, n in replay_cases for a, q_ in [(rp.get((s, n, "stock")), rp.get((s, n, "quadtree-1t")))]
           if a and q_ and a.get("bytes_per_proxy") and q_.get("bytes_per_proxy")]
    if mem:
        w = max(mem)
        L.append(f"| memory: no more bytes per proxy than the stock tree (replay heap) | worst {w[1]} {w[2]}: "
                 f"{w[3]:.0f} vs {w[4]:.0f} B/proxy ({w[0]:.2f}×) | {met(w[0] <= 1.0)} |")
    return L + [""]


def step_section(d, by, plots):
    if not d["step"]:
        return []
    ccd = {r.get("continuous") for r in d["step"]}
    L = section("## 1. In-engine step benchmark", TEXT["step"].format(
        ccd="on" if ccd == {1} else "off" if ccd == {0} else "not recorded or mixed"), plots, "step",
        "stock / quadtree time per scene")
    rows, small = [], []
    for s, n in sorted({(r["scene"], r["size"]) for r in d["step"]}):
        a, q1, q2 = by.get((s, n, "stock")), by.get((s, n, "quadtree-1t")) or {}, by.get((s, n, "quadtree-2t")) or {}
        if not a:
            continue
        share = ratio(a["broadphase_ms"], a["step_ms"])
        rows.append([s, n, fmt(a["proxies"]), fmt(a["step_ms"]), fmt(a["broadphase_ms"]),
                     f"{fmt(share and 100 * share, 0)}%"]
                    + [fmt(q.get(k)) for q in (q1, q2) for k in ("step_ms", "broadphase_ms")]
                    + [" / ".join(fmt(x_stock(by, (s, n), e, k)) for e in QUADTREES)
                       for k in ("step_ms", "broadphase_ms")]
                    + [f"{fmt(a['contacts_mean'], 0)} / {fmt(q1.get('contacts_mean'), 0)}",
                       f"{fmt(a['new_pairs_per_step'], 1)} / {fmt(q1.get('new_pairs_per_step'), 1)}",
                       f"{fmt(a['peak_rss_bytes'] / 1048576, 1)} / "
                       f"{fmt(q1.get('peak_rss_bytes') and q1['peak_rss_bytes'] / 1048576, 1)}",
                       fmt(q1.get("bp_bytes_per_proxy"), 0)])
        if (share or 1) < 0.10:
            small.append(f"{s} {n} ({100 * share:.0f}%)")
    L += table(["scene", "size", "proxies", "stock step", "bp", "bp share", "1t step", "1t bp", "2t step", "2t bp",
                "step × 1t / 2t", "bp × 1t / 2t", "contacts (stock / qt)", "new pairs/step", "peak RSS MB stock / qt",
                "qt B/proxy"], rows) + [""]
    if small:
        L += [TEXT["small_share"].format(cases=", ".join(small)), ""]
    return L


def steps_range(r, p):
    """Phase p's steps of a row: first–last."""
    return f"{r[p + '_first']:.0f}–{r[p + '_first'] + r[p + '_steps'] - 1:.0f}"


def phase_lows(rows, fair=False):
    """(stock / quadtree broadphase, "scene size steps phase engine") for every measured phase, lowest first; fair:
    over the same steps (fair_phases)."""
    by = keyed(rows, ("scene", "size", "steps", "engine"))
    if fair:
        return sorted((v, f"{s} {n} ({q[f'fair_{p}_steps']} steps) {p} {threads(e)}")
                      for (s, n, st, e), q in by.items() if e != "stock" for p in PHASES if q.get(f"fair_{p}_steps")
                      for v in [ratio(q[f"fair_{p}_stock_bp_ms"], q[f"fair_{p}_bp_ms"])] if v)
    return sorted((v, f"{s} {n} (steps {steps_range(a, p)}) {p} {threads(e)}")
                  for (s, n, st, e), q in by.items() if e != "stock" for a in [by.get((s, n, st, "stock"))] if a
                  for p in PHASES if a.get(p + "_steps")
                  for v in [ratio(a[p + "_broadphase_ms"], q[p + "_broadphase_ms"])] if v)


def phase_section(data, levels):
    if not any(data[lv]["phases"] for lv in levels):
        return []
    L = section("## 1b. In-engine, by phase: falling, piling, resting", TEXT["phases"])
    rows = []
    for lv in levels:
        by = keyed(data[lv]["phases"], ("scene", "size", "steps", "engine"))
        for (s, n, st, e), a in sorted(by.items()):
            qs = [by.get((s, n, st, q)) or {} for q in QUADTREES]
            for p in (p for p in PHASES if e == "stock" and a.get(p + "_steps")):
                bp, step = p + "_broadphase_ms", p + "_step_ms"
                rows.append([lv, f"{s} {n}", "on" if a.get("continuous") else "off", p,
                             " / ".join(steps_range(r, p) if r.get(p + "_steps") else "–" for r in [a] + qs)]
                            + [fmt(r.get(bp), 3) for r in [a] + qs]
                            + [" / ".join(fmt(ratio(a[bp], q.get(bp))) for q in qs), fmt(a[step]),
                               " / ".join(fmt(ratio(a[step], q.get(step))) for q in qs)])
    L += table(["opt", "scene", "CCD", "phase", "steps: stock / 1t / 2t", "stock bp ms", "1t bp ms", "2t bp ms",
                "bp × 1t / 2t", "stock step ms", "step × 1t / 2t"], rows) + [""]
    L += [TEXT["same_steps"], ""]
    rows = [[lv, f"{r['scene']} {r['size']}", threads(r["engine"]), p, r.get(f"fair_{p}_steps"),
             fmt(r.get(f"fair_{p}_stock_bp_ms"), 3), fmt(r.get(f"fair_{p}_bp_ms"), 3),
             fmt(ratio(r.get(f"fair_{p}_stock_bp_ms"), r.get(f"fair_{p}_bp_ms"))),
             f"{fmt(r.get(f'{p}_stock_us_per_awake'), 3)} / {fmt(r.get(f'{p}_qt_us_per_awake'), 3)}"]
            for lv in levels for r in data[lv]["phases"] if r["engine"] != "stock" for p in PHASES
            if r.get(f"fair_{p}_steps")]  # a phase the run did not reach has no row
    return L + table(["opt", "scene", "threads", "phase (stock's)", "steps", "stock bp ms", "qt bp ms", "bp ×",
                      "µs per awake body: stock / qt"], rows) + [""]


def replay_section(d, rp, plots):
    if not d["replay"]:
        return []
    L = section("## 2. Broadphase replay (identical trace)", TEXT["replay"], plots, "replay",
                "time against N, every broadphase")
    rows = []
    for s, n in sorted({(r["scene"], r["size"]) for r in d["replay"]}):
        for e in (e for e in REPLAY_ENGINES if (s, n, e) in rp):
            r, own = rp[(s, n, e)], e != "null"
            ex = r.get("exact", "")
            if e == "paper" and r.get("missed_pct") is not None:
                ex = (f"no: misses {r['missed_pct']:.2f}% of the pairs, {r['duplicates_pct']:.2f}% duplicates "
                      f"(levels {r.get('levels')})")
            sp = x_stock(rp, (s, n), e, "ms_per_step") if own and e != "stock" else None
            rows.append([f"{s} {n}", ENGINE_LABEL[e], r.get("mode", ""), fmt(r["ms_per_step"], 3),
                         fmt(r["ns_per_proxy_step"], 1), report.times(sp), fmt(r["pairs_per_step"], 0) if own else "",
                         fmt(r["bytes_per_proxy"], 0) if own else "", ex])
    L += table(["trace", "engine", "mode", "ms/step", "ns/proxy/step", "× stock", "pairs/step", "B/proxy", "exact"],
               rows)
    bad = [f"{r['scene']} {r['size']} {r['engine']}" for r in d["replay"] if r.get("exact") == "MISMATCH"]
    L += ["", "**PAIR SET MISMATCHES: " + ", ".join(bad) + "**" if bad else TEXT["replay_exact"], ""]
    L += ["### 2a. Fastest tuned peer and the floors", "", TEXT["peers"], ""]
    L += table(["trace", "quadphase 1t ms", "fastest exact peer", "peer ms", "× peer", "oracle ms", "÷ oracle",
                "floor MB/step", "memory floor ms", "÷ memory floor", "triad GB/s"], [
        [f"{r['scene']} {r['size']}", fmt(r["qt1_ms"], 3), ENGINE_LABEL.get(r["peer"], "–"), fmt(r["peer_ms"], 3),
         fmt(r["peer_x"]), fmt(r["oracle_ms"], 3), fmt(r["qt_over_oracle"]), fmt(r["floor_mb_per_step"], 2),
         fmt(r["memory_floor_ms"], 4), fmt(r["qt_over_memory"], 0), fmt(r["triad_gb_s"], 1)] for r in d["peers"]])
    if d["replay_phases"]:
        L += ["", "### 2b. Rain by phase (replay)", "", TEXT["replay_phases"], ""]
        L += table(["trace", "phase", "steps", "engine", "ms/step", "× stock"], [
            [f"{r['scene']} {r['size']}", r["phase"], f"{r['first']}–{r['first'] + r['steps'] - 1}",
             ENGINE_LABEL[r["engine"]], fmt(r["ms_per_step"], 3), fmt(r["x_stock"])] for r in d["replay_phases"]])
    return L + [""]


def levels_section(data, levels):
    if len(levels) < 2:
        return []
    L = section("## 2c. Both optimisation levels", TEXT["levels"])
    rows = []
    for lv in levels:
        for part, what, field, unit in (("replay", "replay", "ms_per_step", " ms/step"),
                                        ("step", "in-engine bp", "broadphase_ms", " ms")):
            by = keyed(data[lv][part])
            rows += [[lv, f"{what} {s} {n}", fmt(a[field], 3) + unit]
                     + [fmt(x_stock(by, (s, n), e, field)) + "×" for e in QUADTREES]
                     for (s, n, e0), a in sorted(by.items()) if e0 == "stock"]
    return L + table(["opt", "what", "stock", "quadphase 1t", "quadphase 2t"], rows) + [""]


def floor_ms(q, w):
    """A workload's floor: the lower of the builds' <workload>_floor medians (the same code in both; each build
    records its own candidates), or None."""
    return min([r["ms"] for e in ["stock"] + QUADTREES for r in [q.get((w + "_floor", e))] if r and r["ms"]] or [None])


def query_section(d):
    if not d["queries"]:
        return []
    q = keyed(d["queries"], ("workload", "engine"))
    floors = any(floor_ms(q, w) for w in QUERY_FLOORS)
    L = section("## 3. Queries through b2World (issue 19)", TEXT["queries"].format(bodies=d["queries"][0]["bodies"])
                + ("\n\n" + TEXT["query_floors"] if floors else ""))
    rows = []
    for w, what in QUERY_WORKLOADS:
        a, qs, f = q.get((w, "stock")), [q.get((w, e)) or {} for e in QUADTREES], floor_ms(q, w)
        if a:
            rows.append([what.format(**a), fmt(a["queries"], 0), fmt(a["hits"], 0), fmt(a["ms"], 3)]
                        + [x for r in qs for x in (fmt(r.get("ms"), 3), fmt(ratio(a["ms"], r.get("ms"))))]
                        + ([fmt(f, 3), fmt(ratio(a["ms"], f))] if floors else [])
                        + ["yes" if all(r.get("same_hits_as_stock") for r in qs) else "**NO**"])
    return L + table(["workload", "queries", "hits", "stock ms", "1t ms", "× stock", "2t ms", "× stock"]
                     + (["floor ms", "stock ÷ floor"] if floors else []) + ["same hits"], rows) + [""]


def circles_section(d, plots):
    names = {"pairwise": "brute force (pairwise)", "paper": "paper's design", "stock": "stock b2DynamicTree",
             "quadtree": "quadphase"}
    if not d["circles"]:
        return []
    L = section("## 4. The paper's protocol: circles under 20 ms per frame", TEXT["circles"], plots, "circles",
                "circles under 20 ms")
    L += table(["engine", "threads", "depth", "circles (here)", "capped"], [
        [names[r["engine"]], r["threads"], r["depth"] if r["engine"] in ("paper", "quadtree") else "–",
         f"{r['n_max']:,}", "yes: time cap, a lower bound" if r["capped"] else ""] for r in d["circles"]])
    return L + ["", "The paper (published): " + "; ".join(
        f"{cpu}: " + ", ".join(f"{k} {max(v):,}" for k, v in t.items()) for cpu, t in paper.TABLES.items())
        + " (best over levels 4–9).", ""]


if __name__ == "__main__":
    main()
