#!/usr/bin/env bash
# Fuzzer: builds tests/fuzz/broadphase_fuzz.cpp with clang-14's libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer (the core instrumented too, no NDEBUG), and runs it over a scratch copy of the
# committed seed corpus for a bounded time. Every input drives the quadtree and the brute-force reference with the
# same calls and aborts on the first divergence, so any divergence, crash, sanitizer report or leak fails this
# script. New corpus entries go to the scratch copy only, never into the repository.
#
# Exit status: non-zero on a divergence or crash (the input is saved under <build>/artifacts/), 0 otherwise.
# Prints the number of executions.
# Environment: FUZZ_SECONDS (default 60), BUILD_DIR (default build-fuzz), JOBS (default nproc),
#              QUADPHASE_SKIP_DEPS=1, QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh
#              (configure needs Box2D's source even though the fuzzer does not use Box2D).
# Extra arguments are passed to the fuzzer (e.g. -seed=1 -runs=1000).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    scripts/install-deps.sh --for fuzz >&2
fi

build_dir=${BUILD_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
seconds=${FUZZ_SECONDS:-60}
llvm_lib=/usr/lib/llvm-14/lib

# -O1 -g without NDEBUG, like a debug build. fuzzer-no-link gives the core coverage instrumentation;
# the fuzz target itself adds -fsanitize=fuzzer (tests/fuzz/CMakeLists.txt).
sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
configure_args=(-S . -B "$build_dir"
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
    -DCMAKE_CXX_COMPILER=clang++-14
    "-DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link $sanitizers"
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g"
    "-DCMAKE_EXE_LINKER_FLAGS=$sanitizers -Wl,-rpath,$llvm_lib"
    -DQUADPHASE_FUZZ=ON
    -DQUADPHASE_BUILD_BENCH=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF -DQUADPHASE_INSTALL=OFF
    -DQUADPHASE_PACKAGE_TESTS=OFF)
[[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]] && configure_args+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
[[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]] && configure_args+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")

set -x
cmake "${configure_args[@]}"
cmake --build "$build_dir" -j "$jobs" --target qp_fuzz_broadphase
set +x

# A scratch copy of the seed corpus: libFuzzer adds the inputs it finds interesting to the first directory.
work="$build_dir/fuzz-run"
rm -rf "$work"
mkdir -p "$work/corpus" "$work/artifacts"
cp tests/fuzz/corpus/* "$work/corpus/"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export OMP_NUM_THREADS=2
export KMP_BLOCKTIME=0 # libomp threads sleep at once instead of spinning 200 ms: twice the executions on 2 shared cores
log="$work/fuzz.log"
status=0
"$build_dir/tests/fuzz/qp_fuzz_broadphase" "$work/corpus" \
    -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$work/artifacts/" "$@" 2>&1 | tee "$log" | grep -E "^#[0-9]+[[:space:]]+(INITED|DONE)|DIVERGENCE|ERROR|SUMMARY|stat::" || true
status=${PIPESTATUS[0]}

executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
if [[ $status -ne 0 ]]; then
    echo "fuzz: FAILED (exit status $status) after ${executions:-?} executions; input saved in $work/artifacts/:" >&2
    ls -l "$work/artifacts/" >&2 || true
    tail -40 "$log" >&2
    exit 1
fi
corpus_size=$(find "$work/corpus" -type f | wc -l)
echo "fuzz: ${executions:-?} executions in ${seconds} s, 0 divergences, 0 crashes (corpus $corpus_size inputs in $work/corpus)"
