#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The report of a bench/manycore.sh run: bench/results/manycore.{md,csv,png} from the raw results a prepared folder's
run.sh wrote (OUT: machine.txt, build.json, timing.txt, replay.jsonl, circles.jsonl, frames.jsonl, mismatch.txt).
Run it through bench/manycore.sh --report OUT. --describe BUILD_DIR prints the build's part of the machine description
(compiler, flags, git commit, Box2D source checksum) as JSON: bench/manycore.sh --prepare puts it in the folder."""

import argparse
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from qpbench import frames, plot, report  # noqa: E402
from qpbench.report import num as fmt, table  # noqa: E402
from qpbench.stats import amdahl, karp_flatt, serial_fractions  # noqa: E402
from quadphase_tools import machine  # noqa: E402
from quadphase_tools.stats import med, ratio  # noqa: E402

TEXT = report.prose(os.path.join(HERE, "prose", "manycore.md"))
GOALS = {"whole": 5.0, "find": 10.0, "circles": 5.0}  # on 16 cores, the most threads over 1 thread
FRAME_ENGINES = ("stock", "1 thread", "defaults", "job system")
TICK = frames.TICK
NAN = float("nan")


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", nargs="?", help="a run's raw results (DIR/run.sh --out OUT)")
    ap.add_argument("--results", default=os.path.join(HERE, "results"), help="where manycore.* go (bench/results)")
    ap.add_argument("--describe", metavar="BUILD_DIR", help="print the build's description as JSON and exit")
    a = ap.parse_args()
    if not a.describe and not a.out:
        ap.error("give a run's OUT directory (or --describe BUILD_DIR)")
    return a


def read_lines(path):
    """The JSON lines of a file; none when it is missing."""
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def read_keyed(path):
    """A run's 'key value' text file as a dict (lscpu's lines, 'lscpu Key: value', under their own keys)."""
    info = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f.read().splitlines():
                k, _, v = line.partition(" ")
                if k == "lscpu":
                    k, _, v = v.partition(":")
                    if k.strip() in machine.LSCPU_KEYS:
                        info[k.strip()] = v.strip()
                elif k:
                    info[k] = v.strip()
    return info


def minutes(times):
    """Minutes of CPU from bash's `times` line of the children ("7m40.7s 0m2.9s": user, system); None without one."""
    parts = [re.fullmatch(r"(\d+)m([\d.]+)s", t) for t in (times or "").split()]
    return sum(int(m[1]) + float(m[2]) / 60 for m in parts) if parts and all(parts) else None


def machine_info(out):
    """The run's machine (machine.txt) over the build's description (build.json): report.machine_section's fields."""
    run = read_keyed(os.path.join(out, "machine.txt"))
    # The build machine's compiler, flags, commit and Box2D source; the measured machine's hardware and load.
    info = {k: v for k, v in report.read_json(os.path.join(out, "build.json")).items()
            if k not in machine.LSCPU_KEYS and k not in ("cpu", "cores", "kernel", "loadavg_start", "omp_env")}
    info.update({k: v for k, v in run.items() if k in machine.LSCPU_KEYS})
    info.update(cpu=run.get("cpu", "?"), cores=int(run.get("cores", 0)), kernel=run.get("kernel", "?"),
                loadavg_start=run.get("loadavg_start", "").split(), loadavg_end=run.get("loadavg_end", "").split(),
                omp_env=dict(kv.split("=", 1) for kv in run.get("omp_env", "").split() if "=" in kv),
                default_config=run.get("default_config", ""),
                quiet_samples=[float(v) for k, v in run.items() if k.startswith("busy_before_")])
    return info, run


