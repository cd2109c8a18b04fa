#!/usr/bin/env bash
# quadphase's side-by-side benchmark (issue 4): in-engine step benchmark (stock Box2D against quadphase, every scene),
# broadphase replay (stock, quadphase, brute force, the paper's design, Chipmunk2D, Bullet, memory floor) and the
# paper's protocol (circles under 20 ms). Installs what it needs (bench/install-deps.sh), configures and builds the
# tools (Release), runs bench/bench.py, which writes bench/results/{step,replay,circles}.csv, bench.json, the PNG
# plots and bench/RESULTS.md. See bench/README.md.
#
#   bench/run.sh            # quick profile: under 5 minutes on a 2-core machine (plus the first build)
#   bench/run.sh --full     # full profile: about 30 minutes
#   bench/run.sh --help     # every option (parts, rounds, scale, output paths)
#
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run bench/install-deps.sh
#   BUILD_DIR                   build directory (default: build-bench; traces go to BUILD_DIR/tmp/bench/traces)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

for arg in "$@"; do
    if [[ "$arg" == "-h" || "$arg" == "--help" ]]; then
        exec /usr/bin/python3 bench/bench.py --help
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

mkdir -p "$build_dir"
echo "bench/run.sh: configuring and building the benchmark tools in $build_dir ..." >&2
if ! cmake "${configure_args[@]}" >"$build_dir/configure.log" 2>&1; then
    cat "$build_dir/configure.log" >&2
    echo "bench/run.sh: configuring $build_dir failed (see above)." >&2
    exit 1
fi
grep -E "quadphase bench:" "$build_dir/configure.log" >&2 || true
if ! cmake --build "$build_dir" -j "$jobs" --target qp-bench-all >"$build_dir/build.log" 2>&1; then
    tail -n 40 "$build_dir/build.log" >&2
    echo "bench/run.sh: building the benchmark tools failed (see above; full log $build_dir/build.log)." >&2
    exit 1
fi

exec /usr/bin/python3 bench/bench.py --build-dir "$build_dir" "$@"
