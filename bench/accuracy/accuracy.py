#!/usr/bin/python3
# SPDX-License-Identifier: MIT
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
from qpbench import plot, report, run  # noqa: E402
from qpbench.report import sig as fmt, table  # noqa: E402
from quadphase_tools import machine  # noqa: E402

# (scene, size, simulated seconds). Modest sizes: the whole sweep (2 rounds) took about 25 minutes on 2 busy cores.
SCENES = [("pyramid", 20, 10.0), ("tiles", 1000, 10.0), ("particles", 1000, 10.0), ("rain", 1000, 5.0),
          ("tumbler", 200, 5.0), ("bullets", 100, 5.0), ("sparse", 1000, 5.0), ("shooter", 200, 5.0),
          ("openworld", 500, 5.0), ("mixed", 200, 5.0), ("terrain", 300, 5.0), ("churn", 500, 5.0)]
SCENE_NAMES = [s[0] for s in SCENES]
# Scenes that settle rather than diverge: the only ones compared with a reference run.
NON_CHAOTIC = ("pyramid", "tiles")
# Scenes with the pyramid whose top box drift is reported.
TOP_BOX = ("pyramid", "tiles")
ENERGY = ("particles",)

DEFAULT_STEP = (60, 8, 3)
STEP_SETTINGS = [DEFAULT_STEP, (30, 8, 3), (120, 8, 3), (240, 8, 3), (60, 4, 2), (60, 16, 6)]
REFERENCE_STEP = (240, 32, 12)  # 4x the default rate and 4x the default iterations


def _threads(key, build, option, family, what):
    """A design at its automatic depth: 1 thread, 2 threads, 2 threads with OMP_WAIT_POLICY=passive."""
    auto = [option, "auto", "--threads"]
    return [(f"{key}-auto-t1", build, auto + ["1"], family, f"{what}, 1 thr"),
            (f"{key}-auto-t2", build, auto + ["2"], family + "-t2", f"{what}, 2 thr"),
            (f"{key}-auto-t2-passive", build, auto + ["2"], family + "-t2p",
             f"{what}, 2 thr, OMP_WAIT_POLICY=passive")]


def _fixed(key, build, option, family, what, offsets):
    """A design at fixed offsets from its automatic depth, 1 thread."""
    return [(key + o, build, [option, "auto" + o, "--threads", "1"], family, f"{what} auto{o}") for o in offsets]


# Broadphase configurations: key, build, extra arguments, family (colour), label. A key ending in "-passive" runs
# with OMP_WAIT_POLICY=passive (libgomp's idle threads sleep instead of spinning; see the report).
BROADPHASES = ([("stock", "stock", [], "stock", "stock tree")]
               + _threads("qp", "quadphase", "--depth", "quadphase", "quadphase auto")
               + _fixed("qp-d", "quadphase", "--depth", "quadphase-fixed", "quadphase depth", ("-2", "-1", "+1"))
               + _threads("paper", "paper", "--levels", "paper", "paper auto levels")
               + _fixed("paper-l", "paper", "--levels", "paper-coarse", "paper levels", ("-2", "-4")))
# Configurations that are also run at every step setting (the others only at the default).
SWEEP_STEPS = ("stock", "qp-auto-t1", "paper-auto-t1")

FAMILY_COLOURS = {"stock": "#000000", "quadphase": "#1f4fd0", "quadphase-t2": "#17becf", "quadphase-t2p": "#8c564b",
                  "quadphase-fixed": "#2ca02c", "paper": "#d62728", "paper-t2": "#ff7f0e", "paper-t2p": "#e377c2",
                  "paper-coarse": "#9467bd"}
STEP_MARKERS = dict(zip(STEP_SETTINGS, "ov^s<>"))
TEXT = report.prose(os.path.join(os.path.dirname(HERE), "prose", "accuracy.md"))  # the report's prose

# Error measures of every scene (plotted), then those of some scenes: the scenes, the plotted measure and its title,
# the report's column and its cell.
MEASURES = [("missed_per_check", "missed contacts per check"), ("pen_max_mm", "max penetration (mm)"),
            ("pen_mean_mm", "mean penetration (mm)")]
SCENE_MEASURES = [
    (ENERGY, "abs_energy_drift", "|energy drift| after the run", "energy drift", lambda r: fmt(r["energy_drift"], 3)),
    (TOP_BOX, "abs_top_dx", "top box horizontal drift (m)", "top box dx (m)", lambda r: fmt(r["top_dx"], 3)),
    (NON_CHAOTIC, "deviation_mean", "deviation from reference (m, RMS)", "deviation mean / final (m)",
     lambda r: "%s / %s" % (fmt(r.get("deviation_mean"), 3), fmt(r.get("deviation_final"), 3))),
]


