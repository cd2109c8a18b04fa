# SPDX-License-Identifier: MIT
"""bench.py's circles section (RESULTS.md 4): the paper's protocol, the most circles whose collision detection
stays under 20 ms per frame (qp-circles), beside the paper's published Tables 1 and 2."""

import os

from . import paper, plot, run
from .bench_common import TEXT, section
from .report import table

# The paper's protocol configurations: (engine, threads, depth); depth None = automatic.
CIRCLES = {
    "quick": [("pairwise", 1, None), ("paper", 1, None), ("stock", 1, None), ("quadtree", 1, None),
              ("quadtree", 2, None)],
    "full": [("pairwise", 1, None), ("stock", 1, None)] + [(e, t, d) for e in ("paper", "quadtree") for t in (1, 2)
                                                          for d in (4, 5, 6, 7, 8, 9, None)],
}


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


def circles_rows(circles):
    """circles.csv's rows from the searches' results, keyed (engine, threads, depth; depth < 0: automatic)."""
    return [dict(engine=e, threads=t, depth="auto" if d < 0 else d,
                 **{k: r[k] for k in ("n_max", "capped", "evaluations", "seconds")})
            for (e, t, d), r in sorted(circles.items())]


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


def circles_figure(plt, res, d, plots):
    """The paper's table: circles under 20 ms by depth, here and in the paper (results/paper_table.png)."""
    from matplotlib.ticker import FuncFormatter
    if not d["circles"]:
        return
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
