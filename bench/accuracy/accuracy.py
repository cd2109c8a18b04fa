#!/usr/bin/python3
"""Error against run time: sweeps qp-accuracy-{stock,quadphase,paper} over scenes, broadphase configurations and
step settings, then writes the raw results (BUILD_DIR/accuracy/), the plots (docs/accuracy/*.png) and the report
(docs/accuracy.md). Run through bench/accuracy/run.sh, which builds the programs first.

Every configuration is run --rounds times (in a shuffled order per round, so a noisy phase of the shared machine
hits all configurations alike); the run time reported is the smallest of the rounds, the error measures are those
of the first round (they are deterministic except for the paper design at 2 threads, whose pair order depends on
thread timing: the report says when rounds disagreed).
"""

import argparse
import datetime
import json
import math
import os
import random
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
from qpbench import machine, plot, report, run  # noqa: E402
from qpbench.report import sig as fmt, table  # noqa: E402

# (scene, size, simulated seconds). Modest sizes: the whole sweep (2 rounds) took about 25 minutes on 2 busy cores.
SCENES = [
    ("pyramid", 20, 10.0),
    ("tiles", 1000, 10.0),
    ("particles", 1000, 10.0),
    ("rain", 1000, 5.0),
    ("tumbler", 200, 5.0),
    ("bullets", 100, 5.0),
    ("sparse", 1000, 5.0),
    ("shooter", 200, 5.0),
    ("openworld", 500, 5.0),
    ("mixed", 200, 5.0),
    ("terrain", 300, 5.0),
    ("churn", 500, 5.0),
]
# Scenes that settle rather than diverge: the only ones compared with a reference run.
NON_CHAOTIC = ("pyramid", "tiles")
# Scenes with the pyramid whose top box drift is reported.
TOP_BOX = ("pyramid", "tiles")
ENERGY = ("particles",)

DEFAULT_STEP = (60, 8, 3)
STEP_SETTINGS = [DEFAULT_STEP, (30, 8, 3), (120, 8, 3), (240, 8, 3), (60, 4, 2), (60, 16, 6)]
REFERENCE_STEP = (240, 32, 12)  # 4x the default rate and 4x the default iterations

# Broadphase configurations: key, build, extra arguments, family (colour), label. A key ending in "-passive" runs
# with OMP_WAIT_POLICY=passive (libgomp's idle threads sleep instead of spinning; see the report).
BROADPHASES = [
    ("stock", "stock", [], "stock", "stock tree"),
    ("qp-auto-t1", "quadphase", ["--depth", "auto", "--threads", "1"], "quadphase", "quadphase auto, 1 thr"),
    ("qp-auto-t2", "quadphase", ["--depth", "auto", "--threads", "2"], "quadphase-t2", "quadphase auto, 2 thr"),
    ("qp-auto-t2-passive", "quadphase", ["--depth", "auto", "--threads", "2"], "quadphase-t2p",
     "quadphase auto, 2 thr, OMP_WAIT_POLICY=passive"),
    ("qp-d-2", "quadphase", ["--depth", "auto-2", "--threads", "1"], "quadphase-fixed", "quadphase depth auto-2"),
    ("qp-d-1", "quadphase", ["--depth", "auto-1", "--threads", "1"], "quadphase-fixed", "quadphase depth auto-1"),
    ("qp-d+1", "quadphase", ["--depth", "auto+1", "--threads", "1"], "quadphase-fixed", "quadphase depth auto+1"),
    ("paper-auto-t1", "paper", ["--levels", "auto", "--threads", "1"], "paper", "paper auto levels, 1 thr"),
    ("paper-auto-t2", "paper", ["--levels", "auto", "--threads", "2"], "paper-t2", "paper auto levels, 2 thr"),
    ("paper-auto-t2-passive", "paper", ["--levels", "auto", "--threads", "2"], "paper-t2p",
     "paper auto levels, 2 thr, OMP_WAIT_POLICY=passive"),
    ("paper-l-2", "paper", ["--levels", "auto-2", "--threads", "1"], "paper-coarse", "paper levels auto-2"),
    ("paper-l-4", "paper", ["--levels", "auto-4", "--threads", "1"], "paper-coarse", "paper levels auto-4"),
]
# Configurations that are also run at every step setting (the others only at the default).
SWEEP_STEPS = ("stock", "qp-auto-t1", "paper-auto-t1")

