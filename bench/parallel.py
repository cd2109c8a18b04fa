#!/usr/bin/python3
"""Parallel pair-generation benchmark of quadphase (run it through bench/parallel.sh, which builds the tools).

One run records the traces (qp-record), checks every replay's pair sets against stock Box2D's (qp-replay-stock
hashes) and brute force (small traces), replays them with the timings interleaved (every round runs every
configuration once, so a noisy phase of the machine hits all of them), and writes
bench/results/parallel.md, parallel.csv and parallel.png. See bench/README.md for what each number means.
"""

import argparse
import math
import os
import random
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from qpbench import machine, paper, plot, report, run  # noqa: E402
from qpbench.report import fixed as fmt, table  # noqa: E402
from qpbench.stats import amdahl, karp_flatt, round_ratios  # noqa: E402

THRESHOLDS = [0, 64, 128, 256, 512, 1024, 4096]
# Options whose default depends on the version: (option, quick, full, help).
PROFILE_OPTIONS = [("repeats", 7, 11, "timed rounds"), ("table-warmup", 60, 120, "(a) warm-up steps"),
                   ("table-steps", 30, 60, "(a) timed steps"), ("particles-warmup", 60, 120, "(b) particles warm-up"),
                   ("particles-steps", 30, 60, "(b) particles timed steps"),
                   ("rain-warmup", 120, 600, "(b) rain warm-up: bodies falling (quick), pile forming (full)"),
                   ("rain-steps", 30, 60, "(b) rain timed steps"), ("sweep-bullets-size", 1000, 2000, "(c) bullets size"),
                   ("sweep-steps", 60, 120, "(c) sweep timed steps")]


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=os.path.join(os.path.dirname(HERE), "build-bench"),
                    help="build directory holding bench/qp-* (default: build-bench)")
    ap.add_argument("--results", default=os.path.join(HERE, "results"),
                    help="where parallel.md/.csv/.png go (default: bench/results)")
    ap.add_argument("--work", default=None, help="traces, hashes, logs (default: BUILD_DIR/tmp)")
    ap.add_argument("--full", action="store_true",
                    help="longer version: more repeats and steps, rain recorded until its pile has formed")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--sections", default="a,b,c,d,e", help="subset of a,b,c,d,e (default: all)")
    ap.add_argument("--note", default="", help="a sentence to print under the report's title")
    ap.add_argument("--report-only", action="store_true",
                    help="only rewrite the report from the last run's raw results in the work directory")
    ap.add_argument("--rerecord", action="store_true", help="record traces even when a matching one exists")
    ap.add_argument("--wait-quiet", type=float, default=20.0,
                    help="before each timed round, wait up to this many seconds for other processes to use "
                         "less than --quiet-cpus CPUs (default 20; 0: never wait)")
    ap.add_argument("--quiet-cpus", type=float, default=0.3)
    for name, quick, full, what in PROFILE_OPTIONS:
        ap.add_argument("--" + name, type=int, default=None, help=f"{what} (quick {quick}, full {full})")
    for name, default in (("table-size", 50000), ("particles-size", 100000), ("rain-size", 65536), ("small-size", 200),
                          ("small-warmup", 60), ("small-steps", 1000), ("sweep-particles-size", 10000),
                          ("sweep-warmup", 150)):  # sweep-warmup: bullets fires every bullet once in 120 steps
        ap.add_argument("--" + name, type=int, default=default)
    ap.add_argument("--depths", default="4,5,6,7,8,9,auto")
    ap.add_argument("--thresholds", default=",".join(str(t) for t in THRESHOLDS))
    a = ap.parse_args()
    for name, quick, full, _ in PROFILE_OPTIONS:
        key = name.replace("-", "_")
        if getattr(a, key) is None:
            setattr(a, key, full if a.full else quick)
    a.sections = set(s.strip() for s in a.sections.split(",") if s.strip())
    a.depths = [d.strip() for d in a.depths.split(",") if d.strip()]
    a.thresholds = [int(t) for t in a.thresholds.split(",") if t.strip()]
    a.work = a.work or os.path.join(a.build_dir, "tmp")
    return a


def log(msg):
    print(msg, flush=True)


# The core's default parallelThreshold and schedule (qp-replay --print-config), read at start.
DEFAULT = {"threshold": 512, "schedule": "guided"}


def set_defaults(default_config):
    for kv in default_config.split():
        k, _, v = kv.partition("=")
        if k in DEFAULT:
            DEFAULT[k] = int(v) if k == "threshold" else v


def cfg(threads=1, schedule=None, depth="auto", threshold=None, chunk=0):
    return {"threads": threads, "schedule": schedule or DEFAULT["schedule"],
            "depth": -1 if depth == "auto" else int(depth),
            "threshold": DEFAULT["threshold"] if threshold is None else threshold, "chunk": chunk}


def cfg_arg(c):
    return "threads={threads},schedule={schedule},depth={depth},threshold={threshold},chunk={chunk}".format(**c)


def cfg_key(c):
    return (c["threads"], c["schedule"], c["depth"], c["threshold"], c["chunk"])


def med(values):
    return statistics.median(values) if values else float("nan")


class Results:
    """The JSON lines by (trace, engine[, configuration]): timed runs, checking runs, OpenMP overhead."""

    def __init__(self, rows):
        self.runs, self.checks, self.stock_checks, self.omp = {}, {}, {}, []
        for r in rows:
            if r.get("kind") == "omp_overhead":
                self.omp.append(r)
                continue
            trace = r.get("trace")
            if r["tool"] == "qp-replay-stock":
                key = (trace, "stock")
            elif r.get("engine") == "null":
                key = (trace, "null")
            else:
                key = (trace, "quadtree", r["threads"], r["schedule"], r["depth"], r["threshold"], r["chunk"])
            if r.get("kind") == "run":
                self.runs.setdefault(key, []).append(r)
            elif r.get("kind") == "check":
                (self.stock_checks if r["tool"] == "qp-replay-stock" else self.checks)[
                    trace if r["tool"] == "qp-replay-stock" else key] = r

    def key(self, trace, c):
        return (trace, "quadtree") + cfg_key(c)

    def series(self, key, field):
        return [r[field] for r in self.runs.get(key, [])]

    def step_ms(self, key):
        return med([x * 1e-6 for x in self.series(key, "step_ns")])

    def find_ms(self, key):
        return med([x * 1e-6 for x in self.series(key, "find_ns")])

    def maint_ms(self, key):
        return med([(r["step_ns"] - r["find_ns"]) * 1e-6 for r in self.runs.get(key, [])])

    def replace_ms(self, key):
        return med([r.get("replace_s", 0.0) * 1e3 / max(1, r["steps"]) for r in self.runs.get(key, [])])

    def ns_per_proxy(self, key):
        return med(self.series(key, "ns_per_proxy_step"))

    def first(self, key, field, default=float("nan")):
        runs = self.runs.get(key, [])
        return runs[0].get(field, default) if runs else default

    def reps(self, key):
        return len(self.runs.get(key, []))

    def ratios(self, key_num, key_den, field="step_ns"):
        return round_ratios(self.runs.get(key_num, []), self.runs.get(key_den, []), field)


# ----------------------------------------------------------------------------------------------------------------
# The benchmark
# ----------------------------------------------------------------------------------------------------------------
def plan(args):
    """Jobs: (section, scene, size, warmup, steps, configs, check mode, brute force, ...)."""
    jobs = []
    if args.sections & {"a", "e"}:
        configs = [c for d in args.depths for c in [cfg(1, "static", d)] + [cfg(2, s, d) for s in ("static", "dynamic", "guided")]]
        jobs.append(dict(section="a", scene="particles", size=args.table_size, warmup=args.table_warmup,
                         steps=args.table_steps, configs=configs, check="all", brute=False))
    if args.sections & {"b", "d", "e"}:
        for scene, size, w, s in (("particles", args.particles_size, args.particles_warmup, args.particles_steps),
                                  ("rain", args.rain_size, args.rain_warmup, args.rain_steps)):
            jobs.append(dict(section="b", scene=scene, size=size, warmup=w, steps=s,
                             configs=[cfg(1), cfg(2)] + ([cfg(2, "static")] if DEFAULT["schedule"] != "static" else []),
                             check="all", brute=False))
    if "c" in args.sections:
        for scene in ("rain", "particles"):
            # Threshold 0 (every call parallel) runs in a process of its own, after the others, so its worker
            # thread cannot disturb the 1-thread / 2-thread comparison. Steps of a few µs: 5 runs per round.
            jobs.append(dict(section="c-small", scene=scene, size=args.small_size, warmup=args.small_warmup,
                             steps=args.small_steps, configs=[cfg(1), cfg(2)], separate=[cfg(2, threshold=0)],
                             check="all", brute=True, per_call=True, inner=5))
        for scene, size in (("particles", args.sweep_particles_size), ("bullets", args.sweep_bullets_size)):
            jobs.append(dict(section="c-sweep", scene=scene, size=size, warmup=args.sweep_warmup,
                             steps=args.sweep_steps, configs=[cfg(1)] + [cfg(2, threshold=t) for t in args.thresholds],
                             check="all", brute=size <= 2500, per_call=True))
    return jobs


