#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Race checker for the parallel code (the library's pool, OpenMP, a game's job system): builds the parallel tests
# with clang-14, LLVM's libomp and ThreadSanitizer, whose OpenMP support (archer, shipped with libomp-14-dev) the
# runtime loads by itself, and runs them. GCC's ThreadSanitizer is not used: it reports false races inside libgomp,
# which is not instrumented.
#
# Exit status: non-zero when ThreadSanitizer reports a race or a test fails.
# Environment: BUILD_DIR (default build-tsan), JOBS (default nproc), QUADPHASE_SKIP_DEPS=1,
#              QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh.
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for race
build_dir=${BUILD_DIR:-build-tsan}
llvm_lib=/usr/lib/llvm-14/lib

qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
    "-DCMAKE_CXX_FLAGS=-fsanitize=thread -fno-omit-frame-pointer" \
    "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=thread -Wl,-rpath,$llvm_lib" \
    -DQUADPHASE_BUILD_BENCH=OFF -DQUADPHASE_INSTALL=OFF
qp_build "$build_dir" quadphase_core_tests quadphase_parallel_tests
set -x

# ignore_noninstrumented_modules: libomp itself is not instrumented; archer tells TSan about its synchronisation.
# race-check.supp: Box2D's own statistics counters, which worlds stepped at once race on (see the file).
export TSAN_OPTIONS="ignore_noninstrumented_modules=1 halt_on_error=1 exitcode=66"
TSAN_OPTIONS+=" suppressions=$PWD/scripts/race-check.supp"
export LD_LIBRARY_PATH="$llvm_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" # where libomp looks for libarcher.so
export ARCHER_OPTIONS="verbose=1"                                        # prints that archer is loaded
export OMP_NUM_THREADS=2

"$build_dir/tests/core/quadphase_core_tests" "[parallel]"
QUADPHASE_DETERMINISM_STEPS=120 "$build_dir/tests/parallel/quadphase_parallel_tests"
set +x
echo "race-check: ThreadSanitizer found no race"