# ----------------------------------------------------------------------------------------------------------------
# Replay
# ----------------------------------------------------------------------------------------------------------------
def replay_cases(rows):
    """Per trace (in recording order): its display name, stock's ms/step, the pair-set checks, and per thread count
    the medians over the rounds of the whole work, FindPairs and outside FindPairs (ms/step)."""
    cases = {}
    for r in rows:
        c = cases.setdefault(r["trace"], dict(name=f"{r['scene']} {r['size']:,}", warmup=r["warmup"], threads={},
                                              checks={}, stock=NAN))
        engine = r.get("engine", "quadtree")  # (a quadtree configuration's check line names no engine)
        if r["kind"] == "check" and engine == "quadtree":
            c["checks"][r["threads"]] = r["mismatches"] == 0 and r["compared_file"] == 1
        elif r["kind"] == "run" and engine == "stock":
            c["stock"] = r["step_ns"] * 1e-6
        elif r["kind"] == "run" and engine == "quadtree":
            c["steps"] = r["steps"]
            c["threads"].setdefault(r["threads"], []).append(r)
    for c in cases.values():
        c["ms"] = {t: {k: med([f(r) for r in rs]) for k, f in (
            ("whole", lambda r: r["step_ns"] * 1e-6), ("find", lambda r: r["find_ns"] * 1e-6),
            ("outside", lambda r: (r["step_ns"] - r["find_ns"]) * 1e-6),
            # The core's own clock around its cell upkeep (applying the queued moves, re-placing the proxies that
            # changed cell): inside FindPairs, since the adapter's moves are queued; the rest of FindPairs is the
            # search and its joins.
            ("upkeep", lambda r: r.get("replace_s", NAN) * 1e3 / r["steps"]),
            ("search", lambda r: r["find_ns"] * 1e-6 - r.get("replace_s", NAN) * 1e3 / r["steps"]))}
            for t, rs in sorted(c["threads"].items())}
        c["rounds"] = max((len(rs) for rs in c["threads"].values()), default=0)
    return [c for c in cases.values() if c["ms"]]


def speedups(c, what):
    """{threads: the 1-thread time ÷ the time at that many threads} of one figure (whole, find, outside)."""
    one = c["ms"].get(1, {}).get(what)
    return {t: ratio(one, m[what]) for t, m in c["ms"].items()}


def bound_ms(c, t):
    """The whole work's ms/step at t threads if FindPairs scaled perfectly and the work outside it did not change:
    outside (Box2D's serial MoveProxy calls) plus FindPairs ÷ t, both at 1 thread. Amdahl's law with the outside
    share as the serial part: the whole work's speed-up cannot exceed the 1-thread time over this."""
    one = c["ms"][1]
    return one["outside"] + one["find"] / t


