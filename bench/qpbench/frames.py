# SPDX-License-Identifier: MIT
"""bench.py's frames section (--frames, and --full after the rest): every in-engine scene from its first step as a
game runs it, stock and quadphase (1 and 2 threads, its defaults, a job system), each also beside a busy thread;
per-step b2Profile broadphase and step p50/p99/max/total and the process's CPU time -> results/frames.{md,csv,png}.
RESULTS.md quotes the goals table run_frames returns; manycore.py reuses frame_rows and cpu_goal."""

import os
import time

from quadphase_tools import machine
from quadphase_tools.stats import med, ratio

from . import plot, report, run
from .bench_common import TEXT
from .report import num as fmt, table
from .step import STEP_SIZES

# Frames (--frames): (name, build, qp-step options), each also with --busy, on small scenes as well as big ones.
FRAME_ENGINES = [("stock", "stock", []), ("1 thread", "quadtree", ["--threads", 1]),
                 ("2 threads", "quadtree", ["--threads", 2]), ("defaults", "quadtree", ["--threads", "default"]),
                 ("job system", "quadtree", ["--threads", "default", "--jobs", 2])]
# else the quick step sizes; particles 20,000 is above Config::parallelMinProxies, where the defaults go parallel
FRAME_SIZES = {"pyramid": [10, 20, 50], "terrain": [40, 1000], "mixed": [1000], "particles": [10000, 20000]}
FRAME_PLOTS = [("pyramid", 10), ("tumbler", 400), ("rain", 4000)]
FRAME_STATS = ("p50", "p99", "max", "total")
FRAME_TOOLS = ("qp-step-stock", "qp-step-quadtree")
TICK = {True: " ✓", False: " **✗**"}
CPU_GOAL = 1.3  # the process's CPU time at most this many times the 1-thread quadtree's


def run_frames(args):
    """--frames: every frame engine on every scene (also with --busy) for --rounds rounds, then frames.{md,csv,png}."""
    lv, d = args.levels[0]
    runner = run.Runner("bench.py", os.path.join(d, "bench"), os.path.join(args.work, "frames"), "frames",
                        tools=FRAME_TOOLS, append=args.report_only, wait_quiet=args.wait_quiet,
                        quiet_cpus=args.quiet_cpus)
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
    groups, rows = frame_rows(runner.results())
    report.write_csv(os.path.join(args.results, "frames.csv"), rows)
    by = {(r["scene"], r["size"], r["busy"], r["engine"]): r for r in rows}
    cpu = any("cpu_s" in r for r in rows)  # the CPU columns: runs of a qp-step that measures the process's CPU time
    head, misses = [], set()
    for s, n, b in sorted({k[:3] for k in by}):
        a, one = (by.get((s, n, b, e)) or {} for e in ("stock", "1 thread"))
        cells = [f"{s} {n}", "yes" if b else "no", fmt(a.get("proxies"), 0)]
        for e in ("defaults", "job system"):
            q = by.get((s, n, b, e)) or {}
            total = [ratio(x.get("bp_total_best"), q.get("bp_total_best")) for x in (a, one)]
            ok = [(total[0] or 0) >= 1.0, (total[1] or 0) >= 0.95,
                  q.get("bp_max_best", 1e9) <= 1.5 * a.get("bp_max_best", 0) + 0.5]
            cells += [f"{fmt(total[0])}{TICK[ok[0]]}", f"{fmt(total[1])}{TICK[ok[1]]}",
                      f"{fmt(q.get('bp_max_best'), 3)} / {fmt(a.get('bp_max_best'), 3)}{TICK[ok[2]]}"]
            if cpu:
                cpu_x, cpu_ok = cpu_goal(q, one)
                ok.append(cpu_ok)
                cells.append(f"{fmt(cpu_x)}{TICK[cpu_ok]}")
            misses.update(f"{s} {n}{' busy' if b else ''} ({e})" for o in ok if not o)
        head.append(cells)
    L = ["# Frames: per-step broadphase and step, as a game runs the library", "",
         TEXT["frames"].format(steps=info.get("steps"), rounds=info.get("rounds"), minutes=info.get("minutes", 0)), ""]
    if cpu:
        L += [TEXT["frames_cpu"].format(goal=CPU_GOAL), ""]
    if frames_plot(args, groups):
        L += ["![ms per step over the run, stock against quadphase's defaults](frames.png)", ""]
    cpu_head = lambda e: [f"CPU s: {e} ÷ 1 thread (≤{CPU_GOAL})"] if cpu else []  # noqa: E731
    goals = ["## Goals", ""] + table(
        ["scene", "busy", "proxies at the end", "bp total stock ÷ defaults (≥1)", "1 thread ÷ defaults (≥0.95)",
         "worst bp step ms: defaults / stock (≤1.5×+0.5)", *cpu_head("defaults"), "stock ÷ job system",
         "1 thread ÷ job system", "worst: job system / stock", *cpu_head("job system")], head) \
        + ["", "Misses: " + (", ".join(sorted(misses)) or "none") + "."]
    L += goals + ["", "## Per step, ms", ""]
    L += table(["scene", "busy", "engine"] + [f"{m} {st}" for m in ("bp", "step") for st in FRAME_STATS]
               + (["CPU s"] if cpu else []), [
        [f"{r['scene']} {r['size']}", "yes" if r["busy"] else "no", r["engine"]]
        + [fmt(r[f"{m}_{st}"], 3) for m in ("bp", "step") for st in FRAME_STATS]
        + ([fmt(r.get("cpu_s"), 3)] if cpu else []) for r in rows])
    report.write_lines(os.path.join(args.results, "frames.md"), L + [""] + report.machine_section(info))
    print(f"bench.py: wrote {args.results}/frames.md, frames.csv", flush=True)
    return goals


def frame_rows(results):
    """qp-step's frames runs (label "frames|ENGINE|round=R") grouped by (scene, size, busy, engine), and one row per
    group: medians over the rounds of the per-step statistics (bp_*, step_*) and, where the runs measured it, of
    the process's CPU seconds over the timed steps (cpu_s) and their wall time (wall_s); each engine's best round,
    the goals' figure (bp_max_best, bp_total_best, cpu_s_best)."""
    groups = {}
    for r in results:
        groups.setdefault((r["scene"], r["size"], r["busy"], r["label"].split("|")[1]), []).append(r)
    rows = [dict(scene=s, size=n, busy=b, engine=e, rounds=len(rs), proxies=rs[0]["proxies"], **{
        f"{m}_{st}": med([r[f"{f}_ms_{st}"] for r in rs]) for m, f in (("bp", "broadphase"), ("step", "step"))
        for st in FRAME_STATS}, **{f"bp_{st}_best": min(r[f"broadphase_ms_{st}"] for r in rs) for st in ("max", "total")},
        **({"cpu_s": med([r["cpu_s"] for r in rs]), "cpu_s_best": min(r["cpu_s"] for r in rs),
            "wall_s": med([r["wall_s"] for r in rs])} if all("cpu_s" in r for r in rs) else {}))
        for (s, n, b, e), rs in sorted(groups.items())]
    return groups, rows


def cpu_goal(engine, one_thread):
    """The CPU goal on two rows of frame_rows: (the engine's CPU seconds ÷ the 1-thread quadtree's, best rounds;
    whether that is at most CPU_GOAL)."""
    x = ratio(engine.get("cpu_s_best"), one_thread.get("cpu_s_best"))
    return x, x is not None and x <= CPU_GOAL


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
