#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Parallel pair-generation benchmark of quadphase (run it through bench/parallel.sh, which builds the tools).

One run records the traces (qp-record), checks every replay's pair sets against stock Box2D's (qp-replay --engine stock
hashes) and brute force (small traces), replays them with the timings interleaved (every round runs every
configuration once, so a noisy phase of the machine hits all of them), and writes
bench/results/parallel.md, parallel.csv and parallel.png. See bench/README.md for what each number means.
"""

import math
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from qpbench import paper, plot, report, run  # noqa: E402
from qpbench.report import fixed as fmt, table  # noqa: E402
from qpbench.stats import amdahl, karp_flatt, round_ratios, serial_fractions  # noqa: E402
from quadphase_tools import machine, stats  # noqa: E402

THRESHOLDS = [0, 64, 128, 256, 512, 1024, 4096]
# Options whose default depends on the version: (option, quick, full, help).
PROFILE_OPTIONS = [("repeats", 7, 11, "timed rounds"), ("table-warmup", 60, 120, "(a) warm-up steps"),
                   ("table-steps", 30, 60, "(a) timed steps"), ("particles-warmup", 60, 120, "(b) particles warm-up"),
                   ("particles-steps", 30, 60, "(b) particles timed steps"),
                   ("rain-warmup", 120, 600, "(b) rain warm-up: bodies falling (quick), pile forming (full)"),
                   ("rain-steps", 30, 60, "(b) rain timed steps"),
                   ("sweep-bullets-size", 1000, 2000, "(c) bullets size"),
                   ("sweep-steps", 60, 120, "(c) sweep timed steps"), ("wait-quiet", 20.0, 20.0, run.WAIT_HELP)]


def parse_args():
    def more(ap):
        ap.add_argument("--sections", default="a,b,c,d,e", help="subset of a,b,c,d,e (default: all)")
        for name, default in (("table-size", 50000), ("particles-size", 100000), ("rain-size", 65536),
                              ("small-size", 200), ("small-warmup", 60), ("small-steps", 1000),
                              ("sweep-particles-size", 10000),
                              ("sweep-warmup", 150)):  # sweep-warmup: bullets fires every bullet once in 120 steps
            ap.add_argument("--" + name, type=int, default=default)
        ap.add_argument("--depths", default="4,5,6,7,8,9,auto")
        ap.add_argument("--thresholds", default=",".join(str(t) for t in THRESHOLDS))

    a = run.parse_args(__doc__, "longer version: more repeats and steps, rain recorded until its pile has formed",
                       PROFILE_OPTIONS, more)
    a.sections = set(s.strip() for s in a.sections.split(",") if s.strip())
    a.depths = [d.strip() for d in a.depths.split(",") if d.strip()]
    a.thresholds = [int(t) for t in a.thresholds.split(",") if t.strip()]
    a.work = a.work or os.path.join(a.build_dir, "tmp")
    return a


def log(msg):
    print(msg, flush=True)


# The core's default parallelThreshold and schedule (qp-replay --print-config), read at start.
DEFAULT = {"threshold": 512, "schedule": "guided"}
SCHEDULES = ("static", "dynamic", "guided")
ROWS_A = ((1, "static"), (2, "static"), (2, "dynamic"), (2, "guided"))  # the rows of table (a): threads, schedule
CONFIG = ("threads", "schedule", "depth", "threshold", "chunk")  # a configuration's fields, in qp-replay's order
NAN = float("nan")
TEXT = report.prose(os.path.join(HERE, "prose", "parallel.md"))  # the report's prose


def set_defaults(default_config):
    for kv in default_config.split():
        k, _, v = kv.partition("=")
        if k in DEFAULT:
            DEFAULT[k] = int(v) if k == "threshold" else v


def cfg(threads=1, schedule=None, depth="auto", threshold=None, chunk=0):
    return {"threads": threads, "schedule": schedule or DEFAULT["schedule"],
            "depth": -1 if depth == "auto" else int(depth),
            "threshold": DEFAULT["threshold"] if threshold is None else threshold, "chunk": chunk}


def config_args(configs):
    """qp-replay's --config arguments: threads=T,schedule=S,depth=D,threshold=P,chunk=C for each configuration."""
    return [x for c in configs for x in ("--config", ",".join(f"{k}={c[k]}" for k in CONFIG))]


def med(values):
    """The median; NaN when there are no values."""
    return stats.med(values, NAN)


def median_of(value):
    """A method of Results: the median of value(run) over the timed runs of a key."""
    return lambda self, key: med([value(r) for r in self.runs.get(key, [])])