def replay_section(cases, counts, mismatch):
    p = counts[-1]
    L = ["## Replay: the broadphase work against threads", "", TEXT["replay"].format(
        repeats=max(c["rounds"] for c in cases), **GOALS), ""]
    rows = []
    for c in cases:
        label = f"{c['name']} ({c['warmup']} + {c['steps']} steps)"
        for k, (what, name) in enumerate((("whole", "ms/step"), ("find", "FindPairs"),
                                          ("upkeep", "of which cell upkeep"), ("search", "of which the search"),
                                          ("outside", "outside FindPairs"))):
            s = speedups(c, what)
            rows.append([label if k == 0 else "", name] + [fmt(c["ms"][t][what]) if t in c["ms"] else "–"
                                                           for t in counts]
                        + [f"**{fmt(s.get(p))}×**" if what in ("whole", "find") else f"{fmt(s.get(p))}×"])
        rows.append(["", "bound: outside at 1 thread + FindPairs ÷ threads"] + [
            fmt(bound_ms(c, t)) if 1 in c["ms"] else "–" for t in counts]
            + [f"{fmt(ratio(c['ms'][1]['whole'], bound_ms(c, p)))}×" if 1 in c["ms"] else ""])
        sw = speedups(c, "whole")
        rows.append(["", "serial fraction (Karp–Flatt), whole"] + [
            fmt(karp_flatt(sw.get(t), t)) if t > 1 and t in c["ms"] else "–" for t in counts] + [""])
    L += table(["trace", ""] + [f"{t} thread{'s' if t > 1 else ''}" for t in counts] + [f"{p} ÷ 1"], rows) + [""]
    L.append("Stock `b2BroadPhase` on the same traces: " + ", ".join(
        f"{c['name']} {fmt(c['stock'])} ms/step (stock ÷ quadphase at 1 thread "
        f"{fmt(ratio(c['stock'], c['ms'][1]['whole']))}×, at {p} threads "
        f"{fmt(ratio(c['stock'], c['ms'][p]['whole']))}×)" for c in cases) + ".")
    checked = ", ".join(f"{c['name']} at {' and '.join(str(t) for t in sorted(c['checks']))} threads "
                        + ("identical" if all(c["checks"].values()) else "**DIFFERENT**") for c in cases)
    L += ["", f"Pair sets of every `UpdatePairs` call against stock's (`--check all`): {checked}."
          + (f" **qp-replay reported a mismatch: {mismatch}**" if mismatch else ""), ""]
    goal = []
    for c in cases:
        sw, sf = speedups(c, "whole"), speedups(c, "find")
        rising = all((c["ms"][b]["whole"] <= c["ms"][a]["whole"]) for a, b in zip(counts, counts[1:]))
        goal.append(f"{c['name']}: whole {fmt(sw.get(p))}× (≥{GOALS['whole']:g})"
                    f"{TICK[(sw.get(p) or 0) >= GOALS['whole']]} (at most "
                    f"{fmt(ratio(c['ms'][1]['whole'], bound_ms(c, p)))}× while the moves are serial), "
                    f"FindPairs {fmt(sf.get(p))}× "
                    f"(≥{GOALS['find']:g}){TICK[(sf.get(p) or 0) >= GOALS['find']]}, "
                    f"every thread count at least as fast as the one below{TICK[rising]}")
    L += [f"Goals at {p} threads{'' if p >= 16 else ' (they are set for 16)'}: " + "; ".join(goal) + ".", ""]
    return L


def projection_section(cases, counts):
    """Amdahl from the serial fractions measured at the most threads (when they are fewer than 16): the section's
    lines, and (trace, s, s if the outside work were parallel) of the traces the plot projects."""
    p = counts[-1]
    if p >= 16 or p < 2:
        return [], []
    rows, fits = [], []
    for c in cases:
        one = c["ms"][1]
        r = dict(share=one["outside"] / one["whole"], ef=karp_flatt(speedups(c, "find").get(p), p))
        s, s2 = serial_fractions(r)
        if (speedups(c, "find").get(p) or 0) >= 1.0:  # else there is nothing to project (see projection_void)
            fits.append((c["name"], s, s2))
        rows.append([c["name"], fmt(r["share"]), fmt(r["ef"]), fmt(s)] + [fmt(amdahl(s, q), 1) for q in (4, 8, 16)]
                    + [fmt(s2), fmt(amdahl(s2, 16), 1)])
    L = ["## Projection to 16 cores from the measured serial fractions", "", TEXT["projection"].format(p=p), ""]
    slower = [c["name"] for c in cases if (speedups(c, "find").get(p) or 0) < 1.0]
    if slower:
        L += [TEXT["projection_void"].format(p=p, traces=", ".join(slower)), ""]
    L += table(["trace", "m (outside share, 1 thread)", f"e_F (FindPairs, {p} threads)", "s", "projected 4 threads",
                "8", "16", "s if the outside work were parallel", "then 16"], rows) + [""]
    return L, fits


# ----------------------------------------------------------------------------------------------------------------
# Circles and frames
# ----------------------------------------------------------------------------------------------------------------
def circles_results(rows):
    """{(engine, threads): (circles, capped)} of the searches' results."""
    return {(r["engine"], r["threads"]): (r["n_max"], r["capped"]) for r in rows if r.get("kind") == "result"}


