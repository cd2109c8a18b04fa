# SPDX-License-Identifier: MIT
"""bench.py's replay section (RESULTS.md 2, 2a, 2b): one recorded trace per scene and size through stock
b2BroadPhase, quadphase (1 and 2 threads), brute force (small traces), the paper's design, the tuned Chipmunk2D and
Bullet peers in both modes, the oracle floor and the replay loop alone, a triad per round (memory floor); pair sets
checked on every UpdatePairs call; rain phase traces replayed by phase. A new engine is one entry in REPLAY_ENGINES
and ENGINE_LABEL (and its qp-replay --engine name)."""

import os

from quadphase_tools.stats import med, ratio

from . import plot, report, run
from .bench_common import HEADLINE_ENGINES, LABELS, TEXT, scaled, section, x_stock
from .phases import PHASES
from .report import num as fmt, table

# Replay traces: (scene, size, warm-up steps, timed steps). A trace with warm-up 0 and many steps is a phase trace:
# every step timed, its steps split by phase (qp-record's .phases file); it is replayed by PHASE_ENGINES only.
# The headline traces (particles 50k, 100k, rain 64k) time 30 steps: with 10 (15 ms of quadphase's work per run)
# one stall of this shared VM moved a 2-thread ratio by up to 40% between runs.
REPLAY_TRACES = {
    "quick": [("particles", 2000, 30, 10), ("particles", 10000, 30, 10), ("rain", 16000, 60, 10),
              ("bullets", 500, 60, 10), ("rain", 4000, 0, 900)],
    "full": [("particles", 2000, 60, 20), ("particles", 10000, 60, 20), ("particles", 50000, 30, 30),
             ("particles", 100000, 30, 30), ("rain", 4000, 120, 20), ("rain", 16000, 120, 20),
             ("rain", 65536, 60, 30), ("bullets", 1000, 120, 20), ("sparse", 20000, 60, 20),
             ("tiles", 20000, 60, 200), ("pyramid", 60, 60, 20), ("rain", 4000, 0, 1200), ("rain", 16000, 0, 1000)],
}
CELL_SCALES = ("0.5", "1", "2", "4", "8")  # cpSpaceHash's cell side, x the mean fat box side
# Peers (replay_peers.cpp): Box2D's protocol (pairs of the moved proxies, checked against stock's), and native mode
# (every overlapping pair each step, checked against all overlapping fat-box pairs; -mM: displacement multiplier).
PROTOCOL_PEERS = [f"cp-hash-x{k}" for k in CELL_SCALES] + ["cp-tree", "bt-dbvt"]
NATIVE_PEERS = ["cp-hash-native-x2", "cp-hash-native-x4", "cp-tree-native", "bt-dbvt-native-m0",
                "bt-dbvt-native-m4", "bt-sap-native"]
PEERS = PROTOCOL_PEERS + NATIVE_PEERS
REPLAY_ENGINES = ["stock", "quadtree-1t", "quadtree-2t", "oracle", "paper"] + PEERS + ["brute", "null"]
PHASE_ENGINES = HEADLINE_ENGINES + ["oracle"]
EXACT_ENGINES = ["quadtree-1t", "quadtree-2t", "oracle", "brute"] + PEERS
OPTIONAL = {"cp-": "cp-hash", "bt-": "bt-dbvt"}  # engine prefix -> the word qp-replay --help lists when built
BRUTE_MAX_PROXIES = 5000
SLOW_MAX_PROXIES = 60000  # left out of bigger traces: the paper's design (approximate, 3-6x stock) and Bullet's SAP
SLOW = ("paper", "bt-sap-native")  # (particles 50k: check + 2 replays of bt-sap took over 5 min on a loaded machine)
ENGINE_LABEL = dict(LABELS, **{
    "oracle": "oracle floor: known pairs", "paper": "paper's design (approximate)", "cp-tree": "Chipmunk2D cpBBTree",
    "bt-dbvt": "Bullet btDbvtBroadphase", "cp-tree-native": "Chipmunk2D cpBBTree, native",
    "cp-hash-native-x2": "Chipmunk2D cpSpaceHash 2x, native", "cp-hash-native-x4": "Chipmunk2D cpSpaceHash 4x, native",
    "bt-dbvt-native-m0": "Bullet btDbvt, native, no prediction", "bt-dbvt-native-m4": "Bullet btDbvt, native, 4x",
    "bt-sap-native": "Bullet bt32BitAxisSweep3, native", "brute": "brute force O(n^2)", "null": "replay loop alone"},
    **{f"cp-hash-x{k}": f"Chipmunk2D cpSpaceHash, cell {k}x" for k in CELL_SCALES})