FAMILY_COLOURS = {
    "stock": "#000000",
    "quadphase": "#1f4fd0",
    "quadphase-t2": "#17becf",
    "quadphase-t2p": "#8c564b",
    "quadphase-fixed": "#2ca02c",
    "paper": "#d62728",
    "paper-t2": "#ff7f0e",
    "paper-t2p": "#e377c2",
    "paper-coarse": "#9467bd",
}
STEP_MARKERS = {
    (60, 8, 3): "o",
    (30, 8, 3): "v",
    (120, 8, 3): "^",
    (240, 8, 3): "s",
    (60, 4, 2): "<",
    (60, 16, 6): ">",
}


def step_label(step):
    return "%d Hz, %d/%d it" % step


def run_key(scene, bp, step):
    return "%s|%s|%d|%d|%d" % ((scene, bp) + tuple(step))


def run_one(runner, scene, size, seconds, bp_build, bp_args, step, positions_out=None, passive=False):
    hz, vi, pi = step
    argv = ["--scene", scene, "--size", size, "--seconds", seconds, "--hz", hz, "--vel-iters", vi, "--pos-iters", pi]
    argv += list(bp_args) + (["--positions-out", positions_out] if positions_out else [])
    env = {"OMP_WAIT_POLICY": "passive" if passive else None, "GOMP_SPINCOUNT": None}
    return json.loads(runner.run("qp-accuracy-" + bp_build, *argv, env=env)[1].strip().splitlines()[-1])


def read_positions(path):
    samples = {}
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            t = round(float(parts[0]), 6)
            samples[t] = [float(v) for v in parts[1:]]
    return samples


def deviation(path, ref_path):
    """Mean over the common sample times of the RMS (over dynamic bodies) position difference, and the final one."""
    a = read_positions(path)
    b = read_positions(ref_path)
    times = sorted(set(a) & set(b))
    rms = []
    for t in times:
        pa, pb = a[t], b[t]
        if len(pa) != len(pb) or not pa:
            return float("nan"), float("nan")
        n = len(pa) // 2
        s = sum((pa[2 * i] - pb[2 * i]) ** 2 + (pa[2 * i + 1] - pb[2 * i + 1]) ** 2 for i in range(n))
        rms.append(math.sqrt(s / n))
    if not rms:
        return float("nan"), float("nan")
    return sum(rms) / len(rms), rms[-1]


def plan(scenes):
    runs = []
    for scene, size, seconds in scenes:
        for key, build, args, family, label in BROADPHASES:
            steps = STEP_SETTINGS if key in SWEEP_STEPS else [DEFAULT_STEP]
            for step in steps:
                runs.append(dict(scene=scene, size=size, seconds=seconds, bp=key, build=build, args=args,
                                 family=family, label=label, step=step))
    return runs


