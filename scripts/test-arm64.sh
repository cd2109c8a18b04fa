#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ARM64 Linux: cross-build quadphase with Debian's aarch64 toolchain (cmake/toolchains/aarch64-linux-gnu.cmake) and
# run its tests under qemu-user (qemu-aarch64 -L /usr/aarch64-linux-gnu, through CMAKE_CROSSCOMPILING_EMULATOR):
# the core tests against the brute-force reference, the Box2D adapter tests against stock Box2D built for the same
# target (every scene in validation mode, query and ray-cast answers, parallel determinism and threads, robustness,
# the fuzz corpora, the accuracy checker, the ABI and exports of libbox2d.so.2) and Box2D's own unit tests against
# both builds. ARM64 has no SSE2, so box_simd.h's scalar definitions are what every test runs there.
#
# Left out: quadphase-scene and its tests (cairo and ffmpeg of the build machine: QUADPHASE_TEST_HOST_ONLY is OFF in
# a cross build), the package tests, the benchmarks. parallel_determinism steps each scene 120 times instead of 600
# (QUADPHASE_DETERMINISM_STEPS, as scripts/race-check.sh does): at 600 it alone takes about 6 CPU minutes under qemu.
#
# Environment: as scripts/test.sh (QUADPHASE_SKIP_DEPS, JOBS, QUADPHASE_BOX2D_SOURCE_DIR, QUADPHASE_BOX2D_TARBALL);
# BUILD_DIR (default build-arm64). Compiles through ccache when it is installed (scripts/lib/build.sh). Extra
# arguments are passed to the CMake configure step. Prints ctest's summary line last; exits with ctest's status.
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for arm64
build_dir=${BUILD_DIR:-build-arm64}
qp_configure_cross "$build_dir" cmake/toolchains/aarch64-linux-gnu.cmake "$@"
qp_build "$build_dir"

export QUADPHASE_DETERMINISM_STEPS=${QUADPHASE_DETERMINISM_STEPS:-120}
qp_ctest "$build_dir" "$build_dir/ctest-arm64.log" "ARM64 under qemu-aarch64"
