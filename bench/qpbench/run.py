"""Running the benchmark tools: one log and one JSON-lines file per run, quiet-waits before rounds, trace recording
(reused when a matching trace exists), shuffled orders and a progress bar."""

import argparse
import json
import os
import random
import subprocess
import sys
import time

from .machine import REPO, cpus_busy

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


class Runner:
    """Runs BIN_DIR's tools; their output goes to WORK/NAME.log, their JSON lines to WORK/NAME.jsonl (started
    anew unless `append`, as for --report-only)."""

    def __init__(self, who, bin_dir, work, name, tools=(), append=False, traces=None, seed=1, rerecord=False,
                 wait_quiet=0.0, quiet_cpus=0.3, echo=print):
        self.who, self.bin, self.seed, self.rerecord, self.echo = who, bin_dir, seed, rerecord, echo
        self.max_wait, self.quiet_cpus, self.quiet_samples = wait_quiet, quiet_cpus, []
        for tool in tools if not append else ():
            if not os.access(os.path.join(bin_dir, tool), os.X_OK):
                sys.exit(f"{who}: {tool} not found in {bin_dir}; run the script's .sh driver (it builds them)")
        os.makedirs(work, exist_ok=True)
        self.traces = traces or os.path.join(work, "traces")
        self.jsonl = os.path.join(work, name + ".jsonl")
        self.log = open(os.path.join(work, name + ".log"), "a" if append else "w")
        if os.path.exists(self.jsonl) and not append:
            os.remove(self.jsonl)

    def run(self, tool, *argv, ok_codes=(0,), env=None):
        """Runs a tool (env: variables to set, None to unset); exits on a code not in ok_codes."""
        cmd = [os.path.join(self.bin, tool)] + [str(a) for a in argv]
        self.log.write(("" if not env else " ".join(f"{k}={v}" for k, v in env.items() if v is not None) + " ")
                       + "$ " + " ".join(cmd) + "\n")
        self.log.flush()
        full_env = {k: v for k, v in dict(os.environ, **env).items() if v is not None} if env else None
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=full_env)
        self.log.write(p.stdout)
        self.log.flush()
        if p.returncode not in ok_codes:
            print(p.stdout)
            sys.exit(f"{self.who}: {' '.join(cmd)} failed with code {p.returncode}")
        return p.returncode, p.stdout

    def results(self):
        """Every JSON line so far; a label "...|round=R" gives the row its round (rep_round)."""
        rows = []
        if os.path.exists(self.jsonl):
            with open(self.jsonl) as f:
                rows = [json.loads(line) for line in f if line.strip()]
        for row in rows:
            if "|round=" in row.get("label", ""):
                row["rep_round"] = int(row["label"].split("|round=")[1])
        return rows

    def wait_quiet(self, seconds=None):
        """Waits up to `seconds` (default: the runner's) for other processes to use < quiet_cpus CPUs; records and
        returns how many they used."""
        limit = self.max_wait if seconds is None else seconds
        start, busy = time.time(), cpus_busy()
        while busy > self.quiet_cpus and time.time() - start < limit:
            busy = cpus_busy(1.0)
        self.quiet_samples.append(busy)
        return busy

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