def step_label(step):
    return "%d Hz, %d/%d it" % step


def step_of(row):
    return row["hz"], row["vel_iters"], row["pos_iters"]


def pick(record, keys):
    return {k: record[k] for k in keys.split()}


def run_one(runner, scene, size, seconds, bp_build, bp_args, step, positions_out=None, passive=False):
    hz, vi, pi = step
    argv = ["--scene", scene, "--size", size, "--seconds", seconds, "--hz", hz, "--vel-iters", vi, "--pos-iters", pi]
    argv += list(bp_args) + (["--positions-out", positions_out] if positions_out else [])
    env = {"OMP_WAIT_POLICY": "passive" if passive else None, "GOMP_SPINCOUNT": None}
    return json.loads(runner.run("qp-accuracy-" + bp_build, *argv, env=env)[1].strip().splitlines()[-1])


def read_positions(path):
    with open(path) as f:
        return {round(float(p[0]), 6): [float(v) for v in p[1:]] for p in map(str.split, f) if p}


def deviation(path, ref_path):
    """Mean over the common sample times of the RMS (over dynamic bodies) position difference, and the final one."""
    a, b = read_positions(path), read_positions(ref_path)
    rms = []
    for t in sorted(set(a) & set(b)):
        pa, pb, n = a[t], b[t], len(a[t]) // 2
        if len(pa) != len(pb) or not pa:
            return float("nan"), float("nan")
        rms.append(math.sqrt(sum((pa[2 * i] - pb[2 * i]) ** 2 + (pa[2 * i + 1] - pb[2 * i + 1]) ** 2
                                 for i in range(n)) / n))
    return (sum(rms) / len(rms), rms[-1]) if rms else (float("nan"), float("nan"))


def plan(scenes):
    """Every run of a round: the first fields of its row (in the CSV's order) and the broadphase's arguments."""
    return [(dict(scene=scene, size=size, seconds=seconds, config=key, label=label, family=family, build=build,
                  hz=step[0], vel_iters=step[1], pos_iters=step[2]), args)
            for scene, size, seconds in scenes for key, build, args, family, label in BROADPHASES
            for step in (STEP_SETTINGS if key in SWEEP_STEPS else [DEFAULT_STEP])]