class Results:
    """The JSON lines by (trace, engine[, configuration]): timed runs, checking runs, OpenMP overhead."""

    def __init__(self, rows):
        self.runs, self.checks, self.stock_checks, self.omp = {}, {}, {}, []
        for r in rows:
            if r.get("kind") == "omp_overhead":
                self.omp.append(r)
                continue
            trace, engine = r.get("trace"), r.get("engine")
            key = (trace, engine) if engine in ("stock", "null") else self.key(trace, r)
            if r.get("kind") == "run":
                self.runs.setdefault(key, []).append(r)
            elif r.get("kind") == "check":
                (self.stock_checks if engine == "stock" else self.checks)[trace if engine == "stock" else key] = r

    def key(self, trace, c):
        return (trace, "quadtree") + tuple(c[k] for k in CONFIG)

    step_ms = median_of(lambda r: r["step_ns"] * 1e-6)
    find_ms = median_of(lambda r: r["find_ns"] * 1e-6)
    maint_ms = median_of(lambda r: (r["step_ns"] - r["find_ns"]) * 1e-6)  # outside FindPairs
    replace_ms = median_of(lambda r: r.get("replace_s", 0.0) * 1e3 / max(1, r["steps"]))
    ns_per_proxy = median_of(lambda r: r["ns_per_proxy_step"])

    def first(self, key, field, default=NAN):
        return self.runs.get(key, [{}])[0].get(field, default)  # (a key's list of runs is never empty)

    def ratios(self, key_num, key_den, field="step_ns"):
        return round_ratios(self.runs.get(key_num, []), self.runs.get(key_den, []), field)


# ----------------------------------------------------------------------------------------------------------------
# The benchmark
# ----------------------------------------------------------------------------------------------------------------
def plan(args):
    """Jobs: (section, scene, size, warmup, steps, configs, check mode, brute force, ...)."""
    jobs = []

    def job(section, scene, size, warmup, steps, configs, brute=False, separate=None, **more):
        jobs.append(dict(section=section, scene=scene, size=size, warmup=warmup, steps=steps, configs=configs,
                         **({"separate": separate} if separate else {}), check="all", brute=brute, **more))

    if args.sections & {"a", "e"}:
        job("a", "particles", args.table_size, args.table_warmup, args.table_steps,
            [cfg(th, sch, d) for d in args.depths for th, sch in ROWS_A])
    if args.sections & {"b", "d", "e"}:
        for scene, size, w, s in (("particles", args.particles_size, args.particles_warmup, args.particles_steps),
                                  ("rain", args.rain_size, args.rain_warmup, args.rain_steps)):
            job("b", scene, size, w, s,
                [cfg(1), cfg(2)] + ([cfg(2, "static")] if DEFAULT["schedule"] != "static" else []))
    if "c" in args.sections:
        for scene in ("rain", "particles"):
            # Threshold 0 (every call parallel) runs in a process of its own, after the others, so its worker
            # thread cannot disturb the 1-thread / 2-thread comparison. Steps of a few µs: 5 runs per round.
            job("c-small", scene, args.small_size, args.small_warmup, args.small_steps, [cfg(1), cfg(2)], True,
                [cfg(2, threshold=0)], per_call=True, inner=5)
        for scene, size in (("particles", args.sweep_particles_size), ("bullets", args.sweep_bullets_size)):
            job("c-sweep", scene, size, args.sweep_warmup, args.sweep_steps,
                [cfg(1)] + [cfg(2, threshold=t) for t in args.thresholds], size <= 2500, per_call=True)
    return jobs


