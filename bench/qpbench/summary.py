# SPDX-License-Identifier: MIT
"""bench.py's RESULTS.md: its header and machine, the headline (every target against what this run measured), the
frames goals, each section's table (the section modules write them), both optimisation levels side by side, notes."""

from quadphase_tools.stats import ratio

from . import report
from .bench_common import PARTS, QUADTREES, TEXT, keyed, section, threads, x_stock
from .circles import circles_section
from .phases import phase_lows, phase_section
from .queries import QUERY_GOALS, QUERY_WORKLOADS, floor_ms, query_section
from .replay import replay_section
from .report import num as fmt, table
from .step import step_section

# Stock's figures and the circles counts measured on this machine earlier: the headline's reference rows.
REFERENCE = {"circles_stock": 52000, "circles_brute": 6200, "replay_stock_particles50k": 490,
             "replay_stock_rain64k": 510, "step_bp_stock_particles10k": 3.3, "step_bp_stock_particles50k": 43.9}


def met(ok):
    return "met" if ok else ("not met" if ok is False else "n/a")


def markdown(info, data, levels, plots, frame_goals=()):
    d = data[levels[0]]
    by, rp = keyed(d["step"]), keyed(d["replay"])
    # bench/run.sh's levels: --full means both unless --opt says one, the quick profile O2 unless it says O3.
    full = info["profile"] == "full"
    command = (" --full" if full else "") + (" --opt both" if len(levels) > 1 else "")
    if len(levels) == 1 and (full or levels[0] != "O2"):
        command += " --opt " + levels[0]
    if info.get("parts") and list(info["parts"]) != list(PARTS):  # a run of some parts only
        command += " --parts " + ",".join(info["parts"])
    if info.get("replay_engines"):
        command += " --replay-engines " + info["replay_engines"]
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
    if info.get("engines_left_out"):
        L.append(f"- not replayed in this run (--replay-engines): {', '.join(info['engines_left_out'])}")
    L += [""] + headline(d, by, rp, levels[0])
    if frame_goals:  # "## Goals" becomes this report's frames section, with the per-step tables in frames.md
        L += ["## Frames: worst step and total at the defaults", "",
              f"The goals from this run's frames section: {info.get('frame_steps', 600)} steps from the first, "
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
    L = [f"## Headline: every target against this run ({level})", "",
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


