# SPDX-License-Identifier: MIT
"""The benchmark scripts' command line, trace recording (reused when a matching trace exists), shuffled orders and a
progress bar, over quadphase_tools' runner (logs, JSON lines, quiet-waits)."""

import argparse
import os
import random
import sys
import time

from quadphase_tools import runner
from quadphase_tools.machine import REPO

WAIT_HELP = ("before each timed round, wait up to this many seconds for other processes to use less than "
             "--quiet-cpus CPUs")


def parse_args(doc, full_help, profile_options, more):
    """The command line of a benchmark script: the options every script has, its own (more(ap) adds them) and its
    profile options ((option, quick, full, help): one left out takes the value of the profile, quick or --full)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--full", action="store_true", help=full_help + "; default: the quick profile")
    ap.add_argument("--build-dir", default=os.path.join(REPO, "build-bench"),
                    help="build directory holding bench/qp-* (default: build-bench)")
    ap.add_argument("--results", default=os.path.join(REPO, "bench", "results"),
                    help="where the reports, CSV, JSON and PNG go (default: bench/results)")
    ap.add_argument("--work", default=None, help="traces, raw results, logs (default: under BUILD_DIR/tmp)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--report-only", action="store_true", help="rewrite the outputs from the last run's raw results")
    ap.add_argument("--rerecord", action="store_true", help="record traces even when a matching one exists")
    ap.add_argument("--quiet-cpus", type=float, default=0.3)
    for name, quick, full, what in profile_options:
        ap.add_argument("--" + name, type=type(quick), default=None, help=f"{what} (quick {quick}, full {full})")
    more(ap)
    a = ap.parse_args()
    for name, quick, full, _ in profile_options:
        if getattr(a, name.replace("-", "_")) is None:
            setattr(a, name.replace("-", "_"), full if a.full else quick)
    return a


class Runner(runner.Runner):
    """quadphase_tools' runner, plus the traces the benchmark scripts replay (TRACES, default WORK/traces)."""

    def __init__(self, who, bin_dir, work, name, traces=None, seed=1, rerecord=False, **options):
        super().__init__(who, bin_dir, work, name, **options)
        self.traces, self.seed, self.rerecord = traces or os.path.join(work, "traces"), seed, rerecord

    def record(self, scene, size, warmup, steps):
        """The trace of (scene, size, seed, warm-up, steps), recorded with qp-record unless a matching one exists."""
        os.makedirs(self.traces, exist_ok=True)
        path = os.path.join(self.traces, f"{scene}-{size}-w{warmup}-s{steps}-seed{self.seed}.qptrace")
        want = {"scene": scene, "size": str(size), "seed": str(self.seed), "warmup": str(warmup), "steps": str(steps)}
        if not self.rerecord and all(os.path.exists(path + x) for x in ("", ".steps", ".phases")):
            with open(path + ".steps") as f:
                have = dict(p for p in (line.split() for line in f) if len(p) == 2 and p[0] in want)
            if have == want:
                self.echo(f"  {scene} {size}: reusing {path}")
                return path
        t0 = time.time()
        _, out = self.run("qp-record", "--scene", scene, "--size", size, "--seed", self.seed, "--warmup", warmup,
                          "--steps", steps, "--out", path)
        self.echo(f"  {scene} {size}: recorded {warmup} + {steps} steps in {time.time() - t0:.0f} s")
        for line in out.splitlines():
            if line.startswith(("bodies", "ops", "scene")):
                self.echo("    " + line)
        return path


def shuffled(items, seed):
    order = list(items)
    random.Random(seed).shuffle(order)
    return order


def trace_proxies(path):
    with open(path + ".steps") as f:
        return next((int(l.split()[1]) for l in f if l.startswith("proxies ")), 0)


class Progress:
    """A textual progress bar on stderr: one line, rewritten in place on a terminal, every 5% otherwise."""

    def __init__(self, total):
        self.total, self.done, self.start, self.last_pct = max(1, total), 0, time.time(), -5
        self.tty = sys.stderr.isatty()

    def step(self, what, n=1):
        self.done = min(self.total, self.done + n)
        pct = 100.0 * self.done / self.total
        el = time.time() - self.start
        eta = el / self.done * (self.total - self.done) if self.done else 0
        bar = "#" * int(pct / 2.5) + "-" * (40 - int(pct / 2.5))
        line = f"[{bar}] {pct:3.0f}% {self.done}/{self.total}  {el:4.0f} s, ~{eta:3.0f} s left  {what}"
        if self.tty:
            sys.stderr.write("\r" + line[:150].ljust(150))
            sys.stderr.flush()
        elif pct - self.last_pct >= 5 or self.done == self.total:
            sys.stderr.write(line + "\n")
            self.last_pct = pct

    def end(self):
        if self.tty:
            sys.stderr.write("\n")
