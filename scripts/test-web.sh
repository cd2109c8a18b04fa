#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# quadphase on the web: Box2D 2.4.1 with quadphase built to WebAssembly by Debian's Emscripten
# (cmake/toolchains/emscripten.cmake: no OpenMP, no pthread, so the library runs serially) and tested under
# Node.js:
#   - quadphase_core_tests, Box2D's own unit tests against both Box2D builds, the scene tests (every scene 600 steps
#     with validation on against the shadow b2DynamicTree; determinism) and example_headless;
#   - then quadphase-headless (every scene with validation on) under Node.js and built natively (GCC, x86-64, in
#     the build directory of scripts/test.sh): both must report 0 mismatches, and their position hashes are
#     printed side by side. They may differ: Box2D is not bit-identical across compilers and C libraries
#     (docs/design.md, "Platforms and floating point", says where and why); the pairs are the same on each.
# Left out on the web: what starts threads ([concurrent], tests/parallel: no pthread build), the package, ABI and
# fuzz-replay tests (no shared libraries, no installed package), quadphase-scene (cairo), the benchmarks (OpenMP).
#
# Exit status: non-zero when a test fails or a scene has a validation mismatch.
# Environment: BUILD_DIR (default build-web), NATIVE_BUILD_DIR (default build), JOBS (default nproc),
#              QUADPHASE_SKIP_DEPS=1, QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh.
# Extra arguments are passed to quadphase-headless (e.g. --steps 600 --scale 1).
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for web
build_dir=${BUILD_DIR:-build-web}
native_dir=${NATIVE_BUILD_DIR:-build}
# Debian's node-acorn (which Emscripten's JavaScript optimizer needs) lives in /usr/share/nodejs: Debian's own
# nodejs looks there, other builds of Node.js only through NODE_PATH.
export NODE_PATH="/usr/share/nodejs${NODE_PATH:+:$NODE_PATH}"

web_targets=(quadphase_core_tests box2d_unit_tests_quadphase box2d_unit_tests_stock quadphase_scene_tests
    quadphase-headless)
qp_configure "$build_dir" -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/emscripten.cmake -DCMAKE_BUILD_TYPE=Release \
    -DQUADPHASE_BUILD_BENCH=OFF -DQUADPHASE_PACKAGE_TESTS=OFF -DQUADPHASE_INSTALL=OFF
qp_build "$build_dir" "${web_targets[@]}"
qp_configure "$native_dir" -DCMAKE_BUILD_TYPE=Release
qp_build "$native_dir" quadphase-headless

set -x
ctest --test-dir "$build_dir" --output-on-failure -j "$QP_JOBS" \
    -R '^(quadphase_core_tests|box2d_unit_tests_(quadphase|stock)|scenes:.*|example_headless)$'
node "$build_dir/examples/headless/quadphase-headless.js" "$@" | tee "$build_dir/headless-web.txt"
"$(qp_exe "$native_dir/examples/headless/quadphase-headless")" "$@" | tee "$build_dir/headless-native.txt"
set +x
web_line=$(tail -n 1 "$build_dir/headless-web.txt")
native_line=$(tail -n 1 "$build_dir/headless-native.txt")
echo "$QP_NAME: WebAssembly: $web_line"
echo "$QP_NAME: native:      $native_line"
if [[ "${web_line##* }" == "${native_line##* }" ]]; then
    echo "$QP_NAME: the position hashes are the same"
else
    echo "$QP_NAME: the position hashes differ in the scenes below (docs/design.md, \"Platforms and floating point\")"
    scene_hashes() { awk 'NF == 7 && $7 ~ /^[0-9a-f]+$/ { print $1, $7 }' "$1"; }
    diff <(scene_hashes "$build_dir/headless-web.txt") <(scene_hashes "$build_dir/headless-native.txt") || true
fi