def main():
    args = parse_args()
    state_path = os.path.join(args.work, "parallel-state.json")
    if args.report_only:
        state = report.read_json(state_path)
        set_defaults(state["info"].get("default_config", ""))
        rows = run.Runner("parallel.py", "", args.work, "parallel", append=True).results()
        report_all(args, state["info"], state["jobs"], Results(rows), state["mismatches"], state["timing"])
        return 1 if any(state["mismatches"].values()) else 0
    t_start = time.time()
    os.makedirs(args.results, exist_ok=True)
    runner = run.Runner("parallel.py", os.path.join(args.build_dir, "bench"), args.work, "parallel",
                        tools=("qp-record", "qp-replay", "qp-replay-stock"), seed=args.seed, rerecord=args.rerecord,
                        wait_quiet=args.wait_quiet, quiet_cpus=args.quiet_cpus, echo=log)
    log(f"parallel.py: work directory {args.work}; {'full' if args.full else 'quick'} version, "
        f"{args.repeats} timed rounds")
    info = machine.describe(args.build_dir)
    info["default_config"] = runner.run("qp-replay", "--print-config")[1].split(" ", 1)[1].strip()
    set_defaults(info["default_config"])
    info["tools"] = runner.run("qp-replay", "--omp-overhead", "--json", runner.jsonl, "--label", "machine")[1] \
        .splitlines()[0].replace("machine: ", "")
    log(f"machine: {info['cpu']}, {info['cores']} CPUs; {info['tools']}")
    jobs = plan(args)

    log("recording traces (quadphase build of Box2D):")
    t0 = time.time()
    for j in jobs:
        j["trace"] = runner.record(j["scene"], j["size"], j["warmup"], j["steps"])
        j["name"] = os.path.basename(j["trace"]).split(".")[0]  # the "trace" field of the JSON lines
        j["display"] = f"{j['scene']} {j['size']}"
    t_record = time.time() - t0

    log("checking pair sets (untimed): stock b2BroadPhase vs quadtree (and brute force on small traces)")
    t0 = time.time()
    mismatches = {}
    for j in jobs:
        stock_hash, quad_hash = j["trace"] + ".stock.hash", j["trace"] + ".quadtree.hash"
        runner.run("qp-replay-stock", "--trace", j["trace"], "--repeats", 0, "--check", "first",
                   "--hashes-out", stock_hash, "--json", runner.jsonl, "--label", j["section"])
        argv = ["--trace", j["trace"], "--repeats", 0, "--check", j["check"], "--compare-hashes", stock_hash,
                "--hashes-out", quad_hash, "--json", runner.jsonl, "--label", j["section"]]
        argv += (["--brute"] if j["brute"] else []) + (["--per-call"] if j.get("per_call") else [])
        for c in j["configs"] + j.get("separate", []):
            argv += ["--config", cfg_arg(c)]
        code, out = runner.run("qp-replay", *argv, ok_codes=(0, 3))
        bad = compare_hash_files(quad_hash, stock_hash)  # the script's own comparison, independent of qp-replay's
        if code == 3 or bad:
            for line in out.splitlines():
                if "MISMATCH" in line:
                    log("    " + line)
        mismatches[j["name"]] = mismatches.get(j["name"], 0) + bad + (1 if code == 3 else 0)
        n_calls = sum(1 for line in open(stock_hash) if not line.startswith("#"))
        log(f"  {j['name']}: {n_calls} UpdatePairs calls, "
            + ("IDENTICAL to stock" if not bad and code == 0 else "*** MISMATCH ***")
            + (" and brute force" if j["brute"] and code == 0 else ""))
    t_check = time.time() - t0
    if any(mismatches.values()):
        log("*" * 80 + "\n*** EXACTNESS MISMATCH against stock Box2D: " + repr(mismatches) + "\n" + "*" * 80)

    for j in jobs:  # replay-loop overhead (null engine), once per trace
        runner.run("qp-replay", "--trace", j["trace"], "--engine", "null", "--repeats", 3, "--json", runner.jsonl,
                   "--label", j["section"])

    log(f"timed rounds ({args.repeats}):")
    t0 = time.time()
    for r in range(args.repeats):
        busy = runner.wait_quiet()
        tr = time.time()
        for j in jobs:
            common = ["--trace", j["trace"], "--repeats", j.get("inner", 1), "--check", "none", "--json",
                      runner.jsonl, "--label", f"{j['section']}|round={r}"]
            runner.run("qp-replay-stock", *common)
            per_call = ["--per-call"] if j.get("per_call") else []
            # The configurations run in a different (seeded) random order in every round, so a burst of other
            # activity on the machine does not always hit the same neighbours.
            order = list(j["configs"])
            random.Random(1000 * r + len(order)).shuffle(order)
            runner.run("qp-replay", *common, *per_call, *[x for c in order for x in ("--config", cfg_arg(c))])
            for c in j.get("separate", []):
                runner.run("qp-replay", *common, "--config", cfg_arg(c), *per_call)
        log(f"  round {r + 1}/{args.repeats}: {time.time() - tr:.0f} s (other processes used {busy:.2f} CPUs "
            f"before it)")
    t_timed = time.time() - t0

    info["loadavg_end"] = open("/proc/loadavg").read().split()[:3]
    info["quiet_samples"] = runner.quiet_samples
    timing = dict(record=t_record, check=t_check, timed=t_timed, total=time.time() - t_start)
    report.write_json(state_path, dict(info=info, jobs=jobs, mismatches=mismatches, timing=timing))
    report_all(args, info, jobs, Results(runner.results()), mismatches, timing)
    return 1 if any(mismatches.values()) else 0


def compare_hash_files(a, b):
    def load(path):
        with open(path) as f:
            return [tuple(line.split()[1:]) for line in f if line.strip() and not line.startswith("#")]
    x, y = load(a), load(b)
    return sum(1 for i in range(max(len(x), len(y))) if i >= len(x) or i >= len(y) or x[i] != y[i])


# ----------------------------------------------------------------------------------------------------------------
# Report
# ----------------------------------------------------------------------------------------------------------------
def rain_floor_steps(n):
    """Steps until the bottom row of rain's spawn grid reaches the floor (scene formulas; drag 1/s, g 10)."""
    width = math.floor(3.0 * math.sqrt(n) + 20.0)
    wall = math.ceil(1.3 * n * 0.75 / width + 5.0)
    y0 = wall + 2.0
    # v(t) = 10 (1 - e^-t) (start speed ~ -1 m/s ignored); fallen distance 10 (t - 1 + e^-t)
    t = 0.0
    while 10.0 * (t - 1.0 + math.exp(-t)) < y0:
        t += 1.0 / 60.0
    return int(round(t * 60.0))


