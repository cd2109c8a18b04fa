#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Parallel pair-generation benchmark: installs what it needs (bench/install-deps.sh), configures and builds
# qp-record / qp-replay (Release), then runs bench/parallel.py, which records the traces, replays
# them and writes bench/results/parallel.md, parallel.csv and parallel.png. See bench/README.md.
#
#   bench/parallel.sh                 # the quick version (under ~15 minutes on a 2-core machine)
#   bench/parallel.sh --full          # more steps and repeats, rain recorded until its pile forms
#   bench/parallel.sh --help          # every option (sizes, steps, repeats, sections, output directory)
#
# Environment: QUADPHASE_SKIP_DEPS=1, BUILD_DIR (default build-bench; traces go to BUILD_DIR/tmp/traces), JOBS,
# QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL (scripts/lib/build.sh).
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/lib/build.sh"
[[ " $* " == *" --help "* || " $* " == *" -h "* ]] && exec /usr/bin/python3 bench/parallel.py --help
qp_deps bench/install-deps.sh
build_dir=${BUILD_DIR:-build-bench}
qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_BENCH=ON -DQUADPHASE_BUILD_TESTS=OFF \
    -DQUADPHASE_BUILD_EXAMPLES=OFF
qp_build "$build_dir" qp-record qp-replay
exec /usr/bin/python3 bench/parallel.py --build-dir "$build_dir" "$@"
