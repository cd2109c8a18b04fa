#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Side-by-side demo: install dependencies (scripts/install-deps.sh), configure + build (Release) the benchmark's
# step tools (qp-step-stock, qp-step-quadtree), then run examples/demo/demo.py with the given arguments.
#
#   scripts/demo.sh                                  # rain, 16000 bodies, 300 steps
#   scripts/demo.sh --scene particles --size 20000 --repeat 3
#   scripts/demo.sh --help                           # all options and scenes
#
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run scripts/install-deps.sh
#   BUILD_DIR                   build directory (default: build)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for demo
build_dir=${BUILD_DIR:-build}
# Configure (cheap when already configured; keeps the build Release with the benchmarks on).
qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_BENCH=ON
qp_build "$build_dir" qp-step-stock qp-step-quadtree
status=0
step=$(qp_exe "$build_dir/bench/qp-step-stock")
python3 "$(dirname "${BASH_SOURCE[0]}")/../examples/demo/demo.py" --bin-dir "$(dirname "$step")" "$@" ||
    status=$?
cat >&2 <<'MSG'

demo: this was one scene. The benchmark steps every scene in both builds, replays identical broadphase
demo: traces through stock, quadphase, brute force, the paper's design, Chipmunk2D and Bullet, and runs the paper's
demo: 20 ms protocol:  bench/run.sh  (quick profile, about 10 minutes; --full for the committed bench/RESULTS.md)
MSG
exit "$status"
