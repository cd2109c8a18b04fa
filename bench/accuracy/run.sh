#!/usr/bin/env bash
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
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run bench/install-deps.sh
#   BUILD_DIR                   build directory (default: build-accuracy)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/../.."

for arg in "$@"; do
    if [[ "$arg" == "-h" || "$arg" == "--help" ]]; then
        exec /usr/bin/python3 bench/accuracy/accuracy.py --build-dir BUILD_DIR --help
    fi
done

if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    bench/install-deps.sh >&2
fi

build_dir=${BUILD_DIR:-build-accuracy}
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
    echo "bench/accuracy/run.sh: configuring $build_dir failed (see above)." >&2
    exit 1
fi
if ! cmake --build "$build_dir" -j "$jobs" --target qp-accuracy >&2; then
    echo "bench/accuracy/run.sh: building qp-accuracy failed (see above)." >&2
    exit 1
fi

exec /usr/bin/python3 bench/accuracy/accuracy.py --build-dir "$build_dir" "$@"
