#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Fuzzing with libFuzzer (clang-14, AddressSanitizer + UndefinedBehaviorSanitizer, no NDEBUG), two targets:
#   core   tests/fuzz/broadphase_fuzz.cpp: QuadtreeBroadPhase against the brute-force reference;
#   box2d  tests/fuzz/box2d_fuzz.cpp: quadphase's b2BroadPhase against Box2D 2.4.1's own, in one process.
# Every input is a program whose every answer is compared with the reference; a divergence aborts, so any
# divergence, crash, sanitizer report or leak fails this script (the input is saved under <build>/fuzz-<target>/).
#
# usage: scripts/fuzz.sh [--minutes M | --seconds S] [--target core|box2d|all] [--campaign] [--update-corpus]
#                        [libFuzzer flags, e.g. -seed=1 -runs=1000]
#   --minutes/--seconds  fuzzing time per target (default: FUZZ_SECONDS, else 60 s)
#   --target             which target (default all: each in turn, for the time given)
#   --campaign           keep the corpus between runs in <build>/campaign/<target>/corpus (seeded from the
#                        committed corpus and seeds) and append each run's executions, cov and ft to
#                        <build>/campaign/<target>/runs.log; at the end merge and minimise it
#                        (-merge=1 over edge coverage, -use_counters=0) into <build>/campaign/<target>/minimised
#   --update-corpus      with --campaign: replace tests/fuzz/corpus/<target> with the minimised corpus
# Without --campaign each run starts from a scratch copy of the committed corpus and seeds (tests/fuzz/seeds)
# and leaves the repository alone.
#
# Why these settings (measured; see docs/robustness.md, "Fuzzing"):
#   -O2; trace-cmp off (-fno-sanitize-coverage=trace-cmp); the checkers (Validate, the brute force, the targets'
#   comparisons) and Box2D's own sources out of coverage (tests/fuzz/coverage_ignorelist.txt). The comparison
#   tracing of UBSan's pointer checks in loops over every cell was most of an execution; ASan and UBSan still
#   instrument everything. -mllvm -inline-threshold=1000: UBSan's checks make one-line accessors (CellStore::Data)
#   too large to inline at -O2, and their calls were a sixth of the time. -entropic_scale_per_exec_time=1 gives
#   inputs that run faster more mutations.
#   OMP_NUM_THREADS=2 and KMP_BLOCKTIME=0: the 2-thread inputs run real parallel regions, and libomp's workers
#   sleep at once instead of spinning (on a 2-core machine a spinning worker steals the fuzzer's core).
#
# Exit status: non-zero on a divergence or crash, 0 otherwise. Prints executions, cov and ft per target.
# Environment: FUZZ_SECONDS (default 60), BUILD_DIR (default build-fuzz), JOBS (default nproc),
#              QUADPHASE_SKIP_DEPS=1, QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

usage() {
    sed -n '2,/^set -euo/{/^# SPDX-License-Identifier: MIT$/!p}' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'
}