# replay.csv's columns (peers.csv and replay_phases.csv: every field)
REPLAY_CSV = ["opt", "scene", "size", "trace", "engine", "mode", "rounds", "mean_proxies", "ms_per_step",
              "ns_per_proxy_step", "pairs_per_step", "bytes_per_proxy", "exact", "missed_pct", "duplicates_pct",
              "levels"]


def available_engines(runner):
    """The engines of REPLAY_ENGINES this build's qp-replay has (Chipmunk2D and Bullet are optional)."""
    usage = runner.run("qp-replay", "--help")[1]
    built = {w for l in usage.splitlines() if l.startswith("available here:") for w in l.split(":", 1)[1].split()}
    return {e for e in REPLAY_ENGINES if not any(e.startswith(p) and w not in built for p, w in OPTIONAL.items())}


def record_traces(runner, args):
    """The profile's traces (recorded unless a matching one exists), each with its name, proxies and phases."""
    traces = []
    for scene, size, w, s in REPLAY_TRACES[args.profile]:
        path = runner.record(scene, scaled(size, args, 2), w, s)
        traces.append(dict(scene=scene, size=scaled(size, args, 2), warmup=w, steps=s, path=path,
                           name=os.path.basename(path).split(".")[0], proxies=run.trace_proxies(path),
                           phases=[l.strip() for l in open(path + ".phases") if not l.startswith("#")][w:]))
    return traces


def replay_argv(engine, trace, extra):
    if engine.startswith("quadtree"):
        return ["--trace", trace, "--threads", 1 if engine == "quadtree-1t" else 2] + extra
    return (["--trace", trace, "--engine", engine] + extra
            + (["--max-proxies", BRUTE_MAX_PROXIES] if engine == "brute" else []))


def replay_engines(trace, available):
    n = trace["proxies"]
    return [e for e in (PHASE_ENGINES if trace["warmup"] == 0 else REPLAY_ENGINES) if e in available
            and not (e == "brute" and n > BRUTE_MAX_PROXIES) and not (e in SLOW and n > SLOW_MAX_PROXIES)]


def replay_units(traces, available):
    """One unit = one qp-replay run per round: (trace, engine), and the triad (None, "triad")."""
    return [(t, e) for t in traces for e in replay_engines(t, available)] + [(None, "triad")]


def run_replay(runner, u, rnd):
    t, e = u
    extra = ["--repeats", 1, "--json", runner.jsonl, "--label", f"replay r{rnd}"]
    runner.run("qp-replay", *(["--triad"] + extra if e == "triad" else replay_argv(e, t["path"], extra + [
        "--check", "none"])))


def check_replays(runner, units, bar):
    """Untimed: stock's pair-set hashes of every trace, and every exact engine's compared with them."""
    for t, e in sorted(units, key=lambda u: u[1] != "stock"):  # stock's hashes first
        if e not in ("triad", "null"):
            hashes = t["path"] + ".stock.hash"
            extra = ["--repeats", 0, "--check", "first", "--json", runner.jsonl, "--label", "check"]
            extra += ["--hashes-out", hashes] if e == "stock" else ["--compare-hashes", hashes]
            if runner.run("qp-replay", *replay_argv(e, t["path"], extra), ok_codes=(0, 3))[0] == 3:
                print(f"\nbench.py: MISMATCH: {e} on {t['name']} (see {runner.log.name})", flush=True)
        bar.step(f"check {(t or {}).get('name')} {e}")


