#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
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
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for test
build_dir=${BUILD_DIR:-build}
qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@"
qp_build "$build_dir"
set -x
ctest --test-dir "$build_dir" --output-on-failure -j "$QP_JOBS"