def sweep(args, runner, workdir, scenes):
    runs = plan(scenes)
    posdir = os.path.join(workdir, "positions")
    os.makedirs(posdir, exist_ok=True)
    results = {}
    loads = []
    rng = random.Random(args.seed)
    started = time.time()

    # Reference runs first (untimed for the report: only their positions are used).
    references = {}
    for scene, size, seconds in scenes:
        if scene not in NON_CHAOTIC:
            continue
        ref_path = os.path.join(posdir, "%s.reference.txt" % scene)
        rec = run_one(runner, scene, size, seconds, "stock", [], REFERENCE_STEP, ref_path)
        references[scene] = (ref_path, rec)
        print("  reference %-9s %s: %.3f s run time per simulated s" % (scene, step_label(REFERENCE_STEP),
                                                                        rec["run_s_per_sim_s"]), flush=True)

    with open(runner.jsonl, "w") as out:
        for rnd in range(args.rounds):
            order = list(runs)
            rng.shuffle(order)
            load_before = os.getloadavg()[0]
            t0 = time.time()
            for i, r in enumerate(order):
                key = run_key(r["scene"], r["bp"], r["step"])
                pos = None
                if rnd == 0 and r["scene"] in references:
                    pos = os.path.join(posdir, key.replace("|", "_") + ".txt")
                rec = run_one(runner, r["scene"], r["size"], r["seconds"], r["build"], r["args"], r["step"], pos,
                              r["bp"].endswith("-passive"))
                rec["round"] = rnd
                rec["config"] = r["bp"]
                out.write(json.dumps(rec) + "\n")
                entry = results.setdefault(key, dict(run=r, records=[], positions=None))
                entry["records"].append(rec)
                if pos:
                    entry["positions"] = pos
                if (i + 1) % 25 == 0:
                    print("  round %d: %d/%d runs, %.0f s" % (rnd + 1, i + 1, len(order), time.time() - t0),
                          flush=True)
            loads.append((load_before, os.getloadavg()[0], time.time() - t0))
            print("round %d done in %.0f s (load average %.2f -> %.2f)" % (rnd + 1, time.time() - t0, load_before,
                                                                           os.getloadavg()[0]), flush=True)
    rows = []
    for key, entry in results.items():
        r = entry["run"]
        recs = entry["records"]
        first = recs[0]
        row = dict(scene=r["scene"], size=r["size"], seconds=r["seconds"], config=r["bp"], label=r["label"],
                   family=r["family"], build=r["build"], hz=r["step"][0], vel_iters=r["step"][1],
                   pos_iters=r["step"][2], threads=first["threads"], depth=first["depth"],
                   auto_depth=first["auto_depth"], levels=first["levels"], auto_levels=first["auto_levels"],
                   rounds=len(recs),
                   run_ms_per_sim_s=1000.0 * min(x["run_s_per_sim_s"] for x in recs),
                   run_ms_per_sim_s_max=1000.0 * max(x["run_s_per_sim_s"] for x in recs),
                   checks=first["checks"], overlapping=first["overlapping"], missed=first["missed"],
                   missed_new=first["missed_new"], missed_static=first.get("missed_static"),
                   missed_max=first["missed_max"],
                   missed_per_check=first["missed"] / max(1, first["checks"]),
                   checks_with_miss=first["checks_with_miss"],
                   missed_all_rounds=";".join(str(x["missed"]) for x in recs),
                   rounds_agree=len(set((x["missed"], x["pen_max"], x["top_dx"]) for x in recs)) == 1,
                   pen_max_mm=1000.0 * first["pen_max"], pen_mean_mm=1000.0 * first["pen_mean"],
                   energy_drift=first["energy_drift"], energy_max_dev=first["energy_max_dev"],
                   top_dx=first["top_dx"], top_dy=first["top_dy"], bodies=first["bodies"],
                   fixtures=first["fixtures"], cxx_flags=first["cxx_flags"])
        if r["scene"] in references and entry["positions"]:
            mean_dev, final_dev = deviation(entry["positions"], references[r["scene"]][0])
            row["deviation_mean"] = mean_dev
            row["deviation_final"] = final_dev
        rows.append(row)
    order_bp = [b[0] for b in BROADPHASES]
    rows.sort(key=lambda x: ([s[0] for s in scenes].index(x["scene"]), order_bp.index(x["config"]),
                             STEP_SETTINGS.index((x["hz"], x["vel_iters"], x["pos_iters"]))))
    ref_rows = {}
    for scene, (path, rec) in references.items():
        ref_rows[scene] = dict(top_dx=rec["top_dx"], top_dy=rec["top_dy"], pen_max_mm=1000 * rec["pen_max"],
                               pen_mean_mm=1000 * rec["pen_mean"],
                               run_ms_per_sim_s=1000 * rec["run_s_per_sim_s"], missed=rec["missed"])
    meta = dict(loads=loads, elapsed=time.time() - started, rounds=args.rounds, references=ref_rows,
                finished=datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M"))
    return rows, meta


# --------------------------------------------------------------------------------------------------------------
# Plots


def measures_for(scene):
    m = [("missed_per_check", "missed contacts per check"), ("pen_max_mm", "max penetration (mm)"),
         ("pen_mean_mm", "mean penetration (mm)")]
    if scene in ENERGY:
        m.append(("abs_energy_drift", "|energy drift| after the run"))
    if scene in TOP_BOX:
        m.append(("abs_top_dx", "top box horizontal drift (m)"))
    if scene in NON_CHAOTIC:
        m.append(("deviation_mean", "deviation from reference (m, RMS)"))
    return m


def value(row, measure):
    if measure == "abs_energy_drift":
        v = row.get("energy_drift")
        return abs(v) if v is not None else None
    if measure == "abs_top_dx":
        v = row.get("top_dx")
        return abs(v) if v is not None else None
    v = row.get(measure)
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return None
    return v


def pareto(points):
    """Points (x, y) not dominated by another (smaller or equal in both, smaller in one)."""
    front = []
    for p in sorted(points):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    return front


def plot_scene(plt, scene, rows, path):
    from matplotlib.lines import Line2D

    measures = measures_for(scene)
    ncols = 3
    nrows = (len(measures) + 1 + ncols - 1) // ncols  # one extra panel for the legend
    fig, axes = plt.subplots(nrows, ncols, figsize=(13, 4.0 * nrows), dpi=72)
    axes = [a for line in (axes if nrows > 1 else [axes]) for a in line]
    srows = [r for r in rows if r["scene"] == scene]
    for ax, (measure, title) in zip(axes, measures):
        vals = [(r["run_ms_per_sim_s"], value(r, measure), r) for r in srows]
        vals = [v for v in vals if v[1] is not None]
        positive = [v[1] for v in vals if v[1] > 0]
        floor = (min(positive) / 30.0) if positive else 1e-6
        pts = []
        for x, y, r in vals:
            yy = y if y > 0 else floor
            pts.append((x, yy))
            ax.scatter([x], [yy], color=FAMILY_COLOURS[r["family"]],
                       marker=STEP_MARKERS[(r["hz"], r["vel_iters"], r["pos_iters"])], s=42,
                       edgecolors="white" if y > 0 else "black", linewidths=0.6, zorder=3)
        front = pareto(pts)
        if len(front) > 1:
            xs, ys = [], []
            for i, (x, y) in enumerate(front):
                if i > 0:
                    xs.append(x)
                    ys.append(front[i - 1][1])
                xs.append(x)
                ys.append(y)
            ax.plot(xs, ys, color="#888888", linestyle="--", linewidth=1, zorder=2)
        if any(v[1] <= 0 for v in vals):
            ax.axhline(floor, color="#bbbbbb", linestyle=":", linewidth=1, zorder=1)
            ax.text(0.99, floor, " = 0 (plotted here)", transform=ax.get_yaxis_transform(), ha="right",
                    va="bottom", fontsize=7, color="#777777")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("run time per simulated second (ms)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    legend_ax = axes[len(measures)]
    legend_ax.axis("off")
    handles = []
    seen = set()
    for key, build, args, family, label in BROADPHASES:
        if family in seen:
            continue
        seen.add(family)
        names = [b[4] for b in BROADPHASES if b[3] == family]
        handles.append(Line2D([], [], color=FAMILY_COLOURS[family], marker="o", linestyle="",
                              label=" / ".join(names) if len(names) < 3 else names[0].rsplit(" ", 1)[0] + " (several)"))
    for step, marker in STEP_MARKERS.items():
        handles.append(Line2D([], [], color="#555555", marker=marker, linestyle="", label=step_label(step)))
    handles.append(Line2D([], [], color="#888888", linestyle="--", label="Pareto front"))
    legend_ax.legend(handles=handles, loc="center", fontsize=8, frameon=False)
    for ax in axes[len(measures) + 1:]:
        ax.axis("off")
    size = srows[0]["size"] if srows else 0
    fig.suptitle("%s (size %d): error against run time, log-log (lower left is better)" % (scene, size), fontsize=12)
    plot.save(plt, fig, path)


# --------------------------------------------------------------------------------------------------------------
# Report


def config_text(r):
    passive = ", passive" if r["config"].endswith("-passive") else ""
    if r["build"] == "quadphase":
        d = "auto (%s)" % r["auto_depth"] if r["depth"] is None else "%s" % r["depth"]
        return "quadphase, depth %s, %d thr%s" % (d, r["threads"], passive)
    if r["build"] == "paper":
        return "paper, %s levels, %d thr%s" % (r["levels"], r["threads"], passive)
    return "stock tree"


def write_report(rows, meta, info, scenes, md_path, png_rel, reading_path, command):
    L = []
    L.append("# Error against run time")
    L.append("")
    L.append("Generated by `%s`; sweep finished %s UTC (%.0f min). Raw results: "
             "`BUILD_DIR/accuracy/accuracy.{csv,jsonl}`." % (command, meta.get("finished", "?"), meta["elapsed"] / 60.0))
    if meta.get("merged"):
        L.append("")
        L.append("Results of %d sweeps with `--merge` (finished %s UTC), each over its own scenes with the same "
                 "configurations; the machine's load differed between them." % (len(meta["merged"]),
                                                                               ", ".join(meta["merged"])))
    L.append("")
    L.append("- Machine: %s, %d logical cores (shared with other work while this ran; load average before/after "
             "each round: %s)." % (info["cpu"], info["cores"] or 0,
                                   ", ".join("%.1f/%.1f" % (a, b) for a, b, _ in meta["loads"])))
    flags = rows[0]["cxx_flags"] if rows else "?"
    L.append("- Compiler: %s; flags %s (quadphase's core adds -fopenmp); kernel %s; commit %s." %
             (info["compiler"], flags, info["kernel"], info["commit"]))
    L.append("- %d configurations per round, %d rounds in a shuffled order; run time = the smallest of the rounds; "
             "errors from the first round." % (len(rows), meta["rounds"]))
    L.append("")
    L.append("## What was run")
    L.append("")
    L.append("Three builds of Box2D 2.4.1 from the same source and flags, each stepping the project's example scenes "
             "(`examples/scenes`) through `bench/accuracy/accuracy.cpp`:")
    L.append("")
    L.append("- **stock tree**: untouched Box2D (`b2DynamicTree`).")
    L.append("- **quadphase**: the static quadtree adapter, automatic depth (which re-tunes itself) at 1 and 2 "
             "threads, and fixed depths auto−2, auto−1, auto+1 (auto = the depth it picks for the built scene; relative "
             "depths and levels are clamped to the valid range, so two of them can coincide, as in tumbler).")
    L.append("- **paper**: the paper's design (`bench/baselines/paper_quadtree.h`) as the broadphase, through "
             "`bench/accuracy/paper_box2d` (an adapter like plugin/box2d's). It reports, every `UpdatePairs`, every "
             "pair it finds among all proxies, as the paper does; Box2D drops repeats. Its bounds are fixed: the "
             "box of all shapes of the built scene and of the same scene after 250 steps (measured on an exact, "
             "one-leaf probe run), grown by 5% per side. \"auto\" levels: a leaf side about twice the median fat "
             "box, as quadphase's rule; auto−2 and auto−4 are coarser (bigger leaves, fewer misses, more tests).")
    L.append("")
    L.append("Step settings: the default (60 Hz, 8 velocity / 3 position iterations) for every configuration; "
             "30, 120, 240 Hz and 4/2, 16/6 iterations for the stock tree, quadphase auto (1 thread) and paper "
             "auto (1 thread). The scenes' per-step hooks (spawning, relaunching) keep the scenes' own 60 Hz clock "
             "whatever the rate.")
    L.append("")
    L.append("| scene | size | simulated | bodies / fixtures at the end |")
    L.append("|---|---|---|---|")
    for scene, size, seconds in scenes:
        r = next((x for x in rows if x["scene"] == scene and x["config"] == "stock"), None)
        L.append("| %s | %d | %.0f s | %s |" % (scene, size, seconds,
                                              "%d / %d" % (r["bodies"], r["fixtures"]) if r else "?"))
    L.append("")
    L.append("## What each number means")
    L.append("")
    L.append("- **Run time per simulated second**: wall time spent in `b2World::Step` only, divided by the simulated "
             "time (the checks below run between steps and are not timed).")
    L.append("- **Missed contacts**: after every step, every pair of fixture children whose shapes overlap "
             "(`b2TestOverlap` on the shapes at the current transforms; candidates from the checker's own grid, "
             "never the broadphase under test) and that Box2D should collide (different bodies, one of them "
             "dynamic, no joint with collideConnected = false between them, the world's contact filter agrees: "
             "b2ContactManager's rules) but has no `b2Contact`. *missed* sums these over the checks (a pair missed "
             "for 20 steps counts 20); *new* counts a pair once each time it becomes missed; *per check* = missed / "
             "checks; *with a static body* counts the missed pairs (as *missed*) in which one body is static (grounds, "
             "walls, tiles). Box2D creates a contact for every pair of overlapping fat AABBs, so an exact broadphase gives 0 "
             "by construction; `tests/accuracy` checks that the checker does find missing contacts.")
    L.append("- **Penetration**: every touching contact's manifold re-evaluated at the end-of-step transforms "
             "(`b2Contact::Evaluate`); depth = max(0, −separation) per manifold point; max and mean over all points "
             "of all checks, in mm. Box2D keeps resting contacts about `b2_linearSlop` (5 mm) deep on purpose. "
             "Missed contacts have no manifold and so do not show here: bodies that pass through each other do "
             "not count as penetrating.")
    L.append("- **Energy drift** (particles, no gravity, restitution 1): kinetic energy at the end / at the start "
             "− 1. Box2D's restitution is inelastic below `b2_velocityThreshold` (1 m/s), so the exact run loses "
             "energy too.")
    L.append("- **Top box drift** (pyramid, tiles): horizontal displacement of the top box of the 20-row pyramid "
             "after the run (10 s); the stack is symmetric, so an ideal solver keeps it at 0.")
    L.append("- **Deviation from reference** (pyramid, tiles only: a settling stack is not chaotic, small "
             "differences do not grow; rain, tumbler, particles, bullets and sparse are chaotic, and any change in "
             "contact order makes them diverge, so a deviation there measures chaos, not error): the stock tree at "
             "4× the default rate and iterations (%s); every 0.5 s of simulated time, the RMS over the dynamic "
             "bodies of the distance between their positions and the reference's; the mean over the 20 samples." %
             step_label(REFERENCE_STEP))
    L.append("")

    # Missed-contact summary.
    L.append("## Missed contacts per configuration")
    L.append("")
    L.append("Missed contacts (summed over the checks, after every step) at the default step settings; in brackets, "
             "the range over the other step settings for the three swept configurations.")
    L.append("")
    L.append("| configuration | " + " | ".join(s[0] for s in scenes) + " |")
    L.append("|---|" + "---|" * len(scenes))
    for key, build, args, family, label in BROADPHASES:
        cells = []
        for scene, size, seconds in scenes:
            rs = [r for r in rows if r["scene"] == scene and r["config"] == key]
            d = [r for r in rs if (r["hz"], r["vel_iters"], r["pos_iters"]) == DEFAULT_STEP]
            cell = str(d[0]["missed"]) if d else "–"
            others = [r["missed"] for r in rs if (r["hz"], r["vel_iters"], r["pos_iters"]) != DEFAULT_STEP]
            if others:
                cell += " (%d–%d)" % (min(others), max(others))
            cells.append(cell)
        L.append("| %s | %s |" % (label, " | ".join(cells)))
    L.append("")
    exact = [r for r in rows if r["build"] in ("stock", "quadphase")]
    paper = [r for r in rows if r["build"] == "paper"]
    L.append("Exact builds (stock and quadphase, %d runs): %d missed contacts in total. Paper design (%d runs): "
             "%d missed in total (%d of them with a static body), in %d of %d runs." %
             (len(exact), sum(r["missed"] for r in exact), len(paper), sum(r["missed"] for r in paper),
              sum(r.get("missed_static") or 0 for r in paper),
              len([r for r in rows if r["build"] == "paper" and r["missed"] > 0]),
              len([r for r in rows if r["build"] == "paper"])))
    disagree = [r for r in rows if not r["rounds_agree"]]
    if disagree:
        L.append("")
        L.append("Runs whose error measures differed between rounds (non-deterministic pair order): " +
                 ", ".join("%s %s %s (missed per round: %s)" % (r["scene"], r["config"],
                                                                 step_label((r["hz"], r["vel_iters"], r["pos_iters"])),
                                                                 r["missed_all_rounds"]) for r in disagree) + ".")
    L.append("")

    if os.path.exists(reading_path):
        L.append("## Reading")
        L.append("")
        with open(reading_path) as f:
            L.append(f.read().strip())
        L.append("")

    L.append("## Per scene")
    L.append("")
    L.append("Every plot: x = run time per simulated second (ms), y = one error measure, log-log; colour = "
             "broadphase configuration, marker = step settings; the dashed staircase is the Pareto front (no other "
             "run is both faster and more accurate). Errors that are exactly 0 are drawn on the dotted line at "
             "the bottom.")
    L.append("")
    for scene, size, seconds in scenes:
        srows = [r for r in rows if r["scene"] == scene]
        if not srows:
            continue
        L.append("### %s" % scene)
        L.append("")
        L.append("![%s](%s/%s.png)" % (scene, png_rel, scene))
        L.append("")
        extra_h, extra = [], []
        if scene in ENERGY:
            extra_h.append("energy drift")
            extra.append(lambda r: fmt(r["energy_drift"], 3))
        if scene in TOP_BOX:
            extra_h.append("top box dx (m)")
            extra.append(lambda r: fmt(r["top_dx"], 3))
        if scene in NON_CHAOTIC:
            extra_h.append("deviation mean / final (m)")
            extra.append(lambda r: "%s / %s" % (fmt(r.get("deviation_mean"), 3), fmt(r.get("deviation_final"), 3)))
        L.append("| configuration | step | ms per sim. s (max round) | missed | new | with a static body | per check "
                 "| max in a check | pen. max (mm) | pen. mean (mm) | " + " | ".join(extra_h) + (" |" if extra_h else ""))
        L.append("|---|---|---|---|---|---|---|---|---|---|" + "---|" * len(extra_h))
        for r in srows:
            cells = [config_text(r), step_label((r["hz"], r["vel_iters"], r["pos_iters"])),
                     "%s (%s)" % (fmt(r["run_ms_per_sim_s"]), fmt(r["run_ms_per_sim_s_max"])), str(r["missed"]),
                     str(r["missed_new"]), fmt(r.get("missed_static")), fmt(r["missed_per_check"]), str(r["missed_max"]), fmt(r["pen_max_mm"]),
                     fmt(r["pen_mean_mm"])] + [f(r) for f in extra]
            L.append("| " + " | ".join(cells) + " |")
        if scene in meta["references"]:
            ref = meta["references"][scene]
            L.append("")
            L.append("Reference run (stock, %s): %s ms per simulated second, missed %d, penetration max %s mm / mean "
                     "%s mm, top box dx %s m." % (step_label(REFERENCE_STEP), fmt(ref["run_ms_per_sim_s"]),
                                                  ref["missed"], fmt(ref["pen_max_mm"]), fmt(ref["pen_mean_mm"]),
                                                  fmt(ref["top_dx"])))
        L.append("")
    with open(md_path, "w") as f:
        f.write("\n".join(L) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build-dir", required=True, help="build directory holding bench/accuracy/qp-accuracy-*")
    p.add_argument("--rounds", type=int, default=2, help="rounds of every configuration (default 2)")
    p.add_argument("--scenes", default=",".join(s[0] for s in SCENES), help="comma-separated subset of: " +
                   ",".join(s[0] for s in SCENES))
    p.add_argument("--seed", type=int, default=1, help="seed of the shuffled run order")
    p.add_argument("--md", default=os.path.join(ROOT, "docs", "accuracy.md"), help="report to write")
    p.add_argument("--png-dir", default=os.path.join(ROOT, "docs", "accuracy"), help="folder of the plots")
    p.add_argument("--merge", action="store_true",
                   help="keep the last sweep's results for the scenes not run now (BUILD_DIR/accuracy/accuracy.json)")
    p.add_argument("--replot", action="store_true",
                   help="do not run: rewrite plots and report from BUILD_DIR/accuracy/accuracy.json")
    p.add_argument("--command", default="bench/accuracy/run.sh", help="command named in the report")
    args = p.parse_args()
    if args.rounds < 1:
        p.error("--rounds must be >= 1")
    wanted = [s for s in args.scenes.split(",") if s]
    unknown = [s for s in wanted if s not in [x[0] for x in SCENES]]
    if unknown:
        p.error("unknown scene(s): " + ", ".join(unknown))
    scenes = [s for s in SCENES if s[0] in wanted]

    tools = os.path.join(args.build_dir, "bench", "accuracy")
    workdir = os.path.join(args.build_dir, "accuracy")
    os.makedirs(workdir, exist_ok=True)
    state = os.path.join(workdir, "accuracy.json")
    if args.replot:
        with open(state) as f:
            saved = json.load(f)
        rows, meta, info = saved["rows"], saved["meta"], saved["info"]
        if "finished" not in meta:  # results written before the field existed: the raw results' time
            meta["finished"] = datetime.datetime.utcfromtimestamp(
                os.path.getmtime(os.path.join(workdir, "accuracy.jsonl"))).strftime("%Y-%m-%d %H:%M")
        scenes = [s for s in SCENES if any(r["scene"] == s[0] for r in rows)]
    else:
        runner = run.Runner("accuracy.py", tools, workdir, "accuracy",
                            tools=["qp-accuracy-" + b for b in ("stock", "quadphase", "paper")])
        info = machine.describe(args.build_dir)
        print("%s, %s cores; %s; commit %s" % (info["cpu"], info["cores"], info["compiler"], info["commit"]))
        print("%d runs per round, %d round(s)" % (len(plan(scenes)), args.rounds), flush=True)
        rows, meta = sweep(args, runner, workdir, scenes)
        if args.merge and os.path.exists(state):
            # Earlier results of the other scenes stay; the report lists every sweep's load and duration.
            with open(state) as f:
                saved = json.load(f)
            ran = set(x[0] for x in scenes)
            rows = [r for r in saved["rows"] if r["scene"] not in ran] + rows
            old = saved["meta"]
            meta["loads"] = old["loads"] + meta["loads"]
            meta["elapsed"] += old["elapsed"]
            meta["references"] = dict(old["references"], **meta["references"])
            meta["merged"] = old.get("merged", [old.get("finished", "?")]) + [meta["finished"]]
            rows.sort(key=lambda x: [s[0] for s in SCENES].index(x["scene"]))
            scenes = [s for s in SCENES if any(r["scene"] == s[0] for r in rows)]
        with open(state, "w") as f:
            json.dump(dict(rows=rows, meta=meta, info=info), f)
        report.write_csv(os.path.join(workdir, "accuracy.csv"), rows)

    os.makedirs(args.png_dir, exist_ok=True)
    plt = plot.pyplot("accuracy.py")
    for scene, size, seconds in scenes if plt else []:
        plot_scene(plt, scene, rows, os.path.join(args.png_dir, scene + ".png"))
    png_rel = os.path.relpath(args.png_dir, os.path.dirname(os.path.abspath(args.md)))
    write_report(rows, meta, info, scenes, args.md, png_rel, os.path.join(HERE, "reading.md"), args.command)
    print("wrote %s, %s/*.png, %s/accuracy.csv" % (args.md, args.png_dir, workdir))


if __name__ == "__main__":
    main()