def replay_phase_rows(replay, traces):
    """Phase traces: each engine's mean ms per step over each phase's steps (qp-record's phases), median over
    rounds; stock ÷ engine."""
    out = []
    for t in (t for t in traces if t["warmup"] == 0):
        for e in (e for e in PHASE_ENGINES if replay.get((t["name"], e))):
            for p in PHASES:
                ks = [k for k, x in enumerate(t["phases"]) if x == p]
                if ks:
                    ms = med([sum(r["steps_ns"][k] for k in ks) / len(ks) * 1e-6 for r in replay[(t["name"], e)]])
                    out.append({"trace": t["name"], "scene": t["scene"], "size": t["size"], "engine": e, "phase": p,
                                "first": ks[0], "steps": len(ks), "ms_per_step": ms})
    ref = {(r["trace"], r["phase"]): r["ms_per_step"] for r in out if r["engine"] == "stock"}
    return [dict(r, x_stock=ratio(ref.get((r["trace"], r["phase"])), r["ms_per_step"])) for r in out]


def peers_floors(rows, checks, triads, traces):
    """Per trace: the fastest exact peer (either mode), quadphase's ratio over it, the oracle and memory floors."""
    out, bw, by, meta = [], med(triads), {}, {t["name"]: t for t in traces}
    for r in rows:
        by.setdefault((r["scene"], r["size"]), {})[r["engine"]] = r
    for (s, n), es in sorted(by.items()):
        q1, o = es.get("quadtree-1t"), es.get("oracle") or {}
        if not q1:
            continue
        exact = [(r["ms_per_step"], e) for e, r in es.items() if e in PEERS and r.get("exact") == "yes"]
        best = min(exact) if exact else (None, None)
        c = checks.get((q1["trace"], "quadtree-1t")) or {}
        steps = c.get("timed_steps") or meta.get(q1["trace"], {}).get("steps")
        mem = c["floor_bytes"] / steps / bw * 1e3 if c.get("floor_bytes") and bw and steps else None
        out.append({"scene": s, "size": n, "qt1_ms": q1["ms_per_step"],
                    "qt2_ms": (es.get("quadtree-2t") or {}).get("ms_per_step"), "peer": best[1], "peer_ms": best[0],
                    "peer_x": ratio(best[0], q1["ms_per_step"]), "oracle_ms": o.get("ms_per_step"),
                    "oracle_exact": o.get("exact"), "qt_over_oracle": ratio(q1["ms_per_step"], o.get("ms_per_step")),
                    "memory_floor_ms": mem, "qt_over_memory": ratio(q1["ms_per_step"], mem),
                    "floor_mb_per_step": steps and c.get("floor_bytes", 0) / steps / 1e6,
                    "triad_gb_s": bw and bw * 1e-9})
    return out


def replay_table(replay, checks, paper_checks, traces):
    """replay.csv's rows: medians over rounds per (trace, engine), with the engine's exactness."""
    out, meta = [], {t["name"]: t for t in traces}
    for (trace, e), runs in replay.items():
        if meta.get(trace, {}).get("warmup") == 0:
            continue  # phase traces: replay_phase_rows
        mode = "native" if "-native" in e else ("protocol" if e in PEERS + ["oracle"] else "")
        row = {"trace": trace, "mode": mode, "scene": runs[0]["scene"], "size": runs[0]["size"], "engine": e,
               "rounds": len(runs), "ms_per_step": med([x["step_ns"] * 1e-6 for x in runs]),
               "proxies_end": meta.get(trace, {}).get("proxies")}
        row.update({k: med([x.get(k) for x in runs]) for k in ("ns_per_proxy_step", "pairs_per_step",
                                                               "bytes_per_proxy", "mean_proxies")})
        c, p = checks.get((trace, e)), paper_checks.get(trace)
        if e in EXACT_ENGINES:
            # Checked: protocol mode against stock's hash file (compared_file); native mode against every
            # overlapping fat-box pair, computed in the tool (checked_against, no file).
            checked = c and (c.get("compared_file") == 1 or ("compared_file" not in c and c.get("checked_against")))
            row["exact"] = ("yes" if checked and c.get("mismatches") == 0
                            else ("MISMATCH" if c and c.get("mismatches") else "not checked"))
        elif e == "paper" and p:
            row.update(exact="no (by design)", missed_pct=100.0 * p["missed"] / max(1, p["exact_pairs"]),
                       duplicates_pct=100.0 * p["duplicates"] / max(1, p["exact_pairs"]), extra=p["extra"],
                       levels=p.get("levels"))
        else:
            row["exact"] = "reference" if e == "stock" else "-"
        out.append(row)
    return sorted(out, key=lambda r: (r["scene"], r["size"], REPLAY_ENGINES.index(r["engine"])))