def main():
    args = parse_args()
    state_path = os.path.join(args.work, "parallel-state.json")
    os.makedirs(args.results, exist_ok=True)
    if args.report_only:
        state = report.read_json(state_path)
        set_defaults(state["info"].get("default_config", ""))
        rows = run.Runner("parallel.py", "", args.work, "parallel", append=True).results()
        report_all(args, state["info"], state["jobs"], Results(rows), state["mismatches"], state["timing"])
        return 1 if any(state["mismatches"].values()) else 0
    t_start = time.time()
    runner = run.Runner("parallel.py", os.path.join(args.build_dir, "bench"), args.work, "parallel",
                        tools=("qp-record", "qp-replay"), seed=args.seed, rerecord=args.rerecord,
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
        runner.run("qp-replay", "--engine", "stock", "--trace", j["trace"], "--repeats", 0, "--check", "first",
                   "--hashes-out", stock_hash, "--json", runner.jsonl, "--label", j["section"])
        argv = ["--trace", j["trace"], "--repeats", 0, "--check", j["check"], "--compare-hashes", stock_hash,
                "--hashes-out", quad_hash, "--json", runner.jsonl, "--label", j["section"]]
        argv += (["--brute"] if j["brute"] else []) + (["--per-call"] if j.get("per_call") else [])
        code, out = runner.run("qp-replay", *argv, *config_args(j["configs"] + j.get("separate", [])),
                               ok_codes=(0, 3))
        bad = compare_hash_files(quad_hash, stock_hash)  # the script's own comparison, independent of qp-replay's
        for line in [ln for ln in out.splitlines() if "MISMATCH" in ln] if code == 3 or bad else []:
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
            runner.run("qp-replay", "--engine", "stock", *common)
            per_call = ["--per-call"] if j.get("per_call") else []
            # The configurations run in a different (seeded) random order in every round, so a burst of other
            # activity on the machine does not always hit the same neighbours.
            order = run.shuffled(j["configs"], 1000 * r + len(j["configs"]))
            runner.run("qp-replay", *common, *per_call, *config_args(order))
            for c in j.get("separate", []):
                runner.run("qp-replay", *common, *config_args([c]), *per_call)
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
def rain_note(j):
    """Where rain's bodies are during the timed steps, from the steps until the bottom row of its spawn grid reaches
    the floor (scene formulas; drag 1/s, g 10)."""
    width = math.floor(3.0 * math.sqrt(j["size"]) + 20.0)
    y0 = math.ceil(1.3 * j["size"] * 0.75 / width + 5.0) + 2.0  # the wall's height + 2
    # v(t) = 10 (1 - e^-t) (start speed ~ -1 m/s ignored); fallen distance 10 (t - 1 + e^-t)
    t = 0.0
    while 10.0 * (t - 1.0 + math.exp(-t)) < y0:
        t += 1.0 / 60.0
    fl = int(round(t * 60.0))
    return (f" — the bodies are still falling (the bottom row of the spawn grid reaches the floor after about {fl} "
            "steps, so no pile yet and no time-of-impact events)" if j["warmup"] + j["steps"] < fl else
            f" — the pile is forming (the bottom row reaches the floor after about {fl} steps)")


def bold(values, best, f=str):
    return [f"**{f(v)}**" if v == best else f(v) for v in values]


def span(values, digits=2):
    """"min–max" of the per-round ratios."""
    return f"{fmt(min(values) if values else None, digits)}–{fmt(max(values) if values else None, digits)}"


def steps_label(j):
    return f"{j['display']} ({j['warmup']} + {j['steps']} steps)"


def report_all(args, info, jobs, res, mismatches, timing):
    md, csv_rows, sec = ["# Parallel pair generation: measurements\n"], [], {}
    for j in jobs:
        sec.setdefault(j["section"], []).append(j)
    dflt, sched = DEFAULT["threshold"], DEFAULT["schedule"]

    def key(j, *a, **kw):  # the quadtree configuration cfg(*a, **kw) on job j's trace
        return res.key(j["name"], cfg(*a, **kw))

    def csv_add(section, j, *configs):
        """A row of parallel.csv per configuration: a quadtree one (cfg) or the engine "stock" / "null"."""
        for c in configs:
            q = isinstance(c, dict)
            k, d = (res.key(j["name"], c), c) if q else ((j["name"], c), dict.fromkeys(CONFIG, ""))
            csv_rows.append(dict(
                section=section, scene=j["scene"], size=j["size"], warmup_steps=j["warmup"], timed_steps=j["steps"],
                engine="quadtree" if q else c, threads=d["threads"], schedule=d["schedule"],
                depth="auto" if q and d["depth"] < 0 else d["depth"],
                depth_used=res.first(k, "depth_used", "") if q else "", threshold=d["threshold"],
                rounds=len(res.runs.get(k, [])), ms_per_step=fmt(res.step_ms(k), 4),
                find_ms_per_step=fmt(res.find_ms(k), 4), outside_findpairs_ms_per_step=fmt(res.maint_ms(k), 4),
                replacement_ms_per_step=fmt(res.replace_ms(k), 4) if q else "",
                ns_per_proxy_step=fmt(res.ns_per_proxy(k), 1), mean_proxies=fmt(res.first(k, "mean_proxies"), 0),
                pairs_per_step=fmt(res.first(k, "pairs_per_step"), 1),
                updatepairs_calls_per_step=fmt(res.first(k, "calls_per_step"), 2),
                parallel_regions_per_step=fmt(res.first(k, "parallel_calls", NAN) / max(1, res.first(k, "steps", 1)), 2)
                if q else ""))

    md.append(TEXT["header"].format(full=" --full" if args.full else "", minutes=timing["total"] / 60,
                                    repeats=args.repeats, **timing) + "\n")
    md += report.machine_section(info)[:-1]
    md.append(TEXT["rounds"].format(**vars(args)))
    omp = {(o["schedule"], o["blocks"]): o["us"] for o in res.omp}
    omp64 = ", ".join(f"{s} {fmt(omp.get((s, 64)), 1)} µs" for s in SCHEDULES) if omp else ""
    if omp:
        md.append(TEXT["omp"].format(omp64=omp64, one=fmt(omp.get(("static", 1)), 1)))
    md.append("")

    # ---------------- exactness ----------------
    md.append("## Exactness\n")
    if any(mismatches.values()):
        md.append("**MISMATCH: the quadtree's pair sets differ from stock Box2D's on "
                  + ", ".join(k for k, v in mismatches.items() if v) + ". These timings are not valid.**\n")
    md.append(TEXT["exactness"] + "\n")
    md += table("trace | UpdatePairs calls | quadtree configurations checked | result", [
        [steps_label(j), res.stock_checks.get(j["name"], {}).get("calls_hashed", "–"),
         f"{sum(k[0] == j['name'] for k in res.checks)}" + (" + brute force" if j["brute"] else ""),
         "**MISMATCH**" if mismatches.get(j["name"]) else "identical"] for j in jobs]) + [""]

    # ---------------- (a) ----------------
    ja = sec.get("a", [None])[0]
    if ja:
        auto_depth = res.first(key(ja, 1, "static", "auto"), "depth_used", "?")
        md.append(f"## (a) The paper's Tables 1 and 2 on this machine: particles {ja['size']}\n")
        md.append(TEXT["a"].format(repeats=args.repeats, steps=ja["steps"], warmup=ja["warmup"], dflt=dflt) + "\n")
        head = ["schedule \\ depth"] + [f"auto (= {auto_depth})" if d == "auto" else d for d in args.depths]
        for title, ms in (("Whole broadphase work, ms/step", res.step_ms), ("FindPairs only, ms/step", res.find_ms)):
            rows = []
            for th, sch in ROWS_A:
                vals = [ms(key(ja, th, sch, d)) for d in args.depths]
                rows.append(["sequential (1 thread)" if th == 1 else f"{sch} (2 threads)"]
                            + bold(vals, min((v for v in vals if not math.isnan(v)), default=None), fmt))
            md += [f"**{title}**\n"] + table(head, rows) + [""]
        csv_add("a", ja, *[cfg(th, sch, d) for th, sch in ROWS_A for d in args.depths])
        twin = str(auto_depth) if str(auto_depth) in args.depths and "auto" in args.depths else None
        gauge = gauge_find = None
        if twin:
            def spread(ms):  # % between "auto" and its twin depth, per row of the table
                pairs = [(ms(key(ja, th, sch, "auto")), ms(key(ja, th, sch, twin))) for th, sch in ROWS_A]
                return [100.0 * abs(x - y) / min(x, y) for x, y in pairs if not math.isnan(x) and not math.isnan(y)]
            fd, diffs = spread(res.find_ms), spread(res.step_ms)
            gauge_find = max(fd) if fd else None
            if diffs:
                gauge = max(diffs)
                md.append(TEXT["noise"].format(twin=twin, lo=fmt(min(diffs), 1), hi=fmt(gauge, 1),
                                               find=fmt(gauge_find, 1)) + "\n")
        md.append("**Speed-up of 2 threads (static) over 1, per depth** (whole work; FindPairs only): " + ", ".join(
            f"{d}: {fmt(res.step_ms(key(ja, 1, 'static', d)) / res.step_ms(key(ja, 2, 'static', d)))}× "
            f"({fmt(res.find_ms(key(ja, 1, 'static', d)) / res.find_ms(key(ja, 2, 'static', d)))}×)"
            for d in args.depths) + "\n")
        md.append(TEXT["depths"] + "\n")
        rows, used = [], {}
        for d in args.depths:
            ck = res.checks.get(key(ja, 1, "static", d))
            if not ck:
                continue
            qn, du = max(1, ck["queries"]), ck["depth_used"]
            used[d] = du
            deepest = max((i for i, c in enumerate(ck.get("proxies_per_level", [])) if c > 0), default=0)
            rows.append([d if d != "auto" else f"auto = {du}", fmt(ck["leaf_size"], 2),
                         fmt(4 ** du / max(1, ck["proxies"]), 3), deepest, fmt(ck["cells"] / qn, 1),
                         fmt(ck["candidates"] / qn, 1), fmt(ck["overlaps"] / qn, 2), fmt(ck["pairs"] / qn, 2),
                         fmt(ck["queries"] / ja["steps"], 0), fmt(ck["memory_bytes"] / 2 ** 20, 1)])
        md += table("depth | leaf side (m) | leaf cells per proxy | deepest occupied level | cells visited per query "
                    "(approx.) | candidates per query | overlaps per query | pairs per query | queries per step | "
                    "memory (MB)", rows) + [""]
        md.append(TEXT["paper"] + "\n")
        for cpu, t in paper.TABLES.items():
            md += table([cpu] + [str(d) for d in paper.DEPTHS], [[row] + bold(v, max(v)) for row, v in t.items()])
            md.append("")
        md.append(analysis_a(res, ja["name"], args.depths, used.get("auto", "?"), omp64, gauge, gauge_find))

    # ---------------- (b) ----------------
    amdahl_rows, static_rows, rows = [], [], []
    for j in sec.get("b", []):
        k1, k2, ks = key(j, 1), key(j, 2), key(j, 2, "static")
        t1, t2, f1, f2 = res.step_ms(k1), res.step_ms(k2), res.find_ms(k1), res.find_ms(k2)
        m1, m2, r1, r2 = res.maint_ms(k1), res.maint_ms(k2), res.replace_ms(k1), res.replace_ms(k2)
        sw, sf, share = t1 / t2, f1 / f2, m1 / t1
        ew, ef = karp_flatt(sw), karp_flatt(sf)
        amdahl_rows.append(dict(name=j["display"], t1=t1, t2=t2, sw=sw, ef=ef, share=share, loop=res.step_ms(
            (j["name"], "null")), buffered=res.checks.get(k1, {}).get("max_buffered")))
        rows.append([j["display"], fmt(res.first(k1, "mean_proxies"), 0), f"{fmt(t1)} = {fmt(f1)} + {fmt(m1)}",
                     f"{fmt(t2)} = {fmt(f2)} + {fmt(m2)}", f"**{fmt(sf)}×** ({span(res.ratios(k1, k2, 'find_ns'))})",
                     f"{fmt(r1)} → {fmt(r2)} ({fmt(r1 / r2) + '×' if r1 > 0 and r2 > 0 else '–'})",
                     f"**{fmt(sw)}×** ({span(res.ratios(k1, k2))})", f"{fmt(100 * share, 0)}%", fmt(ew, 2),
                     fmt(ef, 2)])
        csv_add("b", j, cfg(1), cfg(2))
        if sched != "static" and not math.isnan(res.step_ms(ks)):
            csv_add("b", j, cfg(2, "static"))
            rs = res.ratios(ks, k2)
            static_rows.append(f"{j['display']}: static {fmt(res.step_ms(ks))} ms/step (FindPairs "
                               f"{fmt(res.find_ms(ks))}) against {sched} {fmt(t2)} ({fmt(f2)}); "
                               f"per round, static / {sched} = {fmt(med(rs))} ({span(rs)})")
    if sec.get("b"):
        md.append("## (b) Speed-up of 2 threads over 1 on the broadphase work\n")
        notes = [f"{j['display']}: {j['warmup']} warm-up steps (untimed), then {j['steps']} timed steps"
                 + (rain_note(j) if j["scene"] == "rain" else "") for j in sec["b"]]
        md.append(TEXT["b"].format(notes="; ".join(notes), Sched=sched.capitalize(), dflt=dflt) + "\n")
        md += table("trace | proxies | 1 thread: ms/step = FindPairs + outside | 2 threads: ms/step = FindPairs + "
                    "outside | FindPairs speed-up | grid maintenance, ms/step: 1 → 2 threads | whole-work speed-up | "
                    "outside share at 1 thread (m) | serial fraction, whole (Karp–Flatt) | serial fraction, "
                    "FindPairs (Karp–Flatt, e_F)", rows) + [""]
        if static_rows:
            md.append(TEXT["static"].format(sched=sched, rows="; ".join(static_rows)) + "\n")
        md.append(analysis_b(amdahl_rows))

    # ---------------- (c) ----------------
    smalls, sweeps = sec.get("c-small", []), sec.get("c-sweep", [])
    if smalls or sweeps:
        md.append("## (c) Small scenes and the parallel threshold\n")
    if smalls:
        inner = smalls[0].get("inner", 1)
        md.append(TEXT["small"].format(inner=inner, runs=inner * args.repeats, dflt=dflt, **vars(args)) + "\n")
        rows = []
        for j in smalls:
            k1, k2, k0 = key(j, 1), key(j, 2), key(j, 2, threshold=0)
            s1, s2, s0 = res.step_ms(k1), res.step_ms(k2), res.step_ms(k0)
            rows.append([j["display"], fmt(s1 * 1e3, 1), fmt(s2 * 1e3, 1),
                         f"**{fmt(s2 / s1, 3)}** (rounds {span(res.ratios(k2, k1), 3)})",
                         res.checks.get(k1, {}).get("max_buffered", "–"), int(res.first(k2, "parallel_calls", 0)),
                         f"{fmt(s0 * 1e3, 1)} µs/step ({fmt(s0 / s1, 2)}×)"])
            csv_add("c-small", j, cfg(1), cfg(2), cfg(2, threshold=0))
        md += table("trace | 1 thread µs/step | 2 threads µs/step | 2 threads / 1 thread | largest UpdatePairs "
                    "call (buffered proxies) | parallel regions opened | for comparison: 2 threads, threshold 0",
                    rows) + [""]
    if sweeps:
        md.append(TEXT["sweep"].format(sched=sched) + "\n")
        rows = [["1 thread (reference)"] + [f"{fmt(res.step_ms(key(j, 1)), 3)} ({fmt(res.find_ms(key(j, 1)), 3)})"
                                            for j in sweeps]]
        for t in args.thresholds:
            rows.append([f"{t}{' (default)' if t == dflt else ''}"])
            for j in sweeps:
                k = key(j, 2, threshold=t)
                pc = res.first(k, "parallel_calls", NAN) / max(1, res.first(k, "steps", 1))
                rows[-1].append(f"{fmt(res.step_ms(k), 3)} ({fmt(res.find_ms(k), 3)}); "
                                f"×{fmt(res.step_ms(key(j, 1)) / res.step_ms(k), 2)}; {fmt(pc, 1)}")
        md += table(["threshold"] + [steps_label(j) for j in sweeps], rows) + [""]
        for j in sweeps:
            csv_add("c-sweep", j, cfg(1), *[cfg(2, threshold=t) for t in args.thresholds])
        md.append("UpdatePairs calls per timed step, by buffered proxies per call:\n")
        edges = res.checks.get(key(sweeps[0], 1), {}).get("bucket_edges", [0, 1, 64, 128, 256, 512, 1024, 4096])
        cks = [res.checks.get(key(j, 1), {}) for j in sweeps]
        # The counts are joined into one cell, as an empty list must leave one empty cell.
        md += table(["trace"] + [bucket_label(edges, i) for i in range(len(edges))] + ["largest"], [
            [j["display"], " | ".join(fmt(c / j["steps"], 2) for c in ck.get("bucket_calls", [])),
             ck.get("max_buffered", "–")] for j, ck in zip(sweeps, cks)]) + [""]
    per_call = [(j, t) for j, t in ((j, per_call_rows(res, j)) for j in smalls + sweeps) if t is not None]
    if per_call:
        md += [TEXT["per_call"] + "\n"] + table("trace | buffered proxies per call | calls per step | serial µs/call "
                                                 "| parallel µs/call | serial / parallel", [
            [j["display"], r["label"], fmt(r["per_step"], 2), fmt(r["serial"], 1), fmt(r["parallel"], 1),
             fmt(r["ratio"], 2)] for j, t in per_call for r in t]) + [""]
    if smalls or sweeps:
        md.append(analysis_c(res, sweeps, smalls, args.thresholds, per_call))

    # ---------------- (d) ----------------
    if "d" in args.sections:
        md += ["## (d) Stock Box2D 2.4.1 `b2BroadPhase` on the same traces\n", TEXT["d"] + "\n"]
        rows = []
        for j in jobs:
            ks = (j["name"], "stock")
            s, q1, q2 = res.ns_per_proxy(ks), res.ns_per_proxy(key(j, 1)), res.ns_per_proxy(key(j, 2))
            rows.append([steps_label(j), fmt(res.first(ks, "mean_proxies"), 0), fmt(s, 1), fmt(q1, 1), fmt(q2, 1),
                         f"**{fmt(s / q1, 1)}×**", f"**{fmt(s / q2, 1)}×**",
                         fmt(res.ns_per_proxy((j["name"], "null")), 1)])
            csv_add("d", j, "stock", "null")
        md += table("trace | proxies | stock ns/proxy/step | quadtree, 1 thread | quadtree, 2 threads | stock / "
                    "quadtree (1 thread) | stock / quadtree (2 threads) | replay overhead ns/proxy/step", rows) + [""]

    # ---------------- (e) ----------------
    if "e" in args.sections and amdahl_rows:
        drew = figure(os.path.join(args.results, "parallel.png"), res, args, amdahl_rows, ja)
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
def analysis_a(res, na, depths, auto_used, omp64, gauge, gauge_find):
    """The numbers behind table (a); how to read them: bench/README.md, section (a)."""
    grid = {(th, sch, d): res.step_ms(res.key(na, cfg(th, sch, d))) for th, sch in ROWS_A for d in depths}
    fgrid = {k: res.find_ms(res.key(na, cfg(*k))) for k in grid}
    valid, fvalid = ({k: v for k, v in g.items() if not math.isnan(v)} for g in (grid, fgrid))
    if not valid or not fvalid:
        return ""
    name = lambda k: ("sequential" if k[0] == 1 else k[1]) + f" depth {k[2]}"  # noqa: E731
    best, fbest = min(valid, key=valid.get), min(fvalid, key=fvalid.get)
    seq = {d: grid[(1, "static", d)] for d in depths if (1, "static", d) in valid}
    out = [f"- Fastest, whole work: {name(best)}, {fmt(valid[best])} ms/step; FindPairs only: {name(fbest)}, "
           f"{fmt(fvalid[fbest])} ms/step; fastest sequential: depth {min(seq, key=seq.get)}, {fmt(min(seq.values()))}"
           f" ms/step; the automatic depth picks {auto_used}; noise gauge "
           f"{fmt(gauge, 1)}% (whole), {fmt(gauge_find, 1)}% (FindPairs)."]
    cols = [{x: fgrid[(2, x, d)] for x in SCHEDULES} for d in depths]
    cols = [c for c in cols if not any(math.isnan(v) for v in c.values())]
    if cols:
        out.append("- 2-thread schedules, FindPairs, median % above each depth's fastest: " + ", ".join(
            f"{x} {fmt(med([100.0 * (c[x] / min(c.values()) - 1.0) for c in cols]), 1)}%" for x in SCHEDULES)
            + (f" (an empty 64-iteration parallel loop: {omp64})" if omp64 else ""))
    sp, fs = ([g[(1, "static", d)] / g[(2, "static", d)] for d in depths
               if (1, "static", d) in v and (2, "static", d) in v] for g, v in ((grid, valid), (fgrid, fvalid)))
    if sp and fs:
        out.append(f"- Static at 2 threads over sequential: whole work {fmt(min(sp))}–{fmt(max(sp))}×, FindPairs "
                   f"{fmt(min(fs), 2)}–{fmt(max(fs), 2)}×, faster at {sum(x > 1 for x in sp)} of {len(sp)} depths.")
    return "\n".join(out) + "\n"


def analysis_b(rows):
    """Numbers beside table (b): the whole work less the replay loop, and the Amdahl bound of the outside share."""
    return "\n".join(
        f"- {r['name']}: had the outside share stayed serial, 2 threads could not beat {fmt(amdahl(r['share'], 2))}×"
        + (f"; less the replay loop ({fmt(r['loop'], 2)} ms/step): {fmt(r['t1'] - r['loop'])} → "
           f"{fmt(r['t2'] - r['loop'])} ms ({fmt((r['t1'] - r['loop']) / (r['t2'] - r['loop']))}×)"
           if not math.isnan(r.get("loop", NAN)) and r["t2"] > r["loop"] else "") + "." for r in rows) + "\n"


CALL_BUCKETS = [0, 1, 16, 64, 128, 256, 512, 1024, 2048, 4096]


def bucket_label(edges, i):
    """Size class i of the sorted lower edges: "lo–hi", "lo" when it holds one size, "≥ lo" for the last."""
    if i + 1 >= len(edges):
        return f"≥ {edges[i]}"
    return str(edges[i]) if edges[i + 1] - 1 == edges[i] else f"{edges[i]}–{edges[i + 1] - 1}"


def per_call_rows(res, j):
    """Per-call FindPairs times by size class: serial (1 thread) vs forced parallel (2 threads, threshold 0)."""
    ck = res.checks.get(res.key(j["name"], cfg(1)))
    sizes = ck.get("calls_buffered") if ck else None
    if not sizes:
        return None
    bucket = [sum(n >= e for e in CALL_BUCKETS[1:]) for n in sizes]  # each call's size class

    def pooled(c, b):  # the times of the calls of size class b under configuration c, over the rounds
        return [t for r in res.runs.get(res.key(j["name"], c), []) if len(r.get("calls_ns") or []) == len(sizes)
                for cb, t in zip(bucket, r["calls_ns"]) if cb == b]

    rows = []
    for b in range(len(CALL_BUCKETS)):
        serial, parallel = pooled(cfg(1), b), pooled(cfg(2, threshold=0), b)
        if bucket.count(b) and serial and parallel:
            sm, pm = med(serial) * 1e-3, med(parallel) * 1e-3
            rows.append(dict(bucket=b, label=bucket_label(CALL_BUCKETS, b), per_step=bucket.count(b) / j["steps"],
                             serial=sm, parallel=pm, ratio=sm / pm if pm > 0 else NAN))
    return rows


def analysis_c(res, sweeps, smalls, thresholds, per_call):
    """The numbers behind (c) and the recommended threshold (how it is chosen: bench/README.md, section (c))."""
    out, rows = [], [r for _, t in per_call for r in t if CALL_BUCKETS[r["bucket"]] > 0]
    # A size class wins or loses beyond ±5%: the end of the largest that loses, the start of the smallest that wins.
    lose_hi = max((CALL_BUCKETS[r["bucket"] + 1] for r in rows
                   if r["ratio"] < 1.05 and r["bucket"] + 1 < len(CALL_BUCKETS)), default=None)
    win_lo = min((CALL_BUCKETS[r["bucket"]] for r in rows if r["ratio"] > 1.05), default=None)
    if per_call:
        out.append(f"- Call by call: largest size class where a parallel call does not win ends at "
                   f"{lose_hi - 1 if lose_hi else '–'} buffered proxies; smallest where it wins starts at "
                   f"{win_lo if win_lo is not None else '–'}.")
    rel = {t: [] for t in thresholds}
    for j in sweeps:
        vals = {t: res.step_ms(res.key(j["name"], cfg(2, threshold=t))) for t in thresholds}
        vals = {t: v for t, v in vals.items() if not math.isnan(v)}
        if vals:
            best = min(vals, key=vals.get)
            for t, v in vals.items():
                rel[t].append(v / vals[best])
            out.append(f"- {j['display']}: fastest at threshold {best} ({fmt(vals[best], 3)} ms/step, "
                       f"{fmt(res.step_ms(res.key(j['name'], cfg(1))) / vals[best], 2)}× the 1-thread time).")
    score = {t: math.exp(sum(math.log(x) for x in v) / len(v)) for t, v in rel.items() if v}
    if score:
        best_t, dflt = min(score, key=score.get), DEFAULT["threshold"]
        near = sorted(t for t, v in score.items() if v <= score[best_t] * 1.03)
        above = [t for t in sorted(score) if lose_hi is None or t >= lose_hi]
        rec = dflt if dflt in near else (above[0] if above else best_t)
        out.append("- Geometric mean over the sweep scenes of time ÷ that scene's fastest: " + ", ".join(
            f"{t}: {fmt(score[t], 3)}" for t in sorted(score)) + f"; within 3% of the lowest: "
            f"{', '.join(map(str, near))}. **Recommended parallelThreshold: {rec}** (the core's default: {dflt}).")
    if smalls:
        worst = max(res.step_ms(res.key(j["name"], cfg(2))) / res.step_ms(res.key(j["name"], cfg(1))) for j in smalls)
        regions = sum(res.first(res.key(j["name"], cfg(2)), "parallel_calls", 0) for j in smalls)
        out.append(f"- {smalls[0]['size']}-body scenes at the default threshold: 2 threads take at most "
                   f"{fmt(worst, 3)}× the 1-thread time; {regions} parallel regions opened.")
    return "\n".join(out) + "\n"


def analysis_e(rows):
    """The projection's table (what it assumes: bench/README.md, section (e))."""
    out = []
    for r in rows:
        s, s2 = serial_fractions(r)
        out.append([r["name"], fmt(r["share"], 2), fmt(r["ef"], 2), fmt(s, 2),
                    " / ".join(fmt(amdahl(s, p), 1) for p in (4, 8, 16)), fmt(s2, 2),
                    " / ".join(fmt(amdahl(s2, p), 1) for p in (4, 8, 16)), fmt((r["buffered"] or 0) / 64.0, 0)])
    return "\n".join(table("trace | m | e_F | s | projected 4 / 8 / 16 threads | s if the outside work were parallel | "
                           "projected 4 / 8 / 16 threads | blocks of 64 in the largest call", out)) + "\n"


def figure(path, res, args, rows, ja):
    plt = plot.pyplot("parallel.py")
    if plt is None:
        return False
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(10, 3.8), dpi=80)
    if ja:
        xs = [d for d in args.depths if d != "auto"]
        for (th, sch), style in zip(ROWS_A, ("k-o", "C0-s", "C1-^", "C2-v")):
            ax.plot([int(x) for x in xs], [res.step_ms(res.key(ja["name"], cfg(th, sch, d))) for d in xs], style,
                    label="1 thread" if th == 1 else f"2 threads, {sch}", markersize=4, linewidth=1)
        # The scale before the formatters: setting it resets them.
        ax.set(xlabel="quadtree depth", ylabel="broadphase ms per step (median)", yscale="log")
        ax.set_title(f"(a) particles {ja['size']}: measured", fontsize=10)
        from matplotlib.ticker import FormatStrFormatter
        ax.yaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(FormatStrFormatter("%g"))
        ax.tick_params(axis="y", which="minor", labelsize=7)
        ax.legend(fontsize=8)
        ax.grid(True, alpha=0.3)
    ps = list(range(1, 17))
    for i, r in enumerate(rows):
        s, s2 = serial_fractions(r)
        ax2.plot(ps, [amdahl(s, p) for p in ps], f"C{i}-", linewidth=1.2,
                 label=f"{r['name']}, as measured: s = {s:.2f}")
        ax2.plot(ps, [amdahl(s2, p) for p in ps], f"C{i}--", linewidth=1.0,
                 label=f"{r['name']}, outside work parallel too: s = {s2:.2f}")
        ax2.plot([1, 2], [1.0, r["sw"]], f"C{i}o", markersize=5)
    ax2.plot(ps, ps, ":", color="grey", linewidth=0.8, label="ideal")
    ax2.set(xlabel="threads", ylabel="speed-up of the broadphase work", xlim=(1, 16), ylim=(0, 16))
    ax2.set_title("(e) PROJECTION: Amdahl with s measured on 2 cores (dots: measured)", fontsize=9)
    ax2.legend(fontsize=7, loc="upper left")
    ax2.grid(True, alpha=0.3)
    plot.save(plt, fig, path)
    return True


if __name__ == "__main__":
    sys.exit(main())