def sweep(args, runner, workdir, scenes):
    runs = plan(scenes)
    posdir = os.path.join(workdir, "positions")
    os.makedirs(posdir, exist_ok=True)
    results, loads, rng, started = {}, [], random.Random(args.seed), time.time()

    # Reference runs first (untimed for the report: only their positions are used).
    references, ref_rows = {}, {}  # positions file, report line
    for scene, size, seconds in scenes:
        if scene in NON_CHAOTIC:
            references[scene] = os.path.join(posdir, "%s.reference.txt" % scene)
            rec = run_one(runner, scene, size, seconds, "stock", [], REFERENCE_STEP, references[scene])
            ref_rows[scene] = dict(top_dx=rec["top_dx"], top_dy=rec["top_dy"], pen_max_mm=1000 * rec["pen_max"],
                                   pen_mean_mm=1000 * rec["pen_mean"], run_ms_per_sim_s=1000 * rec["run_s_per_sim_s"],
                                   missed=rec["missed"])
            print("  reference %-9s %s: %.3f s run time per simulated s" % (scene, step_label(REFERENCE_STEP),
                                                                            rec["run_s_per_sim_s"]), flush=True)

    with open(runner.jsonl, "w") as out:
        for rnd in range(args.rounds):
            order = list(runs)
            rng.shuffle(order)
            load_before, t0 = os.getloadavg()[0], time.time()
            for i, (r, bp_args) in enumerate(order):
                key = "%s|%s|%d|%d|%d" % ((r["scene"], r["config"]) + step_of(r))
                # Positions of the first round only, for the deviation from the reference.
                pos = rnd == 0 and r["scene"] in references and os.path.join(posdir, key.replace("|", "_") + ".txt")
                rec = run_one(runner, r["scene"], r["size"], r["seconds"], r["build"], bp_args, step_of(r), pos,
                              r["config"].endswith("-passive"))
                rec["round"], rec["config"] = rnd, r["config"]
                out.write(json.dumps(rec) + "\n")
                results.setdefault(key, dict(run=r, records=[], positions=pos))["records"].append(rec)
                if (i + 1) % 25 == 0:
                    print("  round %d: %d/%d runs, %.0f s" % (rnd + 1, i + 1, len(order), time.time() - t0),
                          flush=True)
            loads.append((load_before, os.getloadavg()[0], time.time() - t0))
            print("round %d done in %.0f s (load average %.2f -> %.2f)" % (rnd + 1, time.time() - t0, load_before,
                                                                           os.getloadavg()[0]), flush=True)
    rows = []
    for key, entry in results.items():
        r, recs = entry["run"], entry["records"]
        first = recs[0]
        row = dict(r, **pick(first, "threads depth auto_depth levels auto_levels"), rounds=len(recs),
                   run_ms_per_sim_s=1000.0 * min(x["run_s_per_sim_s"] for x in recs),
                   run_ms_per_sim_s_max=1000.0 * max(x["run_s_per_sim_s"] for x in recs),
                   **pick(first, "checks overlapping missed missed_new"), missed_static=first.get("missed_static"),
                   missed_max=first["missed_max"], missed_per_check=first["missed"] / max(1, first["checks"]),
                   checks_with_miss=first["checks_with_miss"],
                   missed_all_rounds=";".join(str(x["missed"]) for x in recs),
                   rounds_agree=len(set((x["missed"], x["pen_max"], x["top_dx"]) for x in recs)) == 1,
                   pen_max_mm=1000.0 * first["pen_max"], pen_mean_mm=1000.0 * first["pen_mean"],
                   **pick(first, "energy_drift energy_max_dev top_dx top_dy bodies fixtures cxx_flags"))
        if r["scene"] in references and entry["positions"]:
            row["deviation_mean"], row["deviation_final"] = deviation(entry["positions"], references[r["scene"]])
        rows.append(row)
    rows.sort(key=lambda x: (SCENE_NAMES.index(x["scene"]), [b[0] for b in BROADPHASES].index(x["config"]),
                             STEP_SETTINGS.index(step_of(x))))
    meta = dict(loads=loads, elapsed=time.time() - started, rounds=args.rounds, references=ref_rows,
                finished=datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M"))
    return rows, meta


# --------------------------------------------------------------------------------------------------------------
# Plots


def value(row, measure):
    v = row.get(measure[4:] if measure.startswith("abs_") else measure)
    if measure.startswith("abs_"):  # the size of a signed measure ("abs_top_dx": |top_dx|)
        return abs(v) if v is not None else None
    return None if v is None or (isinstance(v, float) and math.isnan(v)) else v


def pareto(points):
    """Points (x, y) not dominated by another (smaller or equal in both, smaller in one)."""
    front = []
    for p in sorted(points):
        if not front or p[1] < front[-1][1]:
            front.append(p)
    return front


def plot_scene(plt, scene, rows, path):
    from matplotlib.lines import Line2D

    measures = MEASURES + [(m, title) for scenes, m, title, _, _ in SCENE_MEASURES if scene in scenes]
    nrows = (len(measures) + 3) // 3  # three columns, and one extra panel for the legend
    fig, axes = plt.subplots(nrows, 3, figsize=(13, 4.0 * nrows), dpi=72)
    axes = [a for line in (axes if nrows > 1 else [axes]) for a in line]
    srows = [r for r in rows if r["scene"] == scene]
    for ax, (measure, title) in zip(axes, measures):
        vals = [v for v in ((r["run_ms_per_sim_s"], value(r, measure), r) for r in srows) if v[1] is not None]
        positive = [v[1] for v in vals if v[1] > 0]
        floor = (min(positive) / 30.0) if positive else 1e-6
        for x, y, r in vals:
            ax.scatter([x], [y if y > 0 else floor], color=FAMILY_COLOURS[r["family"]], marker=STEP_MARKERS[step_of(r)],
                       s=42, edgecolors="white" if y > 0 else "black", linewidths=0.6, zorder=3)
        front = pareto([(x, y if y > 0 else floor) for x, y, _ in vals])
        if len(front) > 1:  # the front as a staircase
            ax.step(*zip(*front), where="post", color="#888888", linestyle="--", linewidth=1, zorder=2)
        if any(v[1] <= 0 for v in vals):
            ax.axhline(floor, color="#bbbbbb", linestyle=":", linewidth=1, zorder=1)
            ax.text(0.99, floor, " = 0 (plotted here)", transform=ax.get_yaxis_transform(), ha="right",
                    va="bottom", fontsize=7, color="#777777")
        ax.set(xscale="log", yscale="log", xlabel="run time per simulated second (ms)")
        ax.set_title(title, fontsize=10)
        ax.grid(True, which="major", linewidth=0.4, alpha=0.5)
    handles = []
    for family in dict.fromkeys(b[3] for b in BROADPHASES):
        names = [b[4] for b in BROADPHASES if b[3] == family]
        handles.append(Line2D([], [], color=FAMILY_COLOURS[family], marker="o", linestyle="",
                              label=" / ".join(names) if len(names) < 3 else names[0].rsplit(" ", 1)[0] + " (several)"))
    handles += [Line2D([], [], color="#555555", marker=marker, linestyle="", label=step_label(step))
                for step, marker in STEP_MARKERS.items()]
    handles.append(Line2D([], [], color="#888888", linestyle="--", label="Pareto front"))
    for ax in axes[len(measures):]:  # the first of them holds the legend
        ax.axis("off")
    axes[len(measures)].legend(handles=handles, loc="center", fontsize=8, frameon=False)
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


def missed_cell(rows, key, scene):
    """Missed contacts of a configuration in a scene at the default step settings, and their range at the others."""
    rs = [r for r in rows if r["scene"] == scene and r["config"] == key]
    d = [r["missed"] for r in rs if step_of(r) == DEFAULT_STEP]
    others = [r["missed"] for r in rs if step_of(r) != DEFAULT_STEP]
    return (str(d[0]) if d else "–") + (" (%d–%d)" % (min(others), max(others)) if others else "")


def write_report(rows, meta, info, scenes, md_path, png_rel, reading_path, command):
    L = ["# Error against run time", "", TEXT["header"].format(command=command, finished=meta.get("finished", "?"),
                                                              minutes=meta["elapsed"] / 60.0)]
    if meta.get("merged"):
        L += ["", TEXT["merged"].format(sweeps=len(meta["merged"]), finished=", ".join(meta["merged"]))]
    L += ["", TEXT["machine"].format(
        cpu=info["cpu"], cores=info["cores"] or 0, loads=", ".join("%.1f/%.1f" % (a, b) for a, b, _ in meta["loads"]),
        compiler=info["compiler"], flags=rows[0]["cxx_flags"] if rows else "?", kernel=info["kernel"],
        commit=info["commit"], configurations=len(rows), rounds=meta["rounds"]),
          "", "## What was run", "", TEXT["builds"], "", TEXT["build_list"], "", TEXT["step_settings"], ""]
    L += table(["scene", "size", "simulated", "bodies / fixtures at the end"],
               [[scene, "%d" % size, "%.0f s" % seconds, next(("%d / %d" % (r["bodies"], r["fixtures"]) for r in rows
                                                               if r["scene"] == scene and r["config"] == "stock"), "?")]
                for scene, size, seconds in scenes])
    L += ["", "## What each number means", "", TEXT["meanings"].format(reference=step_label(REFERENCE_STEP)),
          "", "## Missed contacts per configuration", "", TEXT["missed"], ""]
    L += table(["configuration"] + [s[0] for s in scenes],
               [[label] + [missed_cell(rows, key, s[0]) for s in scenes] for key, _, _, _, label in BROADPHASES])
    exact = [r for r in rows if r["build"] in ("stock", "quadphase")]
    paper = [r for r in rows if r["build"] == "paper"]
    L += ["", TEXT["totals"].format(
        exact=len(exact), exact_missed=sum(r["missed"] for r in exact), paper=len(paper),
        paper_missed=sum(r["missed"] for r in paper), paper_static=sum(r.get("missed_static") or 0 for r in paper),
        paper_missing=len([r for r in paper if r["missed"] > 0]))]
    disagree = [r for r in rows if not r["rounds_agree"]]
    if disagree:
        L += ["", "Runs whose error measures differed between rounds (non-deterministic pair order): " +
              ", ".join("%s %s %s (missed per round: %s)" % (r["scene"], r["config"], step_label(step_of(r)),
                                                              r["missed_all_rounds"]) for r in disagree) + "."]
    L.append("")
    if os.path.exists(reading_path):
        with open(reading_path) as f:
            L += ["## Reading", "", f.read().strip(), ""]
    L += ["## Per scene", "", TEXT["per_scene"], ""]
    for scene, size, seconds in scenes:
        srows = [r for r in rows if r["scene"] == scene]
        if not srows:
            continue
        extra = [(head, cell) for scenes_of, _, _, head, cell in SCENE_MEASURES if scene in scenes_of]
        T = table(["configuration", "step", "ms per sim. s (max round)", "missed", "new", "with a static body",
                   "per check", "max in a check", "pen. max (mm)", "pen. mean (mm)"] + [h for h, _ in extra],
                  [[config_text(r), step_label(step_of(r)),
                    "%s (%s)" % (fmt(r["run_ms_per_sim_s"]), fmt(r["run_ms_per_sim_s_max"])), str(r["missed"]),
                    str(r["missed_new"]), fmt(r.get("missed_static")), fmt(r["missed_per_check"]), str(r["missed_max"]),
                    fmt(r["pen_max_mm"]), fmt(r["pen_mean_mm"])] + [cell(r) for _, cell in extra] for r in srows])
        if not extra:
            T[0] += " "  # the published reports' header ends in "| " when a scene has no columns of its own
        L += ["### %s" % scene, "", "![%s](%s/%s.png)" % (scene, png_rel, scene), ""] + T
        if scene in meta["references"]:
            ref = meta["references"][scene]
            L += ["", TEXT["reference"].format(step=step_label(REFERENCE_STEP), ms=fmt(ref["run_ms_per_sim_s"]),
                                              missed=ref["missed"], pen_max=fmt(ref["pen_max_mm"]),
                                              pen_mean=fmt(ref["pen_mean_mm"]), top_dx=fmt(ref["top_dx"]))]
        L.append("")
    with open(md_path, "w") as f:
        f.write("\n".join(L) + "\n")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--build-dir", required=True, help="build directory holding bench/accuracy/qp-accuracy-*")
    p.add_argument("--rounds", type=int, default=2, help="rounds of every configuration (default 2)")
    p.add_argument("--scenes", default=",".join(SCENE_NAMES),
                   help="comma-separated subset of: " + ",".join(SCENE_NAMES))
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
    unknown = [s for s in wanted if s not in SCENE_NAMES]
    if unknown:
        p.error("unknown scene(s): " + ", ".join(unknown))
    scenes = [s for s in SCENES if s[0] in wanted]

    workdir = os.path.join(args.build_dir, "accuracy")
    os.makedirs(workdir, exist_ok=True)
    state = os.path.join(workdir, "accuracy.json")
    if args.replot:
        saved = report.read_json(state)
        rows, meta, info = saved["rows"], saved["meta"], saved["info"]
        if "finished" not in meta:  # results written before the field existed: the raw results' time
            meta["finished"] = datetime.datetime.utcfromtimestamp(
                os.path.getmtime(os.path.join(workdir, "accuracy.jsonl"))).strftime("%Y-%m-%d %H:%M")
    else:
        runner = run.Runner("accuracy.py", os.path.join(args.build_dir, "bench", "accuracy"), workdir, "accuracy",
                            tools=["qp-accuracy-" + b for b in ("stock", "quadphase", "paper")])
        info = machine.describe(args.build_dir)
        print("%s, %s cores; %s; commit %s" % (info["cpu"], info["cores"], info["compiler"], info["commit"]))
        print("%d runs per round, %d round(s)" % (len(plan(scenes)), args.rounds), flush=True)
        rows, meta = sweep(args, runner, workdir, scenes)
        if args.merge and os.path.exists(state):
            # Earlier results of the other scenes stay; the report lists every sweep's load and duration.
            saved = report.read_json(state)
            rows = [r for r in saved["rows"] if r["scene"] not in wanted] + rows
            old = saved["meta"]
            meta.update(loads=old["loads"] + meta["loads"], elapsed=meta["elapsed"] + old["elapsed"],
                        references=dict(old["references"], **meta["references"]),
                        merged=old.get("merged", [old.get("finished", "?")]) + [meta["finished"]])
            rows.sort(key=lambda x: SCENE_NAMES.index(x["scene"]))
        with open(state, "w") as f:
            json.dump(dict(rows=rows, meta=meta, info=info), f)
        report.write_csv(os.path.join(workdir, "accuracy.csv"), rows)
    # The scenes with results (those of earlier sweeps too after --merge), in SCENES order.
    scenes = [s for s in SCENES if any(r["scene"] == s[0] for r in rows)]

    os.makedirs(args.png_dir, exist_ok=True)
    plt = plot.pyplot("accuracy.py")
    for scene, size, seconds in scenes if plt else []:
        plot_scene(plt, scene, rows, os.path.join(args.png_dir, scene + ".png"))
    png_rel = os.path.relpath(args.png_dir, os.path.dirname(os.path.abspath(args.md)))
    write_report(rows, meta, info, scenes, args.md, png_rel, os.path.join(HERE, "reading.md"), args.command)
    print("wrote %s, %s/*.png, %s/accuracy.csv" % (args.md, args.png_dir, workdir))


if __name__ == "__main__":
    main()