def replay_section(d, rp, plots):
    if not d["replay"]:
        return []
    L = section("## 2. Broadphase replay (identical trace)", TEXT["replay"], plots, "replay",
                "time against N, every broadphase")
    rows = []
    for s, n in sorted({(r["scene"], r["size"]) for r in d["replay"]}):
        for e in (e for e in REPLAY_ENGINES if (s, n, e) in rp):
            r, own = rp[(s, n, e)], e != "null"
            ex = r.get("exact", "")
            if e == "paper" and r.get("missed_pct") is not None:
                ex = (f"no: misses {r['missed_pct']:.2f}% of the pairs, {r['duplicates_pct']:.2f}% duplicates "
                      f"(levels {r.get('levels')})")
            sp = x_stock(rp, (s, n), e, "ms_per_step") if own and e != "stock" else None
            rows.append([f"{s} {n}", ENGINE_LABEL[e], r.get("mode", ""), fmt(r["ms_per_step"], 3),
                         fmt(r["ns_per_proxy_step"], 1), report.times(sp), fmt(r["pairs_per_step"], 0) if own else "",
                         fmt(r["bytes_per_proxy"], 0) if own else "", ex])
    L += table(["trace", "engine", "mode", "ms/step", "ns/proxy/step", "× stock", "pairs/step", "B/proxy", "exact"],
               rows)
    bad = [f"{r['scene']} {r['size']} {r['engine']}" for r in d["replay"] if r.get("exact") == "MISMATCH"]
    L += ["", "**PAIR SET MISMATCHES: " + ", ".join(bad) + "**" if bad else TEXT["replay_exact"], ""]
    L += ["### 2a. Fastest tuned peer and the floors", "", TEXT["peers"], ""]
    L += table(["trace", "quadphase 1t ms", "fastest exact peer", "peer ms", "× peer", "oracle ms", "÷ oracle",
                "floor MB/step", "memory floor ms", "÷ memory floor", "triad GB/s"], [
        [f"{r['scene']} {r['size']}", fmt(r["qt1_ms"], 3), ENGINE_LABEL.get(r["peer"], "–"), fmt(r["peer_ms"], 3),
         fmt(r["peer_x"]), fmt(r["oracle_ms"], 3), fmt(r["qt_over_oracle"]), fmt(r["floor_mb_per_step"], 2),
         fmt(r["memory_floor_ms"], 4), fmt(r["qt_over_memory"], 0), fmt(r["triad_gb_s"], 1)] for r in d["peers"]])
    if d["replay_phases"]:
        L += ["", "### 2b. Rain by phase (replay)", "", TEXT["replay_phases"], ""]
        L += table(["trace", "phase", "steps", "engine", "ms/step", "× stock"], [
            [f"{r['scene']} {r['size']}", r["phase"], f"{r['first']}–{r['first'] + r['steps'] - 1}",
             ENGINE_LABEL[r["engine"]], fmt(r["ms_per_step"], 3), fmt(r["x_stock"])] for r in d["replay_phases"]])
    return L + [""]


def replay_figure(plt, res, d, plots):
    """Time against N, log-log, every broadphase of the replay, per scene (results/replay_scaling.png)."""
    rows = d["replay"]
    scenes = sorted({r["scene"] for r in rows if len({x["size"] for x in rows if x["scene"] == r["scene"]}) > 1})
    scenes = scenes or sorted({r["scene"] for r in rows})
    if not scenes:
        return
    fig, axes = plt.subplots(1, len(scenes), figsize=(5.2 * len(scenes), 4.6), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        for e in REPLAY_ENGINES:
            pts = sorted((r["mean_proxies"], r["ms_per_step"]) for r in rows
                         if r["scene"] == scene and r["engine"] == e and r["ms_per_step"])
            if pts:
                ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3,
                        ls="--" if e in ("oracle", "null", "paper") else "-", label=ENGINE_LABEL[e])
        ax.set(xscale="log", yscale="log", xlabel="live proxies", ylabel="broadphase work, ms per step",
               title=f"replay: {scene}")
        ax.grid(alpha=0.3, which="both")
    axes[0][0].legend(fontsize=7)
    plots["replay"] = "results/replay_scaling.png"
    plot.save(plt, fig, os.path.join(res, "replay_scaling.png"), 90)
