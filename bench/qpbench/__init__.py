# SPDX-License-Identifier: MIT
"""qpbench: what every report script of bench/ shares (bench.py -> RESULTS.md, parallel.py -> parallel.md,
accuracy/accuracy.py -> docs/accuracy.md).

  run      the scripts' command line, trace recording, rounds in random order, progress
  stats    per-round ratios, Karp-Flatt, serial fractions and Amdahl
  report   number formats, markdown tables, CSV/JSON writing, the machine section of a report, the reports' prose
           (bench/prose: fixed paragraphs with fields to fill in)
  plot     matplotlib (Agg) through /usr/bin/python3, or a note when it is missing
  paper    the paper's published Tables 1 and 2

bench.py's sections, one module each (its sizes and engines, its tool runs, its rows, its RESULTS.md table and plot):
  step, phases, replay, queries, circles, frames
and what they share (bench_common), the CSV, JSON and plot files (outputs) and RESULTS.md's frame (summary).

A new engine is one more entry in a script's engine list (bench.py's replay: replay.REPLAY_ENGINES and
replay.ENGINE_LABEL); a new table is one function returning markdown lines built with report.table().

What the demo (examples/demo) shares with them is in support/tools/python/quadphase_tools: the machine, running
the tools (logs, JSON lines, quiet-waits), medians and ratios.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), *[os.pardir] * 2, "support", "tools",
                                "python"))
