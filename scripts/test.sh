#!/usr/bin/env bash
# Install dependencies (scripts/install-deps.sh), configure (Release), build and run
# all tests of quadphase.
#
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run scripts/install-deps.sh
#   BUILD_DIR                   build directory (default: build)
#   JOBS                        parallel build/test jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
# Extra arguments are passed to the CMake configure step.
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Dependencies first (a no-op when everything is installed).
if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    scripts/install-deps.sh --for test >&2
fi

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}

configure_args=(-S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release)
if [[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
fi
if [[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")
fi

set -x
cmake "${configure_args[@]}" "$@"
cmake --build "$build_dir" -j "$jobs"
ctest --test-dir "$build_dir" --output-on-failure -j "$jobs"
