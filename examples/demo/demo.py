#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""quadphase's side-by-side demo: one scene stepped with stock Box2D 2.4.1 and with the quadtree broadphase.

Runs the benchmark's step tools (bench/src/step_bench.cpp: qp-step-stock and qp-step-quadtree) alternately, stock,
quadtree, stock, ... --repeat times each, through the runner the benchmark uses (support/tools/python), and prints
one table of medians over the repeats with stock / quadtree ratios of the times. scripts/demo.sh builds the tools
and runs this.
"""

import argparse
import json
import math
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "support", "tools", "python"))
from quadphase_tools import machine  # noqa: E402
from quadphase_tools.runner import Runner  # noqa: E402
from quadphase_tools.stats import med  # noqa: E402

EPILOG = """Broadphase ms is Box2D's b2Profile::broadphase (proxy synchronisation and new-pair search in
b2World::Solve, pair callbacks included); step ms is b2Profile::step. 'new pairs at filtering' counts
b2ContactFilter::ShouldCollide calls, the same metric in both builds. Positions may legitimately
differ between the builds: the two broadphases report the same pairs in a different order.

scenes:
{scenes}
exit status: 0 ok, 1 a run failed (or validation found a mismatch), 2 bad options"""
# (label, key of qp-step's JSON line, decimals, print stock / quadtree)
ROWS = [("bodies", "bodies", 0, False), ("fixtures (proxies)", "fixtures", 0, False),
        ("contacts at end", "contacts_end", 0, False), ("contacts, mean per step", "contacts_mean_all_steps", 1, False),
        ("new pairs at filtering", "new_pairs", 0, False), ("  per measured step", "new_pairs_per_step", 1, False),
        ("broadphase ms/step, median", "broadphase_ms", 3, True),
        ("broadphase ms/step, mean", "broadphase_ms_mean", 3, True),
        ("broadphase ms/step, p99", "broadphase_ms_p99", 3, True),
        ("broadphase ms, worst step", "broadphase_ms_max", 3, True),
        ("broadphase ms, total", "broadphase_ms_total", 2, True), ("step ms, median", "step_ms", 3, True),
        ("step ms, mean", "step_ms_mean", 3, True), ("step ms, worst step", "step_ms_max", 3, True), ("  collide ms, mean", "collide_ms_mean", 3, True),
        ("  solve ms (incl. bp), mean", "solve_ms_mean", 3, True),
        ("  time of impact ms, mean", "toi_ms_mean", 3, True), ("build s", "build_s", 3, False),
        ("run s (all steps)", "run_s", 3, True)]
VARIANTS = ("stock", "quadtree")


def scene_table(bin_dir):
    """name -> (min, max, default, what the size counts, description), from qp-step-stock --list."""
    out = subprocess.run([os.path.join(bin_dir, "qp-step-stock"), "--list"], stdout=subprocess.PIPE, text=True,
                         check=True).stdout
    scenes = {}
    for line in out.splitlines():
        head, meaning, description = line.split("\t")
        name, lo, hi, default = head.split()
        scenes[name] = (int(lo), int(hi), int(default), meaning, description)
    return scenes


def parse_args(scenes):
    help_scenes = "".join(f"  {name:<11}{s[4]}\n             size = {s[3]}, {s[0]}..{s[1]}, default {s[2]}\n"
                          for name, s in scenes.items())
    ap = argparse.ArgumentParser(
        prog="quadphase-demo", formatter_class=argparse.RawDescriptionHelpFormatter,
        description="Steps one scene with stock Box2D 2.4.1 (dynamic AABB tree) and with the quadphase quadtree "
                    "broadphase, alternately, and prints a side-by-side table of medians over the repeats, with "
                    "stock/quadtree time ratios (> 1: quadtree faster).",
        epilog=EPILOG.format(scenes=help_scenes))
    ap.add_argument("--scene", default="rain", choices=sorted(scenes), metavar="NAME", help="scene (default rain)")
    ap.add_argument("--size", type=int, help="scene size (default: 16000 for rain, else the scene's default)")
    ap.add_argument("--steps", type=int, default=300, help="steps per run (default 300)")
    ap.add_argument("--warmup", type=int, help="first steps left out of the timing statistics (default 10)")
    ap.add_argument("--seed", type=int, default=1, help="scene seed, 0..4294967295 (default 1)")
    ap.add_argument("--repeat", type=int, default=1, help="runs of each build; the table shows medians (default 1)")
    ap.add_argument("--validate", action="store_true", help="the quadtree run checks every UpdatePairs against a "
                    "shadow b2DynamicTree (its times then include the shadow tree); fails on a mismatch")
    ap.add_argument("--timing", action="store_true", help="the quadtree run also times proxy updates")
    ap.add_argument("--json", action="store_true", help="print the medians as one JSON object instead of the table")
    ap.add_argument("--bin-dir", default=os.path.join(REPO, "build", "bench"), help="where qp-step-* are")
    args = ap.parse_args()
    lo, hi, default = scenes[args.scene][:3]
    args.size = args.size if args.size is not None else 16000 if args.scene == "rain" else default
    if not lo <= args.size <= hi:
        ap.error(f"--size {args.size} is outside {args.scene}'s range [{lo}, {hi}]")
    if not 1 <= args.steps <= 10000000 or not 1 <= args.repeat <= 1000 or not 0 <= args.seed <= 4294967295:
        ap.error("--steps must be in [1, 10000000], --repeat in [1, 1000], --seed in [0, 4294967295]")
    if args.warmup is None:
        args.warmup = 10 if args.steps > 10 else args.steps // 10
    if not 0 <= args.warmup < args.steps:
        ap.error(f"--warmup ({args.warmup}) must be smaller than --steps ({args.steps})")
    return args


def fmt(value, decimals):
    return "-" if value is None or math.isnan(value) else f"{value:.{decimals}f}"


def main():
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--bin-dir", default=os.path.join(REPO, "build", "bench"))
    bin_dir = pre.parse_known_args()[0].bin_dir
    if not os.access(os.path.join(bin_dir, "qp-step-stock"), os.X_OK):
        sys.exit(f"quadphase-demo: {bin_dir}/qp-step-stock not found (scripts/demo.sh builds it)")
    scenes = scene_table(bin_dir)
    args = parse_args(scenes)
    runner = Runner("quadphase-demo", args.bin_dir, os.path.join(os.path.dirname(args.bin_dir), "tmp", "demo"), "demo",
                    tools=["qp-step-" + v for v in VARIANTS])
    common = ["--scene", args.scene, "--size", args.size, "--seed", args.seed, "--warmup", args.warmup,
              "--steps", args.steps - args.warmup, "--threads", "default", "--json", runner.jsonl]
    extra = (["--validate"] if args.validate else []) + (["--timing"] if args.timing else [])
    failed = False
    for r in range(args.repeat):
        for variant in VARIANTS:
            if not args.json:
                print(f"quadphase-demo: run {r + 1}/{args.repeat} {variant:<8} ...", end="", file=sys.stderr,
                      flush=True)
            code, _ = runner.run("qp-step-" + variant, *common, *(extra if variant == "quadtree" else []),
                                 "--label", variant, ok_codes=(0, 1) if args.validate else (0,))
            failed = failed or code != 0
            if not args.json:
                print(f" {runner.results()[-1]['run_s']:.3f} s", file=sys.stderr)
    runs = {v: [row for row in runner.results() if row["variant"] == v] for v in VARIANTS}

    def median(variant, key):
        value = med([row.get(key) for row in runs[variant]])
        return float("nan") if value is None else value

    def finite(x):
        return None if isinstance(x, float) and math.isnan(x) else x

    if args.json:
        out = {k: getattr(args, k) for k in ("scene", "size", "steps", "warmup", "seed", "repeat")}
        out.update({v: {k: finite(median(v, k)) for k, x in runs[v][0].items() if isinstance(x, (int, float))}
                    for v in VARIANTS})
        for v in VARIANTS:
            out[v]["position_hash"] = runs[v][0]["position_hash"]
        out["ratio_stock_over_quadtree"] = {key: finite(median("stock", key) / median("quadtree", key))
                                            for _, key, _, ratio in ROWS if ratio}
        out["validation_failed"] = failed
        print(json.dumps(dict(out, machine=machine.describe(os.path.dirname(args.bin_dir))), indent=1))
        return 1 if failed else 0

    info = machine.describe(os.path.dirname(args.bin_dir))
    print(f"\nquadphase demo: scene {args.scene}, size {args.size}, {args.steps} steps ({args.warmup} warmup steps "
          f"not timed), seed {args.seed}, {args.repeat} run{'' if args.repeat == 1 else 's'} each")
    print(f"  {scenes[args.scene][4]}")
    print(f"CPU: {info['cpu']}, {info['cores']} cores online, load average {' '.join(info['loadavg_start'])}")
    print(f"Build: {info['compiler']}, {info.get('CMAKE_BUILD_TYPE') or '(no build type)'}, flags: "
          f"{info.get('CMAKE_CXX_FLAGS_RELEASE') or '(none)'}")
    if args.repeat > 1:
        print(f"Values are medians over the {args.repeat} runs of each build.")
    line = "{:<30} {:>14} {:>14} {:>16}".format
    print("\n" + line("", "stock tree", "quadtree", "stock/quadtree"))
    print(line("", "----------", "--------", "--------------"))
    for label, key, decimals, ratio in ROWS:
        stock, quadtree = median("stock", key), median("quadtree", key)
        shown = fmt(stock / quadtree, 2) + "x" if ratio and quadtree > 0 and not math.isnan(stock) else ""
        print(line(label, fmt(stock, decimals), fmt(quadtree, decimals), shown))
    hashes = [runs[v][-1]["position_hash"] for v in VARIANTS]
    print(line("final position hash", hashes[0][:12], hashes[1][:12], "same" if hashes[0] == hashes[1] else "differ"))

    q = runs["quadtree"][-1]
    print("\nquadtree broadphase (state at the end of the run; counters cover the measured steps):")
    print(f"  depth {fmt(median('quadtree', 'qt_depth'), 0)} (leaf cells {fmt(median('quadtree', 'qt_leaf_size'), 3)}"
          f" m), {fmt(median('quadtree', 'qt_proxies'), 0)} proxies ({fmt(median('quadtree', 'qt_outside'), 0)} "
          f"outside the bounds), {fmt(median('quadtree', 'qt_occupied_cells'), 0)} occupied cells, largest cell "
          f"{fmt(median('quadtree', 'qt_largest_cell'), 0)}")
    print(f"  memory {fmt(median('quadtree', 'bp_bytes') / (1024.0 * 1024.0), 2)} MiB, "
          f"{fmt(median('quadtree', 'qt_rebuilds'), 0)} rebuilds, {fmt(median('quadtree', 'qt_update_pairs_calls'), 0)}"
          f" UpdatePairs calls, {fmt(median('quadtree', 'qt_pairs_reported'), 0)} pairs reported, "
          f"{fmt(median('quadtree', 'qt_proxies_queried'), 0)} proxies queried")
    print(f"  pair generation {fmt(median('quadtree', 'qt_find_ms_per_step'), 3)} ms/step (UpdatePairs without "
          "Box2D's callbacks)" + (f", proxy updates {fmt(median('quadtree', 'qt_update_ms_per_step'), 3)} ms/step"
                                  if args.timing else ""))
    if args.validate:
        print(f"  validation: {fmt(median('quadtree', 'validation_checks'), 0)} checks, "
              f"{fmt(median('quadtree', 'validation_pairs_compared'), 0)} pairs compared, "
              f"{q['validation_mismatches']} mismatches"
              + (f": FAILED, first: {q['validation_first_mismatch']}" if failed else ""))
        print("  (validation on: the quadtree times include the shadow tree; ignore the ratios)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
