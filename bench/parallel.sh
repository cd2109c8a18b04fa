#!/usr/bin/env bash
# Parallel pair-generation benchmark: installs what it needs (bench/install-deps.sh), configures and builds
# qp-record / qp-replay / qp-replay-stock (Release), then runs bench/parallel.py, which records the traces, replays
# them and writes bench/results/parallel.md, parallel.csv and parallel.png. See bench/README.md.
#
#   bench/parallel.sh                 # the quick version (under ~15 minutes on a 2-core machine)
#   bench/parallel.sh --full          # more steps and repeats, rain recorded until its pile forms
#   bench/parallel.sh --help          # every option (sizes, steps, repeats, sections, output directory)
#
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run bench/install-deps.sh
#   BUILD_DIR                   build directory (default: build-bench; traces go to BUILD_DIR/tmp/traces)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

for arg in "$@"; do
    if [[ "$arg" == "-h" || "$arg" == "--help" ]]; then
        exec /usr/bin/python3 bench/parallel.py --help
    fi
done

if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    bench/install-deps.sh >&2
fi

build_dir=${BUILD_DIR:-build-bench}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}

configure_args=(-S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_BENCH=ON
                -DQUADPHASE_BUILD_TESTS=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF)
if [[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
fi
if [[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")
fi

if ! cmake "${configure_args[@]}" >&2; then
    echo "bench/parallel.sh: configuring $build_dir failed (see above)." >&2
    exit 1
fi
if ! cmake --build "$build_dir" -j "$jobs" --target qp-record qp-replay qp-replay-stock >&2; then
    echo "bench/parallel.sh: building the benchmark tools failed (see above)." >&2
    exit 1
fi

exec /usr/bin/python3 bench/parallel.py --build-dir "$build_dir" "$@"
