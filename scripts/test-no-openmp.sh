#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The test suite as Apple's default toolchain would build it: clang-14 with LLVM's libc++ and no OpenMP
# (-DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=TRUE, so QUADPHASE_OPENMP is OFF). Pair generation then runs in parallel on
# the library's own pool (the default executor, plain std::thread) or a game's TaskSystem (tests/parallel,
# examples/job_system); only Executor::OpenMP falls back to serial, as Config::threads says (tests/core
# [fallback]). Every test runs, Box2D's own unit tests against both builds included, except:
#   - the cases of OpenMP's schedules and team ([openmp] in quadphase_core_tests and parallel_determinism,
#     parallel_threads_openmp, parallel_spin_openmp): tests/ leaves them out in a build without OpenMP;
#   - package_add_subdirectory: it compiles Box2D a third time to test CMake packaging, which package_find_package
#     tests here already (with the installed libbox2d.so needing no OpenMP runtime);
#   - the benchmarks (bench/ needs OpenMP).
#
# Prints ctest's summary line last; exits with ctest's status.
# Environment: BUILD_DIR (default build-no-openmp), JOBS (default nproc), QUADPHASE_SKIP_DEPS=1,
#              QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh.
# Extra arguments are passed to ctest (e.g. -R core).
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for no-openmp
build_dir=${BUILD_DIR:-build-no-openmp}

qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER=clang++-14 \
    -DCMAKE_CXX_FLAGS=-stdlib=libc++ -DCMAKE_EXE_LINKER_FLAGS=-stdlib=libc++ \
    -DCMAKE_SHARED_LINKER_FLAGS=-stdlib=libc++ \
    -DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=TRUE -DQUADPHASE_BUILD_BENCH=OFF
if grep -q '^QUADPHASE_OPENMP:BOOL=ON' "$build_dir/CMakeCache.txt"; then
    echo "$QP_NAME: $build_dir was configured with QUADPHASE_OPENMP=ON; use a fresh BUILD_DIR" >&2
    exit 1
fi
qp_build "$build_dir"
qp_ctest "$build_dir" "$build_dir/ctest-no-openmp.log" "clang-14 + libc++ without OpenMP" \
    -E '^package_add_subdirectory$' "$@"