def circles_bound(rows, p):
    """(f, bound): pair finding's share f of quadphase's 1-thread frame at its largest passing size, and the most its
    count can grow at p threads while the rest of the frame runs on one thread, 1 / (1 - f + f/p) (Amdahl, with the
    frame's work in proportion to the circles). (None, None) for runs whose qp-circles did not report the share."""
    f = next((r.get("find_share") for r in rows if r.get("kind") == "result" and r["engine"] == "quadtree"
              and r["threads"] == 1), None)
    return (f, 1.0 / (1.0 - f + f / p)) if f is not None else (None, None)


def circles_section(res, counts, cap, bound=(None, None)):
    if not res:
        return []
    p, one = counts[-1], res.get(("quadtree", 1), (None, 0))[0]
    n = [res.get(("quadtree", t), (None, 0)) for t in counts]
    rising = all((b[0] or 0) >= (a[0] or 0) for a, b in zip(n, n[1:]))
    x = ratio(n[-1][0], one)
    L = ["## The paper's protocol: circles under 20 ms per frame against threads", "",
         TEXT["circles"].format(cap=cap, goal=f"{GOALS['circles']:g}"), ""]
    L += table(["", *(f"{t} thread{'s' if t > 1 else ''}" for t in counts), f"{p} ÷ 1", "stock"], [
        ["quadphase"] + [f"{fmt(v)}{' (capped)' if capped else ''}" for v, capped in n]
        + [f"**{fmt(x)}×**", fmt(res.get(("stock", 1), (None, 0))[0])]]) + [""]
    f, most = bound
    if f is not None:
        L += [TEXT["circles_bound"].format(share=f"{100 * f:.0f}", p=p, most=fmt(most)), ""]
    return L + [f"Goal at {p} threads{'' if p >= 16 else ' (set for 16)'}: ≥{GOALS['circles']:g}×"
                f"{TICK[(x or 0) >= GOALS['circles']]}"
                + (f" (at most {fmt(most)}× while the rest of the frame is serial)" if f is not None else "")
                + f"; rising with the threads{TICK[rising]}.", ""]


def frames_section(rows, run):
    if not rows:
        return []
    by = {(r["scene"], r["size"], r["busy"], r["engine"]): r for r in rows}
    cases = sorted({k[:3] for k in by}, key=lambda k: (k[0], k[1], k[2]))
    L = ["## Frames: broadphase time and the process's CPU time", "",
         TEXT["frames"].format(steps=run.get("frame_steps"), jobs=run.get("job_workers"), cpu=frames.CPU_GOAL), ""]
    def cell(r):
        return f"{fmt(r.get('bp_total'))}; {fmt(r.get('cpu_s'))} ({fmt(ratio(r.get('cpu_s'), r.get('wall_s')), 1)})"
    L += table(["scene", "busy"] + [f"{e}: bp ms; CPU s (cores)" for e in FRAME_ENGINES], [
        [f"{s} {n:,}", "yes" if b else "no"] + [cell(by.get((s, n, b, e)) or {}) for e in FRAME_ENGINES]
        for s, n, b in cases]) + [""]
    goal_rows, misses = [], []
    for s, n, b in cases:
        a, one, d = (by.get((s, n, b, e)) or {} for e in ("stock", "1 thread", "defaults"))
        total = ratio(one.get("bp_total"), d.get("bp_total"))
        cpu_x, cpu_ok = frames.cpu_goal(d, one)
        worst_ok = d.get("bp_max", 1e9) <= a.get("bp_max", 0)
        ok = [(total or 0) >= 1.0, cpu_ok, worst_ok]
        misses += [f"{s} {n}{' busy' if b else ''}"] if not all(ok) else []
        goal_rows.append([f"{s} {n:,}", "yes" if b else "no", f"{fmt(total)}{TICK[ok[0]]}",
                          f"{fmt(cpu_x)}{TICK[cpu_ok]}",
                          f"{fmt(d.get('bp_max'), 3)} / {fmt(a.get('bp_max'), 3)}{TICK[worst_ok]}"])
    L += ["**The defaults' goals**", ""] + table(
        ["scene", "busy", "bp total: 1 thread ÷ defaults (≥1)", f"CPU: defaults ÷ 1 thread (≤{frames.CPU_GOAL})",
         "worst bp step ms: defaults / stock (≤1)"], goal_rows)
    return L + ["", "Misses: " + (", ".join(misses) or "none") + ".", ""]