def report_all(args, info, jobs, res, mismatches, timing):
    md = []
    csv_rows = []
    sec = {}
    for j in jobs:
        sec.setdefault(j["section"], []).append(j)

    def csv_add(section, j, engine, c, key):
        csv_rows.append({
            "section": section, "scene": j["scene"], "size": j["size"], "warmup_steps": j["warmup"],
            "timed_steps": j["steps"], "engine": engine,
            "threads": c["threads"] if c else "", "schedule": c["schedule"] if c else "",
            "depth": ("auto" if c["depth"] < 0 else c["depth"]) if c else "",
            "depth_used": res.first(key, "depth_used", "") if engine == "quadtree" else "",
            "threshold": c["threshold"] if c else "",
            "rounds": res.reps(key),
            "ms_per_step": fmt(res.step_ms(key), 4), "find_ms_per_step": fmt(res.find_ms(key), 4),
            "outside_findpairs_ms_per_step": fmt(res.maint_ms(key), 4),
            "replacement_ms_per_step": fmt(res.replace_ms(key), 4) if engine == "quadtree" else "",
            "ns_per_proxy_step": fmt(res.ns_per_proxy(key), 1),
            "mean_proxies": fmt(res.first(key, "mean_proxies"), 0),
            "pairs_per_step": fmt(res.first(key, "pairs_per_step"), 1),
            "updatepairs_calls_per_step": fmt(res.first(key, "calls_per_step"), 2),
            "parallel_regions_per_step": fmt(res.first(key, "parallel_calls", float("nan")) /
                                             max(1, res.first(key, "steps", 1)), 2) if engine == "quadtree" else "",
        })

    info.setdefault("quiet_samples", info.get("quiet", []))
    md.append("# Parallel pair generation: measurements\n")
    md.append("Generated by `bench/parallel.sh" + (" --full" if args.full else "") + "` in one run "
              f"({timing['total'] / 60:.1f} min: recording {timing['record']:.0f} s, exactness checks "
              f"{timing['check']:.0f} s, {args.repeats} timed rounds {timing['timed']:.0f} s). "
              "What every number means: [bench/README.md](../README.md). Raw numbers: "
              "[parallel.csv](parallel.csv).\n")
    if args.note:
        md.append(args.note + "\n")
    md += report.machine_section(info)[:-1]
    md.append(f"- The script waited up to {args.wait_quiet:.0f} s before each timed round for other processes to use "
              f"< {args.quiet_cpus} CPUs (they may have started more work during a round). Every figure is the median "
              "over the rounds; every round ran every configuration (stock included) once, in a different random order.")
    omp = {(o["schedule"], o["blocks"]): o["us"] for o in res.omp}
    if omp:
        md.append("- Cost of one OpenMP parallel region (2 threads, empty loop, regions back to back, so the "
                  "worker is already spinning): " + ", ".join(
                      f"{s} {fmt(omp.get((s, 64)), 1)} µs" for s in ("static", "dynamic", "guided"))
                  + " for 64 iterations; " + f"{fmt(omp.get(('static', 1)), 1)} µs for 1.")
    md.append("")

    # ---------------- exactness ----------------
    md.append("## Exactness\n")
    if any(mismatches.values()):
        md.append("**MISMATCH: the quadtree's pair sets differ from stock Box2D's on "
                  + ", ".join(k for k, v in mismatches.items() if v) + ". These timings are not valid.**\n")
    md.append("Every UpdatePairs call of every trace (warm-up included) was replayed through stock Box2D 2.4.1's "
              "`b2BroadPhase` and through the quadtree; the sorted unique pair sets (in recorded ids) were hashed "
              "and compared call by call, by `qp-replay --compare-hashes` and again by this script; on the small "
              "traces also against `BruteForceBroadPhase`.\n")
    md.append("| trace | UpdatePairs calls | quadtree configurations checked | result |")
    md.append("|---|---|---|---|")
    for j in jobs:
        calls = res.stock_checks.get(j["name"], {}).get("calls_hashed", "–")
        checked = [k for k in res.checks if k[0] == j["name"]]
        md.append(f"| {j['display']} ({j['warmup']} + {j['steps']} steps) | {calls} | {len(checked)}"
                  + (" + brute force" if j["brute"] else "") + " | "
                  + ("**MISMATCH**" if mismatches.get(j["name"]) else "identical") + " |")
    md.append("")

    # ---------------- (a) ----------------
    ja = sec.get("a", [None])[0]
    if ja:
        na = ja["name"]
        rows = [("sequential (1 thread)", 1, "static"), ("static (2 threads)", 2, "static"),
                ("dynamic (2 threads)", 2, "dynamic"), ("guided (2 threads)", 2, "guided")]
        auto_depth = res.first(res.key(na, cfg(1, "static", "auto")), "depth_used", "?")
        md.append(f"## (a) The paper's Tables 1 and 2 on this machine: particles {ja['size']}\n")
        md.append(f"Broadphase work per step, median ms over {args.repeats} rounds ({ja['steps']} timed steps after "
                  f"{ja['warmup']} warm-up steps): all MoveProxy calls plus FindPairs. Lower is better (the paper's "
                  "tables count objects handled within 20 ms: higher is better). Threshold " + str(DEFAULT["threshold"]) + " (the core's default), chunk 0 (OpenMP's "
                  "default), blocks of 64 queries. Bold: the fastest of each row.\n")
        hdr = "| schedule \\ depth | " + " | ".join(
            f"auto (= {auto_depth})" if d == "auto" else d for d in args.depths) + " |"
        for title, field in (("Whole broadphase work, ms/step", "step"), ("FindPairs only, ms/step", "find")):
            md.append(f"**{title}**\n")
            md.append(hdr)
            md.append("|---" * (len(args.depths) + 1) + "|")
            for label, th, sch in rows:
                vals = []
                for d in args.depths:
                    k = res.key(na, cfg(th, sch, d))
                    vals.append(res.step_ms(k) if field == "step" else res.find_ms(k))
                ok = [v for v in vals if not math.isnan(v)]
                best = min(ok) if ok else None
                md.append(f"| {label} | " + " | ".join(
                    (f"**{fmt(v)}**" if v == best else fmt(v)) for v in vals) + " |")
            md.append("")
        for label, th, sch in rows:
            for d in args.depths:
                csv_add("a", ja, "quadtree", cfg(th, sch, d), res.key(na, cfg(th, sch, d)))
        twin = str(auto_depth) if str(auto_depth) in args.depths and "auto" in args.depths else None
        gauge = None
        gauge_find = None
        if twin:
            def spread(ms):  # % between "auto" and its twin depth, per row of the table
                pairs = [(ms(res.key(na, cfg(th, sch, "auto"))), ms(res.key(na, cfg(th, sch, twin))))
                         for _, th, sch in rows]
                return [100.0 * abs(x - y) / min(x, y) for x, y in pairs if not math.isnan(x) and not math.isnan(y)]
            fd, diffs = spread(res.find_ms), spread(res.step_ms)
            gauge_find = max(fd) if fd else None
            if diffs:
                gauge = max(diffs)
                md.append(f"*Noise gauge:* \"auto\" and depth {twin} are the same configuration (same depth, same "
                          f"bounds) measured twice in every round; their medians differ by {fmt(min(diffs), 1)}–"
                          f"{fmt(max(diffs), 1)}% across the four rows in the whole-work table, up to "
                          f"{fmt(gauge_find, 1)}% in the FindPairs table (machine noise, and heap layout: the two "
                          "reach depth {twin} through different rebuilds). Smaller differences are not significant."
                          "\n".replace("{twin}", twin))
        md.append("**Speed-up of 2 threads (static) over 1, per depth** (whole work; FindPairs only): "
                  + ", ".join(
                      f"{d}: {fmt(res.step_ms(res.key(na, cfg(1, 'static', d))) / res.step_ms(res.key(na, cfg(2, 'static', d))))}× "
                      f"({fmt(res.find_ms(res.key(na, cfg(1, 'static', d))) / res.find_ms(res.key(na, cfg(2, 'static', d))))}×)"
                      for d in args.depths) + "\n")
        md.append("**What each depth does** (untimed checking run over the same steps; \"per query\" = per "
                  "buffered proxy, i.e. per proxy whose fat box was replaced this step):\n")
        md.append("| depth | leaf side (m) | leaf cells per proxy | deepest occupied level | cells visited per query "
                  "(approx.) | candidates per query | overlaps per query | pairs per query | queries per step | "
                  "memory (MB) |")
        md.append("|---|---|---|---|---|---|---|---|---|---|")
        shape = {}
        for d in args.depths:
            ck = res.checks.get(res.key(na, cfg(1, "static", d)))
            if not ck:
                continue
            qn = max(1, ck["queries"])
            du = ck["depth_used"]
            levels = ck.get("proxies_per_level", [])
            deepest = max((i for i, c in enumerate(levels) if c > 0), default=0)
            shape[d] = dict(depth=du, cells=ck["cells"] / qn, cand=ck["candidates"] / qn, deepest=deepest,
                            leafcells=4 ** du / max(1, ck["proxies"]), mem=ck["memory_bytes"] / 2 ** 20,
                            leaf=ck["leaf_size"], queries=ck["queries"] / ja["steps"])
            md.append(f"| {d if d != 'auto' else 'auto = ' + str(du)} | {fmt(ck['leaf_size'], 2)} | "
                      f"{fmt(4 ** du / max(1, ck['proxies']), 3)} | {deepest} | {fmt(ck['cells'] / qn, 1)} | "
                      f"{fmt(ck['candidates'] / qn, 1)} | {fmt(ck['overlaps'] / qn, 2)} | {fmt(ck['pairs'] / qn, 2)} | "
                      f"{fmt(ck['queries'] / ja['steps'], 0)} | {fmt(ck['memory_bytes'] / 2 ** 20, 1)} |")
        md.append("")
        md.append("The paper's Tables 1 and 2 (objects handled within 20 ms; **higher** is better; bold: the best of "
                  "each row). Its quadtree was rebuilt every frame and its threads appended to one shared, "
                  "lock-protected vector:\n")
        for cpu, t in paper.TABLES.items():
            md += table([cpu] + [str(d) for d in paper.DEPTHS], [[row] + [f"**{v}**" if v == max(vals) else str(v)
                                                                    for v in vals] for row, vals in t.items()])
            md.append("")
        md.append(analysis_a(res, na, args.depths, shape, omp, gauge, gauge_find))

    # ---------------- (b) ----------------
    amdahl_rows = []
    static_rows = []
    if sec.get("b"):
        md.append("## (b) Speed-up of 2 threads over 1 on the broadphase work\n")
        notes = []
        for j in sec["b"]:
            note = f"{j['display']}: {j['warmup']} warm-up steps (untimed), then {j['steps']} timed steps"
            if j["scene"] == "rain":
                fl = rain_floor_steps(j["size"])
                note += (f" — the bodies are still falling (the bottom row of the spawn grid reaches the floor "
                         f"after about {fl} steps, so no pile yet and no time-of-impact events)"
                         if j["warmup"] + j["steps"] < fl else
                         f" — the pile is forming (the bottom row reaches the floor after about {fl} steps)")
            notes.append(note)
        md.append("Replays of recorded steps: " + "; ".join(notes) + ". " + DEFAULT["schedule"].capitalize() + " schedule (the core's default), automatic depth, threshold "
                  f"{DEFAULT['threshold']} (the core's default). **Outside** = whole − FindPairs: the time in the "
                  "MoveProxy/CreateProxy/DestroyProxy/TouchProxy calls (Box2D makes them one at a time; its adapter "
                  "queues moves: a serial append, plus, every 8192 moves, the fat-box tests and in-cell rewrites of "
                  "the queued moves, which run on all threads), plus the replay loop's own overhead (the null engine "
                  "of (d)). **Grid maintenance**: the time the core books as Stats::updateSeconds, inside and "
                  "outside FindPairs: applying the queued moves (fat-box tests and in-cell rewrites: the chunk "
                  "applies during the moves, the last chunk inside FindPairs; on all threads) and re-placing the "
                  "proxies that changed cell (inside FindPairs, on one thread). Speed-up = median(1 thread) / median(2 threads); in brackets the range of the per-round "
                  "ratios (each round ran both).\n")
        md.append("| trace | proxies | 1 thread: ms/step = FindPairs + outside | 2 threads: ms/step = "
                  "FindPairs + outside | FindPairs speed-up | grid maintenance, ms/step: 1 → 2 threads | whole-work "
                  "speed-up | outside share at 1 thread (m) | serial fraction, whole (Karp–Flatt) | serial fraction, "
                  "FindPairs (Karp–Flatt, e_F) |")
        md.append("|---|---|---|---|---|---|---|---|---|---|")
        for j in sec["b"]:
            n = j["name"]
            k1, k2 = res.key(n, cfg(1)), res.key(n, cfg(2))
            t1, t2 = res.step_ms(k1), res.step_ms(k2)
            f1, f2 = res.find_ms(k1), res.find_ms(k2)
            m1, m2 = res.maint_ms(k1), res.maint_ms(k2)
            sw, sf = t1 / t2, f1 / f2
            rr = res.ratios(k1, k2)
            rf = res.ratios(k1, k2, "find_ns")
            ew, ef = karp_flatt(sw), karp_flatt(sf)
            share = m1 / t1
            ck = res.checks.get(k1, {})
            amdahl_rows.append(dict(name=j["display"], t1=t1, t2=t2, f1=f1, f2=f2, m1=m1, m2=m2, sw=sw, sf=sf,
                                    ew=ew, ef=ef, share=share,
                                    buffered=ck.get("max_buffered"),
                                    proxies=res.first(k1, "mean_proxies")))
            r1, r2 = res.replace_ms(k1), res.replace_ms(k2)
            amdahl_rows[-1].update(r1=r1, r2=r2, loop=res.step_ms((n, "null")))
            md.append(f"| {j['display']} | {fmt(res.first(k1, 'mean_proxies'), 0)} | {fmt(t1)} = {fmt(f1)} "
                      f"+ {fmt(m1)} | {fmt(t2)} = {fmt(f2)} + {fmt(m2)} | **{fmt(sf)}×** "
                      f"({fmt(min(rf) if rf else None)}–{fmt(max(rf) if rf else None)}) | "
                      f"{fmt(r1)} → {fmt(r2)} ({fmt(r1 / r2) + '×' if r1 > 0 and r2 > 0 else '–'}) | **{fmt(sw)}×** "
                      f"({fmt(min(rr) if rr else None)}–{fmt(max(rr) if rr else None)}) | {fmt(100 * share, 0)}% | "
                      f"{fmt(ew, 2)} | {fmt(ef, 2)} |")
            csv_add("b", j, "quadtree", cfg(1), k1)
            csv_add("b", j, "quadtree", cfg(2), k2)
            ks = res.key(n, cfg(2, "static"))
            if DEFAULT["schedule"] != "static" and not math.isnan(res.step_ms(ks)):
                csv_add("b", j, "quadtree", cfg(2, "static"), ks)
                rs = res.ratios(ks, k2)
                static_rows.append(f"{j['display']}: static {fmt(res.step_ms(ks))} ms/step (FindPairs "
                                   f"{fmt(res.find_ms(ks))}) against {DEFAULT['schedule']} {fmt(t2)} ({fmt(f2)}); "
                                   f"per round, static / {DEFAULT['schedule']} = {fmt(statistics.median(rs) if rs else None)} "
                                   f"({fmt(min(rs) if rs else None)}–{fmt(max(rs) if rs else None)})")
        md.append("")
        if static_rows:
            md.append(f"The same traces at 2 threads under the static schedule (the default before it became "
                      f"{DEFAULT['schedule']}; same rounds): " + "; ".join(static_rows) + ". Static hands each thread "
                      "one contiguous half of the move buffer; when the halves' queries cost unequally (on rain, "
                      "timed per thread with static: one thread's share took 20–25% longer), the other thread "
                      "waits at the loop's end, while guided's shrinking chunks even the halves out.\n")
        md.append(analysis_b(amdahl_rows))

    # ---------------- (c) ----------------
    smalls, sweeps = sec.get("c-small", []), sec.get("c-sweep", [])
    if smalls or sweeps:
        md.append("## (c) Small scenes and the parallel threshold\n")
    if smalls:
        md.append(f"Scenes of {args.small_size} bodies ({args.small_steps} timed steps after {args.small_warmup} "
                  f"warm-up steps; {smalls[0].get('inner', 1)} runs per round, so the medians are over "
                  f"{smalls[0].get('inner', 1) * args.repeats} runs), at the core's default threshold (" + str(DEFAULT["threshold"]) + "): 2 threads must not be "
                  "slower than 1.\n")
        md.append("| trace | 1 thread µs/step | 2 threads µs/step | 2 threads / 1 thread | largest UpdatePairs call "
                  "(buffered proxies) | parallel regions opened | for comparison: 2 threads, threshold 0 |")
        md.append("|---|---|---|---|---|---|---|")
        for j in smalls:
            n = j["name"]
            k1, k2, k0 = res.key(n, cfg(1)), res.key(n, cfg(2)), res.key(n, cfg(2, threshold=0))
            ck = res.checks.get(k1, {})
            rr = res.ratios(k2, k1)
            md.append(f"| {j['display']} | {fmt(res.step_ms(k1) * 1e3, 1)} | {fmt(res.step_ms(k2) * 1e3, 1)} | "
                      f"**{fmt(res.step_ms(k2) / res.step_ms(k1), 3)}** (rounds {fmt(min(rr) if rr else None, 3)}–"
                      f"{fmt(max(rr) if rr else None, 3)}) | {ck.get('max_buffered', '–')} | "
                      f"{int(res.first(k2, 'parallel_calls', 0))} | "
                      f"{fmt(res.step_ms(k0) * 1e3, 1)} µs/step ({fmt(res.step_ms(k0) / res.step_ms(k1), 2)}×) |")
            csv_add("c-small", j, "quadtree", cfg(1), k1)
            csv_add("c-small", j, "quadtree", cfg(2), k2)
            csv_add("c-small", j, "quadtree", cfg(2, threshold=0), k0)
        md.append("")
    if sweeps:
        md.append(f"Threshold sweep at 2 threads ({DEFAULT['schedule']} schedule, automatic depth). Each cell: ms/step (FindPairs "
                  "only), speed-up over 1 thread, parallel regions opened per step. Median over the rounds.\n")
        md.append("| threshold | " + " | ".join(
            f"{j['display']} ({j['warmup']} + {j['steps']} steps)" for j in sweeps) + " |")
        md.append("|---" * (len(sweeps) + 1) + "|")
        md.append("| 1 thread (reference) | " + " | ".join(
            f"{fmt(res.step_ms(res.key(j['name'], cfg(1))), 3)} ({fmt(res.find_ms(res.key(j['name'], cfg(1))), 3)})"
            for j in sweeps) + " |")
        for t in args.thresholds:
            cells = []
            for j in sweeps:
                k = res.key(j["name"], cfg(2, threshold=t))
                ref = res.step_ms(res.key(j["name"], cfg(1)))
                pc = res.first(k, "parallel_calls", float("nan")) / max(1, res.first(k, "steps", 1))
                cells.append(f"{fmt(res.step_ms(k), 3)} ({fmt(res.find_ms(k), 3)}); ×{fmt(ref / res.step_ms(k), 2)}; "
                             f"{fmt(pc, 1)}")
            md.append(f"| {t}{' (default)' if t == DEFAULT['threshold'] else ''} | " + " | ".join(cells) + " |")
        md.append("")
        for j in sweeps:
            csv_add("c-sweep", j, "quadtree", cfg(1), res.key(j["name"], cfg(1)))
            for t in args.thresholds:
                csv_add("c-sweep", j, "quadtree", cfg(2, threshold=t), res.key(j["name"], cfg(2, threshold=t)))
        md.append("UpdatePairs calls per timed step, by buffered proxies per call:\n")
        ck0 = res.checks.get(res.key(sweeps[0]["name"], cfg(1)), {})
        edges = ck0.get("bucket_edges", [0, 1, 64, 128, 256, 512, 1024, 4096])
        labels = []
        for i, e in enumerate(edges):
            if i + 1 < len(edges):
                labels.append(str(e) if edges[i + 1] - 1 == e else f"{e}–{edges[i + 1] - 1}")
            else:
                labels.append(f"≥ {e}")
        md.append("| trace | " + " | ".join(labels) + " | largest |")
        md.append("|---" * (len(labels) + 2) + "|")
        for j in sweeps:
            ck = res.checks.get(res.key(j["name"], cfg(1)), {})
            md.append(f"| {j['display']} | " + " | ".join(fmt(c / j["steps"], 2) for c in ck.get("bucket_calls", []))
                      + f" | {ck.get('max_buffered', '–')} |")
        md.append("")
    per_call = []
    for j in smalls + sweeps:
        t = per_call_table(res, j)
        if t:
            per_call.append((j, t))
    if per_call:
        md.append("**Where a parallel region starts paying, call by call.** Every UpdatePairs call of the timed "
                  "steps, timed alone and grouped by its number of buffered proxies (known from the checking run): "
                  "median µs per call at 1 thread (serial) and at 2 threads with threshold 0 (every call parallel), "
                  "pooled over the rounds. Forced-parallel calls come in quick succession here, so the worker thread "
                  "is usually still spinning; an isolated parallel call (the main call of a step, milliseconds of serial "
                  "MoveProxy work after the previous region) also pays to wake the worker.\n")
        md.append("| trace | buffered proxies per call | calls per step | serial µs/call | parallel µs/call | "
                  "serial / parallel |")
        md.append("|---|---|---|---|---|---|")
        for j, t in per_call:
            for row in t["rows"]:
                md.append(f"| {j['display']} | {row['label']} | {fmt(row['per_step'], 2)} | {fmt(row['serial'], 1)} | "
                          f"{fmt(row['parallel'], 1)} | {fmt(row['ratio'], 2)} |")
        md.append("")
    if smalls or sweeps:
        md.append(analysis_c(res, sweeps, smalls, args.thresholds, omp, per_call))

    # ---------------- (d) ----------------
    if "d" in args.sections:
        md.append("## (d) Stock Box2D 2.4.1 `b2BroadPhase` on the same traces\n")
        md.append("Same replay, same timing definition. ns per proxy per step = time per step / live proxies. "
                  "Ratio = stock time / quadtree time (higher: the quadtree is faster). Replay overhead = the null "
                  "engine (op dispatch and id map only); it is included in every figure.\n")
        md.append("| trace | proxies | stock ns/proxy/step | quadtree, 1 thread | quadtree, 2 threads | stock / "
                  "quadtree (1 thread) | stock / quadtree (2 threads) | replay overhead ns/proxy/step |")
        md.append("|---|---|---|---|---|---|---|---|")
        for j in jobs:
            n = j["name"]
            ks = (n, "stock")
            k1, k2 = res.key(n, cfg(1)), res.key(n, cfg(2))
            s, q1, q2 = res.ns_per_proxy(ks), res.ns_per_proxy(k1), res.ns_per_proxy(k2)
            null = res.ns_per_proxy((n, "null"))
            md.append(f"| {j['display']} ({j['warmup']} + {j['steps']} steps) | {fmt(res.first(ks, 'mean_proxies'), 0)} "
                      f"| {fmt(s, 1)} | {fmt(q1, 1)} | {fmt(q2, 1)} | **{fmt(s / q1, 1)}×** | **{fmt(s / q2, 1)}×** | "
                      f"{fmt(null, 1)} |")
            csv_add("d", j, "stock", None, ks)
            csv_add("d", j, "null", None, (n, "null"))
        md.append("")

    # ---------------- (e) ----------------
    if "e" in args.sections and amdahl_rows:
        png = os.path.join(args.results, "parallel.png")
        drew = figure(png, res, args, amdahl_rows, ja)
        md.append("## (e) Scaling to 16 cores: a projection\n")
        if drew:
            md.append("![left: table (a) measured; right: projected speed-up](parallel.png)\n")
        md.append(analysis_e(amdahl_rows))

    report.write_lines(os.path.join(args.results, "parallel.md"), md)
    report.write_csv(os.path.join(args.results, "parallel.csv"), csv_rows)
    log(f"wrote {os.path.join(args.results, 'parallel.md')}, parallel.csv"
        + (", parallel.png" if "e" in args.sections else "") + f" ({timing['total'] / 60:.1f} min in all)")


