# SPDX-License-Identifier: MIT
"""What the side-by-side demo (examples/demo) and the benchmark's report scripts (bench/) share; the C++ tools' side
is support/tools/include/quadphase_tools.

  machine  the machine, build and code measured (CPU, compiler flags, git, Box2D source checksum), and the load
  runner   running a build's tools: one log and one JSON-lines file per run, quiet-waits before timed rounds
  stats    medians and ratios
"""