# ----------------------------------------------------------------------------------------------------------------
# CSV and plot
# ----------------------------------------------------------------------------------------------------------------
def rounded(x, digits=4):
    return round(x, digits) if isinstance(x, float) and not math.isnan(x) else x


def csv_rows(cases, circles, frame_rows):
    """manycore.csv: one row per replay (trace, engine, threads), circles search and frames run (scene, busy,
    engine); a section's rows fill its own columns."""
    out = []
    for c in cases:
        sw, sf = speedups(c, "whole"), speedups(c, "find")
        out.append(dict(section="replay", case=c["name"], engine="stock", ms_per_step=c["stock"]))
        out += [dict(section="replay", case=c["name"], engine="quadtree", threads=t, rounds=len(c["threads"][t]),
                     ms_per_step=m["whole"], find_ms_per_step=m["find"], outside_ms_per_step=m["outside"],
                     upkeep_ms_per_step=m["upkeep"], search_ms_per_step=m["search"],
                     speedup=sw[t], find_speedup=sf[t],
                     pairs_identical={True: "yes", False: "no"}.get(c["checks"].get(t), "not checked"))
                for t, m in c["ms"].items()]
    one = circles.get(("quadtree", 1), (None,))[0]
    out += [dict(section="circles", case="circles under 20 ms", engine=e, threads=t, circles=n, capped=cap,
                 speedup=ratio(n, one) if e == "quadtree" else "") for (e, t), (n, cap) in sorted(circles.items())]
    out += [dict(section="frames", case=f"{r['scene']} {r['size']}", engine=r["engine"], busy=r["busy"],
                 bp_total_ms=r["bp_total"], bp_max_ms=r["bp_max"], bp_p99_ms=r["bp_p99"], step_total_ms=r["step_total"],
                 cpu_s=r.get("cpu_s"), wall_s=r.get("wall_s")) for r in frame_rows]
    return [{k: rounded(v) for k, v in r.items()} for r in out]


def figure(path, cases, counts, circles, frame_rows, fits):
    plt = plot.pyplot("manycore.py")
    if plt is None:
        return False
    fig, (ax, ax2, ax3) = plt.subplots(1, 3, figsize=(15, 4.2), dpi=80)
    top = max(16, counts[-1])
    for i, c in enumerate(cases):
        ts = sorted(c["ms"])
        for what, style, name in (("whole", "-o", "whole work"), ("find", "--s", "FindPairs")):
            s = speedups(c, what)
            ax.plot(ts, [s[t] for t in ts], f"C{i}{style}", markersize=4, label=f"{c['name']}: {name}")
    for i, (name, s, _) in enumerate(fits):
        ps = list(range(1, 17))
        ax.plot(ps, [amdahl(s, p) for p in ps], f"C{i}:", linewidth=1, label=f"{name}: projected (s = {s:.2f})")
    ax.plot([1, top], [1, top], ":", color="grey", linewidth=0.8, label="ideal")
    ax.set(xscale="log", yscale="log", xlabel="threads", ylabel="speed-up over 1 thread",
           title="replay: speed-up against threads")
    ticks = [t for t in (1, 2, 4, 8, 16, 32, 64) if t <= top]
    for a in (ax, ax2):
        a.set_xscale("log")
        a.minorticks_off()
        a.set_xticks(ticks, [str(t) for t in ticks])
        a.set_xlim(0.9, top * 1.1)
        a.grid(True, alpha=0.3)
    ax.set_yticks(ticks, [str(t) for t in ticks])
    ax.minorticks_off()
    ax.legend(fontsize=7)
    ts = [t for t in counts if ("quadtree", t) in circles]
    ax2.plot(ts, [circles[("quadtree", t)][0] for t in ts], "C0-o", label="quadphase")
    if ("stock", 1) in circles:
        ax2.axhline(circles[("stock", 1)][0], ls=":", color="green", label="stock b2DynamicTree")
    ax2.set(xlabel="threads", ylabel="circles under 20 ms per frame", title="the paper's protocol", ylim=(0, None))
    ax2.legend(fontsize=7)
    cases3 = sorted({(r["scene"], r["size"], r["busy"]) for r in frame_rows})
    by = {(r["scene"], r["size"], r["busy"], r["engine"]): r for r in frame_rows}
    width = 0.8 / len(FRAME_ENGINES)
    for k, e in enumerate(FRAME_ENGINES):
        ax3.bar([i + (k - 1.5) * width for i in range(len(cases3))],
                [(by.get(c + (e,)) or {}).get("cpu_s") or 0 for c in cases3], width, label=e, color=f"C{k}")
    ax3.set_xticks(range(len(cases3)), [f"{s} {n}{' busy' if b else ''}" for s, n, b in cases3], rotation=30,
                   ha="right", fontsize=7)
    ax3.set(ylabel="process CPU s over the run", title="frames: CPU time by engine")
    ax3.legend(fontsize=7)
    ax3.grid(True, axis="y", alpha=0.3)
    plot.save(plt, fig, path)
    return True