seconds=${FUZZ_SECONDS:-60}
target=all
campaign=0
update=0
fuzzer_args=()
while [[ $# -gt 0 ]]; do
    case $1 in
    --minutes)
        [[ $# -ge 2 && $2 =~ ^[0-9]+([.][0-9]+)?$ ]] || { echo "fuzz.sh: --minutes needs a number" >&2; exit 2; }
        seconds=$(awk -v m="$2" 'BEGIN { printf "%d", m * 60 }')
        shift 2 ;;
    --seconds)
        [[ $# -ge 2 && $2 =~ ^[0-9]+$ ]] || { echo "fuzz.sh: --seconds needs a whole number" >&2; exit 2; }
        seconds=$2
        shift 2 ;;
    --target)
        [[ $# -ge 2 && $2 =~ ^(core|box2d|all)$ ]] || { echo "fuzz.sh: --target core|box2d|all" >&2; exit 2; }
        target=$2
        shift 2 ;;
    --campaign) campaign=1; shift ;;
    --update-corpus) update=1; shift ;;
    -h | --help) usage; exit 0 ;;
    -*=*) fuzzer_args+=("$1"); shift ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
if [[ $update == 1 && $campaign == 0 ]]; then
    echo "fuzz.sh: --update-corpus needs --campaign" >&2
    exit 2
fi
targets=(core box2d)
[[ $target != all ]] && targets=("$target")

if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    scripts/install-deps.sh --for fuzz >&2
fi

build_dir=${BUILD_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
llvm_lib=/usr/lib/llvm-14/lib

sanitizers="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
coverage="-fsanitize=fuzzer-no-link -fno-sanitize-coverage=trace-cmp"
coverage+=" -fsanitize-coverage-ignorelist=$PWD/tests/fuzz/coverage_ignorelist.txt"
configure_args=(-S . -B "$build_dir"
    -DCMAKE_BUILD_TYPE=RelWithDebInfo
    -DCMAKE_CXX_COMPILER=clang++-14
    "-DCMAKE_CXX_FLAGS=$coverage $sanitizers -mllvm -inline-threshold=1000"
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -g"
    "-DCMAKE_EXE_LINKER_FLAGS=$sanitizers -Wl,-rpath,$llvm_lib"
    -DQUADPHASE_FUZZ=ON
    -DQUADPHASE_BUILD_BENCH=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF -DQUADPHASE_INSTALL=OFF
    -DQUADPHASE_PACKAGE_TESTS=OFF)
[[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]] && configure_args+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
[[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]] && configure_args+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")

declare -A program=([core]=qp_fuzz_broadphase [box2d]=qp_fuzz_box2d)
build_targets=()
for t in "${targets[@]}"; do build_targets+=("${program[$t]}"); done
(
    set -x
    cmake "${configure_args[@]}"
    cmake --build "$build_dir" -j "$jobs" --target "${build_targets[@]}"
) >&2

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export OMP_NUM_THREADS=2
export KMP_BLOCKTIME=0

# Runs one target for $seconds over corpus directory $2 (inputs found are added there); log in $3.
run_fuzzer() {
    local t=$1 corpus=$2 log=$3 artifacts=$4
    local status=0
    mkdir -p "$artifacts"
    # No pipe: the fuzzer's exit status is the script's verdict.
    "$build_dir/tests/fuzz/${program[$t]}" "$corpus" \
        -max_total_time="$seconds" -timeout=30 -rss_limit_mb=2048 -print_final_stats=1 \
        -entropic_scale_per_exec_time=1 -artifact_prefix="$artifacts/" ${fuzzer_args[@]+"${fuzzer_args[@]}"} \
        >"$log" 2>&1 || status=$?
    grep -E "^#[0-9]+[[:space:]]+(INITED|DONE)|DIVERGENCE|ERROR|SUMMARY" "$log" || true
    return $status
}

# The committed corpus and the seeds (recorded scene traces) of target $1, copied into directory $2.
seed_corpus() {
    local d
    for d in tests/fuzz/corpus/"$1" tests/fuzz/seeds/"$1"; do
        if [[ -d $d ]] && compgen -G "$d/*" >/dev/null; then
            cp "$d"/* "$2/"
        fi
    done
}

failed=0
for t in "${targets[@]}"; do
    if [[ $campaign == 1 ]]; then
        work="$build_dir/campaign/$t"
        corpus="$work/corpus"
        if [[ ! -d $corpus ]]; then
            mkdir -p "$corpus"
            seed_corpus "$t" "$corpus"
        fi
    else
        work="$build_dir/fuzz-$t"
        corpus="$work/corpus"
        rm -rf "$work"
        mkdir -p "$corpus"
        seed_corpus "$t" "$corpus"
    fi
    log="$work/fuzz.log"
    status=0
    run_fuzzer "$t" "$corpus" "$log" "$work/artifacts" || status=$?
    executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    last=$(grep -E "^#[0-9]+[[:space:]]" "$log" | tail -1)
    cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
    ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
    if [[ $status -ne 0 ]]; then
        echo "fuzz[$t]: FAILED (exit status $status) after ${executions:-?} executions; input saved in $work/artifacts/:" >&2
        ls -l "$work/artifacts/" >&2 || true
        tail -40 "$log" >&2
        failed=1
        continue
    fi
    corpus_size=$(find "$corpus" -type f | wc -l)
    echo "fuzz[$t]: ${executions:-?} executions in $seconds s (${rate:-?}/s), cov ${cov:-?}, ft ${ft:-?}," \
        "0 divergences, 0 crashes (corpus $corpus_size inputs in $corpus)"
    if [[ $campaign == 1 ]]; then
        printf '%s seconds=%s executions=%s cov=%s ft=%s corpus=%s\n' "$(date -u +%FT%TZ)" "$seconds" \
            "${executions:-0}" "${cov:-?}" "${ft:-?}" "$corpus_size" >>"$work/runs.log"
        total=$(sed -n 's/.* executions=\([0-9]*\).*/\1/p' "$work/runs.log" | awk '{ s += $1 } END { print s }')
        # Minimise: the smallest set of inputs that keeps every edge (not every hit-count bucket: that keeps the
        # committed corpus at tens of inputs).
        rm -rf "$work/minimised"
        mkdir -p "$work/minimised"
        "$build_dir/tests/fuzz/${program[$t]}" -merge=1 -use_counters=0 "$work/minimised" "$corpus" \
            >"$work/merge.log" 2>&1
        echo "fuzz[$t]: campaign total $total executions over $(wc -l <"$work/runs.log") runs;" \
            "minimised corpus $(find "$work/minimised" -type f | wc -l) inputs in $work/minimised"
        if [[ $update == 1 ]]; then
            rm -f tests/fuzz/corpus/"$t"/*
            cp "$work/minimised"/* tests/fuzz/corpus/"$t"/
            echo "fuzz[$t]: tests/fuzz/corpus/$t replaced by the minimised corpus"
        fi
    fi
done
exit $failed