# ----------------------------------------------------------------------------------------------------------------
# Written analysis: every number in it comes from this run
# ----------------------------------------------------------------------------------------------------------------
def pct(a, b):
    return 100.0 * (a / b - 1.0)


def analysis_a(res, na, depths, shape, omp, gauge, gauge_find):
    out = ["**Which wins, and why.**\n"]
    grid = {}
    for th, sch in ((1, "static"), (2, "static"), (2, "dynamic"), (2, "guided")):
        for d in depths:
            grid[(th, sch, d)] = res.step_ms(res.key(na, cfg(th, sch, d)))
    valid = {k: v for k, v in grid.items() if not math.isnan(v)}
    if not valid:
        return ""
    best = min(valid, key=valid.get)
    seq = {d: grid[(1, "static", d)] for d in depths if not math.isnan(grid[(1, "static", d)])}
    seq_best = min(seq, key=seq.get)
    fixed = [d for d in depths if d != "auto" and d in shape]
    auto_d = shape.get("auto", {}).get("depth", "?")
    def name(k):
        return ("sequential" if k[0] == 1 else f"{k[1]}") + f" depth {k[2]}"

    tol = 1.0 + (gauge if gauge is not None else 10.0) / 100.0
    close = sorted((k for k in valid if valid[k] <= valid[best] * tol), key=valid.get)
    fgrid = {k: res.find_ms(res.key(na, cfg(k[0], k[1], k[2]))) for k in grid}
    fvalid = {k: v for k, v in fgrid.items() if not math.isnan(v)}
    fbest = min(fvalid, key=fvalid.get)
    ftol = 1.0 + (gauge_find if gauge_find is not None else 10.0) / 100.0
    fclose = sorted((k for k in fvalid if fvalid[k] <= fvalid[fbest] * ftol), key=fvalid.get)
    out.append(f"- **Fastest, whole work:** {name(best)}"
               f"{' (= ' + str(auto_d) + ')' if best[2] == 'auto' else ''} at {fmt(valid[best])} ms/step; within the "
               f"noise gauge of it: {', '.join(name(k) for k in close[1:]) or 'nothing else'}. "
               f"**FindPairs only** (where the schedule acts; less noisy, because the serial MoveProxy part, "
               f"the noisiest, is left out): {name(fbest)} at {fmt(fvalid[fbest])} ms/step; within its gauge: "
               f"{', '.join(name(k) for k in fclose[1:]) or 'nothing else'}. Fastest sequential: depth {seq_best}"
               f"{' (= ' + str(auto_d) + ')' if seq_best == 'auto' else ''}, {fmt(seq[seq_best])} ms/step. The "
               f"automatic depth picks {auto_d}.")
    if fixed:
        lo, hi = fixed[0], fixed[-1]
        s_lo, s_hi = shape[lo], shape[hi]
        out.append(f"- **Depth** sets the work per query. At depth {lo} (leaf {fmt(s_lo['leaf'], 1)} m, "
                   f"{fmt(s_lo['leafcells'], 2)} leaf cells per proxy) a query visits {fmt(s_lo['cells'], 1)} cells "
                   f"but tests {fmt(s_lo['cand'], 0)} candidates for about one pair: candidate tests dominate. Each "
                   "level deeper divides the candidates until the leaf is about the size of a fat box.")
        tol = 1.0 + (gauge if gauge is not None else 10.0) / 100.0
        seq_fixed = {d: seq[d] for d in fixed if d in seq}
        if seq_fixed:
            m = min(seq_fixed.values())
            good = [d for d in fixed if d in seq_fixed and seq_fixed[d] <= m * tol]
            out.append(f"  Sequentially, " + (f"depths {', '.join(good)} are" if len(good) > 1 else f"only depth {good[0]} is")
                       + " within the noise of the fastest fixed depth: "
                       + "; ".join(f"depth {d}: leaf {fmt(shape[d]['leaf'], 2)} m, {fmt(shape[d]['cells'], 1)} cells "
                                   f"and {fmt(shape[d]['cand'], 1)} candidates per query, {fmt(shape[d]['mem'], 1)} MB"
                                   for d in good)
                       + f". Deeper still (depth {hi}: {fmt(s_hi['cells'], 1)} cells per query, "
                       f"{fmt(s_hi['leafcells'], 1)} leaf cells per proxy, {fmt(s_hi['mem'], 1)} MB) the candidates "
                       "barely fall while the cells visited and the memory (24 B per cell, empty or not; the caches "
                       "here are 2 MB of L2 per core) grow.")
        sat = None
        for d in fixed:
            if shape[d]["deepest"] < shape[d]["depth"]:
                sat = d
                break
        if sat is not None:
            out.append(f"  From depth {sat} on, the proxies all live at level {shape[sat]['deepest']} or above (a "
                       "proxy is stored at the deepest level where its box spans at most two cells per axis), so "
                       "the deeper levels stay empty and queries see the same candidates "
                       f"({fmt(shape[sat]['cand'], 1)} per query); only the cell array grows — "
                       + (f"{fmt(shape[sat]['mem'], 1)} MB at depth {sat}, " if sat != hi else "")
                       + f"{fmt(s_hi['mem'], 1)} MB at depth {hi} "
                       f"({fmt(s_hi['leafcells'], 1)} leaf cells per proxy, 24 B each even when empty) — which costs "
                       "cache and the rebuilds' time. The times flatten or rise accordingly.")

    # schedules
    spreads, wins = [], {}
    for d in depths:
        col = {s: fgrid[(2, s, d)] for s in ("static", "dynamic", "guided") if not math.isnan(fgrid[(2, s, d)])}
        if len(col) == 3:
            w = min(col, key=col.get)
            wins[w] = wins.get(w, 0) + 1
            spreads.append(pct(max(col.values()), min(col.values())))
    if spreads:
        per_sched = {sch: med([pct(fgrid[(2, sch, d)], min(fgrid[(2, x, d)] for x in ("static", "dynamic", "guided")))
                               for d in depths]) for sch in ("static", "dynamic", "guided")}
        d4 = depths[0]
        col4 = {x: fgrid[(2, x, d4)] for x in ("static", "dynamic", "guided")}
        margin4 = pct(col4["static"], min(col4.values()))
        static_ok = per_sched["static"] <= min(per_sched.values()) + (gauge_find or 0.0)
        out.append(f"- **Schedule** (FindPairs table): the fastest 2-thread schedule per depth column is "
                   + ", ".join(f"{k} in {v}" for k, v in sorted(wins.items(), key=lambda kv: -kv[1]))
                   + f" of {len(spreads)} columns; median distance to the column's fastest: "
                   + ", ".join(f"{k} {fmt(v, 1)}%" for k, v in per_sched.items())
                   + (f" (noise gauge {fmt(gauge_find, 1)}%)" if gauge_find is not None else "")
                   + f". At depth {d4} the fastest is {min(col4, key=col4.get)} (static {fmt(margin4, 1)}% slower)"
                   + (" — as in the paper, the one column where dynamic scheduling helped on the i7: with "
                      f"{fmt(shape[d4]['cand'], 0)} candidates per query the queries' costs vary with their cells' "
                      "crowding, and a dynamic hand-out of blocks evens that out" if min(col4, key=col4.get) != "static"
                      and d4 in shape else "")
                   + (". Elsewhere the blocks of 64 queries cost alike (the buffered proxies, in move-buffer order, "
                      "are spread evenly over the box), so static scheduling is already balanced and dynamic/guided "
                      "only add a shared-counter hand-off per block"
                      if static_ok else
                      ". Static is outside the noise gauge of the fastest here: even on this evenly spread scene the "
                      "two contiguous halves it hands out do not cost exactly alike, and guided's shrinking chunks "
                      "even out the rest, for a hand-off that costs little more than static's")
                   + (f" (an empty 64-iteration loop: static {fmt(omp.get(('static', 64)), 1)} µs, dynamic "
                      f"{fmt(omp.get(('dynamic', 64)), 1)} µs, guided {fmt(omp.get(('guided', 64)), 1)} µs)"
                      if omp else "")
                   + (". The paper saw the same (static ≥ dynamic except at depth 4 on the i7) for the same reason: "
                      "near-equal iterations. " if static_ok else
                      ". Dynamic, which hands out one block at a time, pays its per-block hand-off and trails. ")
                   + (f"The default, {DEFAULT['schedule']}, is within the noise gauge of the fastest here"
                      if per_sched.get(DEFAULT["schedule"], float("inf")) <= min(per_sched.values())
                      + (gauge_find or 0.0) else
                      f"The default, {DEFAULT['schedule']}, is {fmt(per_sched.get(DEFAULT['schedule']), 1)}% from "
                      "the fastest here")
                   + "; it is the default rather than static because its shrinking chunks also even out traces "
                   "whose queries do not cost alike: rain, where static leaves one thread waiting (see the static "
                   "runs under the table of (b)).")
    sp = []
    for d in depths:
        a, b = grid[(1, "static", d)], grid[(2, "static", d)]
        if not math.isnan(a) and not math.isnan(b):
            sp.append((d, a / b))
    fs = [fgrid[(1, "static", d)] / fgrid[(2, "static", d)] for d in depths
          if not math.isnan(fgrid[(1, "static", d)]) and not math.isnan(fgrid[(2, "static", d)])]
    ms = [grid[(1, "static", d)] - fgrid[(1, "static", d)] for d in depths
          if not math.isnan(grid[(1, "static", d)]) and not math.isnan(fgrid[(1, "static", d)])]
    if sp and fs and ms:
        faster = [d for d, x in sp if x > 1.0]
        out.append(f"- **2 threads vs 1:** static at 2 threads is faster than sequential at {len(faster)} of "
                   f"{len(sp)} depths (speed-ups {fmt(min(x for _, x in sp))}–{fmt(max(x for _, x in sp))}×). In the "
                   "paper, the parallel versions lost to sequential at the shallow depths (they looped over leaf "
                   "boxes, few iterations there, and serialised on a lock around the shared output) and won only at "
                   "depth 8–9 on the 2-core i7. Here the loop is over buffered proxies, whatever the depth, and each "
                   "block writes its own vector, so the parallel part does not depend on depth. FindPairs alone "
                   f"speeds up {fmt(min(fs), 2)}–{fmt(max(fs), 2)}× at every depth; the whole work less, the more so the "
                   "smaller FindPairs' share of the step: the serial work outside UpdatePairs (the MoveProxy calls) "
                   f"costs about the same at every depth (1 thread: {fmt(min(ms), 1)}–{fmt(max(ms), 1)} ms/step) — "
                   "see (b).")
    return "\n".join(out) + "\n"


