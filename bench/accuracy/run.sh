#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Error against run time: installs what it needs (bench/install-deps.sh: the project's dependencies plus
# python3-matplotlib), configures and builds qp-accuracy-{stock,quadphase,paper} (Release), then runs
# bench/accuracy/accuracy.py, which sweeps scenes x broadphase configurations x step settings and writes
# docs/accuracy.md and docs/accuracy/*.png (raw results in BUILD_DIR/accuracy/). See bench/accuracy/README.md.
#
#   bench/accuracy/run.sh                       # the whole sweep, 2 rounds (about 25 minutes on 2 busy cores; --rounds 1 halves it)
#   bench/accuracy/run.sh --rounds 1 --scenes pyramid,particles
#   bench/accuracy/run.sh --replot              # plots and report again from the last sweep's results
#   bench/accuracy/run.sh --help
#
# Environment: QUADPHASE_SKIP_DEPS=1, BUILD_DIR (default build-accuracy), JOBS,
# QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL (scripts/lib/build.sh).
source "$(dirname "${BASH_SOURCE[0]}")/../../scripts/lib/build.sh"
[[ " $* " == *" --help "* || " $* " == *" -h "* ]] && exec /usr/bin/python3 bench/accuracy/accuracy.py --build-dir BUILD_DIR --help
qp_deps bench/install-deps.sh
build_dir=${BUILD_DIR:-build-accuracy}
qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_BENCH=ON -DQUADPHASE_BUILD_TESTS=OFF \
    -DQUADPHASE_BUILD_EXAMPLES=OFF
qp_build "$build_dir" qp-accuracy
exec /usr/bin/python3 bench/accuracy/accuracy.py --build-dir "$build_dir" "$@"
