# SPDX-License-Identifier: MIT
"""bench.py's in-engine phases section (RESULTS.md 1b): qp-step from the first step of rain, every step reported
with its phase; the falling, piling and resting phases apart, each build's own and over the same steps."""

from quadphase_tools.stats import med, ratio

from .bench_common import HEADLINE_ENGINES, QUADTREES, TEXT, keyed, scaled, section, threads
from .report import num as fmt, table
from .step import STEP_ENGINES, step_rows

# Phase runs from the first step: (scene, size, steps). Rain 16k's first 200 steps: where quadphase
# once measured 0.77x stock at OMP_NUM_THREADS=2.
PHASE_RUNS = {"quick": [("rain", 4000, 900), ("rain", 16000, 200)],
              "full": [("rain", 4000, 1500), ("rain", 16000, 200), ("rain", 16000, 1000)]}
PHASES = ("falling", "piling", "resting")
PHASE_FIELDS = [f"{p}_{k}" for p in PHASES for k in ("first", "steps", "step_ms", "broadphase_ms")]
# phases.csv's columns after PHASE_FIELDS: the same steps in both builds (fair_phases)
FAIR_FIELDS = [k.format(p) for p in PHASES for k in ("fair_{}_steps", "fair_{}_stock_bp_ms", "fair_{}_bp_ms",
                                                       "{}_stock_us_per_awake", "{}_qt_us_per_awake")]


def phase_units(args):
    """One unit = one qp-step run per round (step.run_step): ("phases", scene, size, build, threads, steps)."""
    return [("phases", s, scaled(n, args, 2), b, t, steps) for s, n, steps in PHASE_RUNS[args.profile]
            for b, t in STEP_ENGINES]


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


def phase_rows(groups):
    """phases.csv's rows: each build's own phases (medians over rounds) plus the same-steps comparison."""
    fair = fair_phases(groups)
    return [dict(r, **fair.get((r["scene"], r["size"], r["steps"], r["engine"]), {}))
            for r in step_rows(groups, "phases", PHASE_FIELDS + ["continuous", "bodies"])]


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
