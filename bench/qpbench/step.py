# SPDX-License-Identifier: MIT
"""bench.py's in-engine step section (RESULTS.md 1): qp-step-stock and qp-step-quadtree (one source, two Box2D
builds) step every scene at Box2D's defaults, quadtree at OMP_NUM_THREADS=1 and 2; b2Profile, contacts, pairs, peak
memory, medians over rounds. The phases section runs the same tool (run_step)."""

import math
import os

from quadphase_tools.stats import med, ratio

from . import plot
from .bench_common import LABELS, QUADTREES, TEXT, keyed, scaled, section, x_stock
from .report import num as fmt, table

# Step benchmark sizes per scene (scenes not listed here: their default size, and in the full profile also 4x it).
STEP_SIZES = {
    "quick": {"pyramid": [20], "rain": [4000], "tumbler": [400], "tiles": [4000], "particles": [10000],
              "bullets": [500], "sparse": [4000]},
    "full": {"pyramid": [20, 60], "rain": [4000, 16000, 32000], "tumbler": [400, 800], "tiles": [4000, 20000],
             "particles": [2000, 10000, 20000, 50000], "bullets": [500, 2000], "sparse": [4000, 20000]},
}
STEP_ENGINES = [("stock", 1), ("quadtree", 1), ("quadtree", 2)]  # (build, OMP_NUM_THREADS)
STEP_CSV = ["step_ms", "collide_ms", "solve_ms", "broadphase_ms", "toi_ms", "contacts_mean", "new_pairs_per_step",
            "pairs_reported_per_step", "qt_find_ms_per_step", "peak_rss_bytes", "bp_bytes_per_proxy"]
STEP_FIELDS = STEP_CSV + ["proxies", "bodies", "continuous", "qt_parallel_calls_per_step"]


def step_units(runner, args):
    """One unit = one tool run per round: ("step", scene, size, build, OMP_NUM_THREADS)."""
    units = []
    scene_list = runner.run("qp-step-stock", "--list")[1].splitlines()
    for scene, lo, hi, default in (line.split("\t")[0].split() for line in scene_list):
        lo, hi, default = int(lo), int(hi), int(default)
        for size in STEP_SIZES[args.profile].get(scene) or [default] + ([4 * default] if args.full else []):
            units += [("step", scene, min(hi, max(lo, scaled(size, args, lo))), b, t) for b, t in STEP_ENGINES]
    return list(dict.fromkeys(units))


def run_step(runner, args, part, u, rnd):
    """One qp-step run of a step or phases unit (phases: from the first step, every step reported)."""
    _, scene, size, build, omp = u[:5]
    warmup, steps = (0, u[5]) if part == "phases" else ((40, 40) if args.full else (20, 20))
    runner.run(f"qp-step-{build}", "--scene", scene, "--size", size, "--seed", args.seed, "--warmup", warmup,
               "--steps", steps, "--threads", "default", "--ccd", args.ccd, "--json", runner.jsonl,
               "--label", f"{part} r{rnd}", *(["--per-step"] if part == "phases" else []),
               env={"OMP_NUM_THREADS": str(omp)})


def step_rows(groups, part, fields):
    """Medians over rounds, one row per (scene, size, steps, engine) of a part ("step" or "phases")."""
    out = [dict({"scene": scene, "size": size, "steps": steps, "engine": name, "rounds": len(runs)},
                **{k: med([x.get(k) for x in runs]) for k in fields})
           for (p, scene, size, steps, name), runs in groups.items() if p == part]
    return sorted(out, key=lambda r: (r["scene"], r["size"], r["steps"], r["engine"]))


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


def step_figure(plt, res, d, plots):
    """Ratio bars per scene: stock / quadtree, whole step and b2Profile::broadphase (results/step_ratios.png)."""
    from matplotlib.ticker import FuncFormatter
    by, cases = keyed(d["step"]), sorted({(r["scene"], r["size"]) for r in d["step"]})
    if not cases:
        return
    fig, axes = plt.subplots(2, 1, figsize=(max(8, 0.55 * len(cases) + 2), 7.5), sharex=True)
    for ax, metric, title in ((axes[0], "step_ms", "whole step (b2Profile::step)"),
                              (axes[1], "broadphase_ms", "broadphase (b2Profile::broadphase)")):
        for k, (eng, color) in enumerate(zip(QUADTREES, ("#4c72b0", "#dd8452"))):
            ax.bar([x + (k - 0.5) * 0.4 for x in range(len(cases))],
                   [x_stock(by, c, eng, metric) or 0 for c in cases], 0.4, color=color, label=LABELS[eng])
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
