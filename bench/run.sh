#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# quadphase's side-by-side benchmark: in-engine step benchmark (stock Box2D against quadphase,
# every scene, and rain by phase), broadphase replay (stock, quadphase, brute force, the paper's design, Chipmunk2D,
# Bullet, memory floor), b2World queries, and the paper's protocol (circles under 20 ms). Installs what it needs,
# configures and builds the tools (Release) per optimisation level, runs bench/bench.py, which writes
# bench/results/*.csv, bench.json, the PNG plots and bench/RESULTS.md. See bench/README.md.
#
#   bench/run.sh                 # quick profile, -O2: under 10 minutes on a 2-core machine (plus the first build)
#   bench/run.sh --full          # full profile, -O2 and -O3 (--opt both unless --opt says otherwise): about 90 minutes
#   bench/run.sh --opt both      # -O2 (Debian's level) and -O3 (Box2D's CMake Release): a stock and a quadphase
#                                # build each, same source, same flags; in-engine and replay headline at both
#   bench/run.sh --frames        # only the frames section (--full runs it too): p50/p99/max/total, CPU time,
#                                # busy, job system; about 18 minutes: bench/results/frames.{md,csv,png}
#   bench/run.sh --help          # every option of bench.py (parts, rounds, scale, output paths)
#
# Environment: QUADPHASE_SKIP_DEPS=1, BUILD_DIR (default build-bench; -O3 builds go to BUILD_DIR-O3), JOBS,
# QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL (scripts/lib/build.sh).
source "$(dirname "${BASH_SOURCE[0]}")/../scripts/lib/build.sh"

opt=
args=()
while [[ $# -gt 0 ]]; do
    case "$1" in
        -h|--help) exec /usr/bin/python3 bench/bench.py --help ;;
        --full) args+=("$1"); opt=${opt:-both}; shift ;;
        --opt) [[ $# -ge 2 ]] || { echo "bench/run.sh: --opt needs O2, O3 or both" >&2; exit 2; }; opt=$2; shift 2 ;;
        --opt=*) opt=${1#--opt=}; shift ;;
        *) args+=("$1"); shift ;;
    esac
done
case "${opt:=O2}" in
    O2|O3) levels=("$opt") ;;
    both) levels=(O2 O3) ;;
    *) echo "bench/run.sh: --opt must be O2, O3 or both, got '$opt'" >&2; exit 2 ;;
esac

qp_deps bench/install-deps.sh
builds=""
for level in "${levels[@]}"; do
    dir=${BUILD_DIR:-build-bench}
    [[ $level == O3 ]] && dir=$dir-O3
    echo "bench/run.sh: configuring and building the benchmark tools in $dir (-$level) ..." >&2
    QP_LOG=1 qp_configure "$dir" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-$level -DNDEBUG" \
        -DQUADPHASE_BUILD_BENCH=ON -DQUADPHASE_BUILD_TESTS=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF
    grep -E "quadphase bench:" "$dir/configure.log" >&2 || true
    QP_LOG=1 qp_build "$dir" qp-bench-all
    builds+="${builds:+,}$level=$dir"
done
exec /usr/bin/python3 bench/bench.py --builds "$builds" "${args[@]}"