def analysis_b(rows):
    out = []
    for r in rows:
        cap2 = amdahl(r["share"], 2)
        rep = ""
        if r.get("r1", 0) > 0:
            rep = (f" Grid maintenance (inside and outside FindPairs) went {fmt(r['r1'])} → {fmt(r['r2'])} ms "
                   f"({fmt(r['r1'] / r['r2']) if r['r2'] > 0 else '–'}×).")
        loop = r.get("loop", float("nan"))
        net = ""
        if not math.isnan(loop) and r["t2"] > loop:
            # The replay loop stands in for Box2D's own body loop: it is not broadphase work, and it is serial.
            net = (f" Less the replay loop's own {fmt(loop, 2)} ms per step (the null engine of (d), run once "
                   f"before the rounds), the broadphase's calls alone went {fmt(r['t1'] - loop)} → "
                   f"{fmt(r['t2'] - loop)} ms ({fmt((r['t1'] - loop) / (r['t2'] - loop))}×).")
        out.append(f"- **{r['name']}**: FindPairs {fmt(r['f1'])} → {fmt(r['f2'])} ms ({fmt(r['sf'])}×); whole work "
                   f"{fmt(r['t1'])} → {fmt(r['t2'])} ms ({fmt(r['sw'])}×).{net}{rep} The work outside UpdatePairs "
                   f"(the MoveProxy calls) is m = {fmt(100 * r['share'], 0)}% of the 1-thread step and went "
                   f"{fmt(r['m1'])} → {fmt(r['m2'])} ms: the queued moves' chunk applies inside "
                   f"it run on both threads, the appends and the replay loop do not. Had it all stayed serial, even a "
                   f"perfect FindPairs speed-up would give only {fmt(cap2)}× at 2 threads. The measured "
                   f"serial fraction (Karp–Flatt, e = 2/S − 1) is {fmt(r['ew'], 2)} for the whole work and "
                   f"{fmt(r['ef'], 2)} for FindPairs alone (its serial parts — move-buffer hand-off, join"
                   + (", the re-placement of cell changes (one thread; see docs/design.md)" if r.get("r1", 0) > 0 else "")
                   + " — the memory stalls both cores share, and the shared machine's noise).")
    out.append("")
    return "\n".join(out)


