"""qpbench: what every report script of bench/ shares (bench.py -> RESULTS.md, parallel.py -> parallel.md,
accuracy/accuracy.py -> docs/accuracy.md).

  machine  the machine, build and code measured (CPU, compiler flags, git, Box2D source checksum), and the load
  run      running the tools: logs, JSON lines, quiet-waits, rounds in random order, trace recording, progress
  stats    medians, ratios, per-round ratios, Karp-Flatt and Amdahl
  report   number formats, markdown tables, CSV/JSON writing, the machine section of a report, the reports' prose
           (bench/prose: fixed paragraphs with fields to fill in)
  plot     matplotlib (Agg) through /usr/bin/python3, or a note when it is missing
  paper    the paper's published Tables 1 and 2

A new engine is one more entry in a script's engine list (bench.py: REPLAY_ENGINES, ENGINE_LABEL); a new table is
one function returning markdown lines built with report.table().
"""