def main():
    args = parse_args()
    if args.describe:
        print(json.dumps(machine.describe(args.describe), indent=1))
        return 0
    out = args.out
    if not os.path.exists(os.path.join(out, "build.json")):
        sys.exit(f"manycore.py: {out} holds no run (no build.json): give the --out directory of DIR/run.sh")
    info, run = machine_info(out)
    timing = read_keyed(os.path.join(out, "timing.txt"))
    counts = [int(t) for t in run.get("threads", "1").split()]
    mismatch = open(os.path.join(out, "mismatch.txt")).read().strip() \
        if os.path.exists(os.path.join(out, "mismatch.txt")) else ""
    cases = replay_cases(read_lines(os.path.join(out, "replay.jsonl")))
    circle_rows = read_lines(os.path.join(out, "circles.jsonl"))
    circles = circles_results(circle_rows)
    _, frame_rows = frames.frame_rows(read_lines(os.path.join(out, "frames.jsonl")))
    os.makedirs(args.results, exist_ok=True)
    parts = {k: timing.get(k, "?") for k in ("record", "check", "replay", "circles", "frames")}
    cpu = minutes(timing.get("tools_cpu"))
    L = ["# Many cores: pair generation against threads, and the CPU the defaults take", "",
         TEXT["header"].format(profile=run.get("profile", "?"), cores=info["cores"], minutes=int(
             timing.get("total", 0)) / 60, repeats=run.get("repeats"), **parts)
         + (f" The tools used {cpu:.1f} min of CPU (user plus system, all their threads)." if cpu else ""), ""]
    if mismatch:
        L += [f"**PAIR SETS DIFFER FROM STOCK'S: {mismatch}. These timings are not valid.**", ""]
    proj, fits = projection_section(cases, counts)
    if figure(os.path.join(args.results, "manycore.png"), cases, counts, circles, frame_rows, fits):
        L += ["![speed-up against threads (replay), circles against threads, CPU seconds of the frames scenes]"
              "(manycore.png)", ""]
    L += replay_section(cases, counts, mismatch) if cases else []
    L += circles_section(circles, counts, run.get("circles_cap_s"), circles_bound(circle_rows, counts[-1]))
    L += frames_section(frame_rows, run)
    L += proj
    L += report.machine_section(info)
    report.write_lines(os.path.join(args.results, "manycore.md"), L)
    report.write_csv(os.path.join(args.results, "manycore.csv"), csv_rows(cases, circles, frame_rows))
    print(f"manycore.py: wrote {args.results}/manycore.md, manycore.csv"
          + (", manycore.png" if os.path.exists(os.path.join(args.results, "manycore.png")) else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