CALL_BUCKETS = [0, 1, 16, 64, 128, 256, 512, 1024, 2048, 4096]


def call_bucket(n):
    b = 0
    while b + 1 < len(CALL_BUCKETS) and n >= CALL_BUCKETS[b + 1]:
        b += 1
    return b


def bucket_label(b):
    lo = CALL_BUCKETS[b]
    if b + 1 >= len(CALL_BUCKETS):
        return f"≥ {lo}"
    hi = CALL_BUCKETS[b + 1] - 1
    return str(lo) if hi == lo else f"{lo}–{hi}"


def per_call_table(res, j):
    """Per-call FindPairs times by size class: serial (1 thread) vs forced parallel (2 threads, threshold 0)."""
    ck = res.checks.get(res.key(j["name"], cfg(1)))
    sizes = ck.get("calls_buffered") if ck else None
    if not sizes:
        return None

    def pooled(c):
        buckets = [[] for _ in CALL_BUCKETS]
        for run in res.runs.get(res.key(j["name"], c), []):
            ns = run.get("calls_ns")
            if not ns or len(ns) != len(sizes):
                continue
            for n, t in zip(sizes, ns):
                buckets[call_bucket(n)].append(t)
        return buckets

    serial, parallel = pooled(cfg(1)), pooled(cfg(2, threshold=0))
    counts = [0] * len(CALL_BUCKETS)
    for n in sizes:
        counts[call_bucket(n)] += 1
    rows = []
    for b in range(len(CALL_BUCKETS)):
        if counts[b] == 0 or not serial[b] or not parallel[b]:
            continue
        sm, pm = med(serial[b]) * 1e-3, med(parallel[b]) * 1e-3
        rows.append(dict(bucket=b, label=bucket_label(b), per_step=counts[b] / j["steps"], serial=sm, parallel=pm,
                         ratio=sm / pm if pm > 0 else float("nan")))
    return dict(rows=rows)


