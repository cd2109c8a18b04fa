# SPDX-License-Identifier: MIT
"""Running a program's tools: one log and one JSON-lines file per run, and quiet-waits before timed rounds."""

import json
import os
import subprocess
import sys
import time

from .machine import cpus_busy


class Runner:
    """Runs BIN_DIR's tools; their output goes to WORK/NAME.log, their JSON lines to WORK/NAME.jsonl (started
    anew unless `append`, as for --report-only)."""

    def __init__(self, who, bin_dir, work, name, tools=(), append=False, wait_quiet=0.0, quiet_cpus=0.3, echo=print):
        self.who, self.bin, self.echo = who, bin_dir, echo
        self.max_wait, self.quiet_cpus, self.quiet_samples = wait_quiet, quiet_cpus, []
        for tool in tools if not append else ():
            if not os.access(os.path.join(bin_dir, tool), os.X_OK):
                sys.exit(f"{who}: {tool} not found in {bin_dir}; run the script's .sh driver (it builds them)")
        os.makedirs(work, exist_ok=True)
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