def analysis_c(res, sweeps, smalls, thresholds, omp, per_call):
    out = []
    # Call by call: the largest size class where a parallel call loses, the smallest where it wins.
    lose_hi, win_lo = None, None
    for j, t in per_call:
        for row in t["rows"]:
            if CALL_BUCKETS[row["bucket"]] == 0:
                continue  # empty calls: no queries at all
            edge_hi = CALL_BUCKETS[row["bucket"] + 1] if row["bucket"] + 1 < len(CALL_BUCKETS) else None
            # a class wins or loses only beyond ±5%; in between it is a tie
            if row["ratio"] < 1.05 and edge_hi is not None:
                lose_hi = edge_hi if lose_hi is None else max(lose_hi, edge_hi)
            if row["ratio"] > 1.05:
                lo = CALL_BUCKETS[row["bucket"]]
                win_lo = lo if win_lo is None else min(win_lo, lo)
    if per_call:
        out.append("- Call by call (a size class wins or loses beyond ±5%): "
                   + (f"the largest size class where a parallel call does not win ends at {lose_hi - 1} buffered "
                      "proxies" if lose_hi else "no size class where a parallel call loses")
                   + "; " + (f"the smallest size class where it wins starts at {win_lo}" if win_lo is not None
                             else "no size class where it wins") + ".")
    small_calls = []
    for j in sweeps:
        ck = res.checks.get(res.key(j["name"], cfg(1)), {})
        edges, calls = ck.get("bucket_edges", []), ck.get("bucket_calls", [])
        if edges and calls:
            big = sum(c for e, c in zip(edges, calls) if e >= 64) / j["steps"]
            few = sum(c for e, c in zip(edges, calls) if 0 < e < 64) / j["steps"]
            small_calls.append(f"{j['display']}: {fmt(few, 1)} calls per step with 1–63 buffered proxies, "
                               f"{fmt(big, 1)} with 64 or more")
    rel = {t: [] for t in thresholds}
    for j in sweeps:
        n = j["name"]
        ref = res.step_ms(res.key(n, cfg(1)))
        vals = {t: res.step_ms(res.key(n, cfg(2, threshold=t))) for t in thresholds}
        vals = {t: v for t, v in vals.items() if not math.isnan(v)}
        if not vals:
            continue
        best = min(vals, key=vals.get)
        for t, v in vals.items():
            rel[t].append(v / vals[best])
        first_par = None
        for t in sorted(vals):
            k = res.key(n, cfg(2, threshold=t))
            if res.first(k, "parallel_calls", 0) == 0:
                first_par = t
                break
        out.append(f"- {j['display']}: fastest at threshold {best} ({fmt(vals[best], 3)} ms/step, "
                   f"{fmt(ref / vals[best], 2)}× the 1-thread time); threshold 0 (a parallel region for every call) "
                   f"{fmt(vals.get(0), 3)} ms/step ({fmt(ref / vals[0], 2) if 0 in vals else '–'}×); 512: "
                   f"{fmt(vals.get(512), 3)} ms/step ({fmt(pct(vals[512], vals[best]), 1) if 512 in vals else '–'}% "
                   "from the fastest)" + (f"; from threshold {first_par} on, no call is parallel" if first_par is not None
                                          else "") + ".")
    score = {t: math.exp(sum(math.log(x) for x in v) / len(v)) for t, v in rel.items() if v}
    # Thresholds that make exactly the same calls parallel on every sweep scene behave identically: group them.
    groups = {}
    for t in thresholds:
        sig = tuple(res.first(res.key(j["name"], cfg(2, threshold=t)), "parallel_calls", -1) for j in sweeps)
        groups.setdefault(sig, []).append(t)
    same = [g for g in groups.values() if len(g) > 1]
    if same:
        out.append("- Thresholds " + "; ".join(", ".join(str(t) for t in g) for g in same)
                   + (" make" if len(same) > 1 else " make") + " exactly the same calls parallel on these scenes "
                   "(same number of parallel regions), so the differences within each group are noise.")
    if score:
        best_t = min(score, key=score.get)
        near = sorted(t for t, v in score.items() if v <= score[best_t] * 1.03)
        out.append("")
        out.append("Geometric mean over the sweep scenes of (time / that scene's fastest threshold): "
                   + ", ".join(f"{t}: {fmt(score[t], 3)}" for t in sorted(score)) + ". "
                   f"Lowest: {best_t}; within 3% of it: {', '.join(str(t) for t in near)}.")
        dflt = DEFAULT["threshold"]
        rec = dflt if dflt in near else best_t
        # Within the best group of equivalent thresholds, take the smallest one that keeps every size class where
        # a parallel call did not win serial.
        best_group = next((g for g in groups.values() if best_t in g), [best_t])
        if lose_hi is not None:
            ok = [t for t in sorted(best_group) if t >= lose_hi]
            if ok:
                rec = ok[0] if dflt not in near else dflt
            else:
                above = [t for t in sorted(score) if t >= lose_hi]
                rec = above[0] if above else rec
        out.append("")
        why = ""
        if rec in best_group and len(best_group) > 1:
            why = (f"Thresholds {', '.join(str(t) for t in sorted(best_group))} make the same calls parallel as the "
                   f"fastest ({best_t}) on the sweep scenes; {rec} is the smallest of them that keeps serial every "
                   "size class where a parallel call did not win. ")
        elif rec == best_t:
            why = "It is the fastest in the sweep. "
        elif rec in near:
            why = f"It is within 3% of the fastest ({best_t}) in the sweep. "
        out.append(f"**Recommendation: parallelThreshold = {rec}"
                   + (" (the core's current default)" if rec == dflt else f" (the core's default is {dflt})")
                   + ".** " + why
                   + (f"Against 512, the old default: {fmt(score[rec] / score[512], 3)}× the time (geometric mean "
                      "over the sweep scenes). " if 512 in score and rec != 512 else "")
                   + "A parallel region costs "
                   + (f"{fmt(omp.get(('static', 1)), 1)} µs " if omp else "a few µs ")
                   + "when the worker thread is still spinning, more when it has gone to sleep or another process "
                   "holds its core; a query costs from tens of ns (particles) to hundreds (bullets, whose piles and "
                   "arena walls give more candidates), so the break-even call size depends on the scene"
                   + (f" — measured above: the largest size class where a parallel call does not win ends at "
                      f"{lose_hi - 1} buffered proxies" if lose_hi else "")
                   + (f", the smallest where it wins starts at {win_lo}" if win_lo is not None else "")
                   + ". The threshold must keep the many small calls serial (" + "; ".join(small_calls)
                   + ") and should let the main call of a mid-size scene (hundreds of buffered proxies) go "
                   "parallel.")
    if smalls:
        worst = max(res.step_ms(res.key(j["name"], cfg(2))) / res.step_ms(res.key(j["name"], cfg(1))) for j in smalls)
        regions = sum(res.first(res.key(j["name"], cfg(2)), "parallel_calls", 0) for j in smalls)
        out.append("")
        out.append(f"On the {smalls[0]['size']}-body scenes at the default threshold, 2 threads take at most "
                   f"{fmt(worst, 3)}× the 1-thread time"
                   + (": no parallel region is opened (every call is under the threshold), so the code run is the "
                      "same and the difference is noise." if regions == 0 else
                      f"; {regions} parallel regions were opened."))
    out.append("")
    return "\n".join(out)


def serial_fractions(r):
    """(s as measured, s if the outside work were parallel) from m and FindPairs' Karp-Flatt fraction."""
    m = min(max(r["share"], 0.0), 1.0)
    ef = min(max(r["ef"], 0.0), 1.0) if not math.isnan(r["ef"]) else 0.0
    return m + ef * (1.0 - m), ef * (1.0 - m)


def analysis_e(rows):
    out = []
    out.append("The curves are a **projection**, not a measurement: Amdahl's law S(p) = 1 / (s + (1 − s) / p) with "
               "serial fractions measured on 2 cores in (b). Solid, the measured design: s = m + e_F (1 − m), where m "
               "is the share of the 1-thread step spent outside UpdatePairs (the MoveProxy calls, made one at a "
               "time by Box2D) and e_F the Karp–Flatt serial fraction of FindPairs: a pessimistic bound, as if all of "
               "the outside work were serial (part of it, the queued moves' chunk applies, runs on all threads; "
               "compare the whole-work Karp–Flatt fraction of (b)). Dashed: s = e_F (1 − m), what would be left if "
               "the work outside UpdatePairs were all parallel (an optimistic bound). The measured design lies "
               "between the two. Dots: measured.\n")
    out.append("| trace | m | e_F | s | projected 4 / 8 / 16 threads | s if the outside work were parallel | "
               "projected 4 / 8 / 16 threads | blocks of 64 in the largest call |")
    out.append("|---|---|---|---|---|---|---|---|")
    for r in rows:
        s, s2 = serial_fractions(r)
        blocks = (r["buffered"] or 0) / 64.0
        out.append(f"| {r['name']} | {fmt(r['share'], 2)} | {fmt(r['ef'], 2)} | {fmt(s, 2)} | "
                   f"{' / '.join(fmt(amdahl(s, p), 1) for p in (4, 8, 16))} | "
                   f"{fmt(s2, 2)} | {' / '.join(fmt(amdahl(s2, p), 1) for p in (4, 8, 16))} | {fmt(blocks, 0)} |")
    out.append("")
    worst_share = max(r["share"] for r in rows)
    best_share = min(r["share"] for r in rows)
    out.append(f"**How the design should scale to 16 cores, and what limits it** (the join, memory and block "
               f"granularity: bench/README.md, section (e)): Box2D calls MoveProxy one proxy at a time, so the work "
               f"outside UpdatePairs is m = {fmt(100 * best_share, 0)}–{fmt(100 * worst_share, 0)}% of the 1-thread "
               f"step here, and were it all serial no thread count could beat {fmt(1 / worst_share, 1)}–"
               f"{fmt(1 / best_share, 1)}×. This overstates the serial part: the adapter's MoveProxy only appends the "
               "move to a queue, applied on all threads every 8192 moves and by FindPairs; the serial rest of m is "
               "the append, the per-call overhead and the replay loop (null engine, (d)); the cell changes run "
               "batched inside FindPairs on one thread (docs/design.md, \"Grid maintenance\"). The whole-work "
               "Karp–Flatt fraction of (b) is the better gauge.")
    out.append("")
    return "\n".join(out)


def figure(path, res, args, rows, ja):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        log("matplotlib is missing (bench/install-deps.sh installs python3-matplotlib); no figure")
        return False
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), dpi=80)
    ax = axes[0]
    if ja:
        xs = [d for d in args.depths if d != "auto"]
        for label, th, sch, style in (("1 thread", 1, "static", "k-o"), ("2 threads, static", 2, "static", "C0-s"),
                                      ("2 threads, dynamic", 2, "dynamic", "C1-^"),
                                      ("2 threads, guided", 2, "guided", "C2-v")):
            ys = [res.step_ms(res.key(ja["name"], cfg(th, sch, d))) for d in xs]
            ax.plot([int(x) for x in xs], ys, style, label=label, markersize=4, linewidth=1)
        ax.set_xlabel("quadtree depth")
        ax.set_ylabel("broadphase ms per step (median)")
        ax.set_title(f"(a) particles {ja['size']}: measured", fontsize=10)
        ax.set_yscale("log")
        from matplotlib.ticker import FormatStrFormatter
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    ax = axes[1]
    ps = list(range(1, 17))
    for i, r in enumerate(rows):
        s, s2 = serial_fractions(r)
        ax.plot(ps, [amdahl(s, p) for p in ps], f"C{i}-", linewidth=1.2, label=f"{r['name']}, as measured: s = {s:.2f}")
        ax.plot(ps, [amdahl(s2, p) for p in ps], f"C{i}--", linewidth=1.0,
                label=f"{r['name']}, outside work parallel too: s = {s2:.2f}")
        ax.plot([1, 2], [1.0, r["sw"]], f"C{i}o", markersize=5)
    ax.plot(ps, ps, ":", color="grey", linewidth=0.8, label="ideal")
    ax.set_xlabel("threads")
    ax.set_ylabel("speed-up of the broadphase work")
    ax.set_title("(e) PROJECTION: Amdahl with s measured on 2 cores (dots: measured)", fontsize=9)
    ax.set_xlim(1, 16)
    ax.set_ylim(0, 16)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return True


if __name__ == "__main__":
    sys.exit(main())
