#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Many cores: how pair generation grows with the cores of a machine, and how much CPU the library's defaults take.
# Records the particles and rain traces, replays them at 1, 2, 4, 8 and 16 threads (up to the machine's cores; pair
# sets checked against stock Box2D's at 1 and the most threads), runs the paper's protocol (qp-circles) at each thread
# count, and steps the frames scenes (particles 20,000 and 50,000, pyramid 50, rain 4,000: stock, 1 thread, the
# defaults, a job system; alone and beside a busy thread) with the process's CPU time beside wall time. See
# bench/README.md ("Many cores").
#
#   bench/manycore.sh                   # here: --prepare, run and --report in one go (BUILD_DIR/manycore, BUILD_DIR/
#                                       # manycore-out; BUILD_DIR default build-bench)
#   bench/manycore.sh --prepare DIR     # build the tools (Release, -O2) and copy them, every shared library they load
#                                       # (glibc's loader and libc included) and this script, as DIR/run.sh, into DIR
#   DIR/run.sh [--small|--large|--smoke] [--out OUT] [--work TMP]
#                                       # on the machine to measure, which needs nothing but bash, coreutils and DIR:
#                                       # raw results (JSON lines, logs, machine.txt) in OUT (default DIR/out); traces
#                                       # in TMP (default a new directory under ${TMPDIR:-/tmp}, removed at the end)
#   bench/manycore.sh --report OUT      # here, with Python (and matplotlib for the plot): bench/results/
#                                       # manycore.{md,csv,png} from a run's OUT
#
# Profiles: --large (the default from 8 cores: traces particles 100,000 and rain 65,536, at most 6 minutes on 16
# cores) and --small (the default below 8 cores: particles 20,000 and rain 16,384, at most 10 minutes on 2 cores).
# The frames scenes and steps are the same in both. --smoke: tiny sizes and few steps, a minute or two: whether the
# folder runs on a machine, not a measurement.
#
# Environment for --prepare: QUADPHASE_SKIP_DEPS=1, BUILD_DIR, JOBS, QUADPHASE_BOX2D_SOURCE_DIR /
# QUADPHASE_BOX2D_TARBALL (scripts/lib/build.sh).
set -euo pipefail

HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
TOOLS=(qp-record qp-replay qp-step-stock qp-step-quadtree qp-circles)
# glibc's own libraries, copied as they are (the folder runs the tools with its own loader, which must match its libc).
GLIBC_RE='^(ld-linux[^/]*|libc|libm|libpthread|libdl|librt|libresolv|libmvec)\.so'

die() {
    echo "manycore: $*" >&2
    exit 2
}

usage() {
    sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'
}

# ---------------------------------------------------------------------------------------------------------------
# --prepare DIR: on a machine with the build dependencies
# ---------------------------------------------------------------------------------------------------------------
prepare() {
    local dir=$1 build tool lib name real
    [[ -n $dir ]] || die "--prepare needs a directory"
    [[ $dir == /* ]] || dir=$PWD/$dir
    source "$HERE/../scripts/lib/build.sh" # cds to the repository root
    build=${BUILD_DIR:-build-bench}
    qp_deps bench/install-deps.sh
    echo "manycore: configuring and building ${TOOLS[*]} in $build (-O2) ..." >&2
    QP_LOG=1 qp_configure "$build" -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" \
        -DQUADPHASE_BUILD_BENCH=ON -DQUADPHASE_BUILD_TESTS=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF
    QP_LOG=1 qp_build "$build" "${TOOLS[@]}"
    if [[ -e $dir && ! -f $dir/manycore.env && -n $(ls -A "$dir") ]]; then
        die "$dir exists and is not a prepared folder: give a new directory"
    fi
    rm -rf "$dir"
    mkdir -p "$dir/bin" "$dir/lib"
    # Every library the tools load (ldd's paths; the loader itself by its own path), one file per soname.
    declare -A where=()
    for tool in "${TOOLS[@]}"; do
        cp "$(qp_exe "$build/bench/$tool")" "$dir/bin/$tool"
        while read -r name real; do
            name=$(basename "$name") real=$(readlink -f "$real")
            [[ -z ${where[$name]:-} || ${where[$name]} == "$real" ]] ||
                die "$tool loads $name from $real, another tool from ${where[$name]}: one folder cannot hold both"
            where[$name]=$real
        done < <(ldd "$dir/bin/$tool" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3} $1 ~ /^\/.*ld-linux/ {print $1, $1}')
    done
    for name in "${!where[@]}"; do
        cp "${where[$name]}" "$dir/lib/$name"
    done
    [[ -f $dir/lib/ld-linux-x86-64.so.2 ]] || die "no ld-linux-x86-64.so.2 among the tools' libraries (x86-64 only)"
    cp "$HERE/manycore.sh" "$dir/run.sh"
    chmod +x "$dir/run.sh"
    /usr/bin/python3 bench/manycore.py --describe "$build" >"$dir/build.json"
    echo "prepared by bench/manycore.sh --prepare from $(git log -1 --format='%h %s' 2>/dev/null || echo '?')" \
        >"$dir/manycore.env"
    # Every tool must find every library in DIR: list what the bundled loader would load, from DIR only.
    for tool in "${TOOLS[@]}"; do
        local outside
        outside=$("$dir/lib/ld-linux-x86-64.so.2" --list --library-path "$dir/lib" "$dir/bin/$tool" |
            awk -v d="$dir/" '$2 == "=>" && index($3, d) != 1')
        [[ -z $outside ]] || die "$tool would load libraries from outside $dir: $outside"
    done
    # Symbols only make the folder heavier to carry.
    for lib in "$dir"/bin/* "$dir"/lib/*; do
        if [[ -f $lib && ! $(basename "$lib") =~ $GLIBC_RE ]]; then
            strip --strip-unneeded "$lib"
        fi
    done
    echo "manycore: prepared $dir ($(du -sh "$dir" | cut -f1)): DIR/run.sh measures, bench/manycore.sh --report OUT" \
        "writes the report" >&2
}

cpus_busy() { # CORES: how many CPUs were in use over the next second (by anything), from /proc/stat, as "1.23"
    local u n s i w q sq st t i2 t2 x
    read -r _ u n s i w q sq st _ </proc/stat
    t=$((u + n + s + i + w + q + sq + st)) i2=$((i + w))
    sleep 1
    read -r _ u n s i w q sq st _ </proc/stat
    t2=$((u + n + s + i + w + q + sq + st - t)) i2=$((i + w - i2))
    x=$(($1 * 100 * (t2 - i2) / (t2 > 0 ? t2 : 1)))
    printf '%d.%02d\n' $((x / 100)) $((x % 100))
}

now() { # seconds since the epoch (bash 5 has them built in)
    echo "${EPOCHSECONDS:-$(date +%s)}"
}

exe() { # DIR TOOL ARG...: runs a tool of a prepared folder through the folder's own loader and libraries
    "$1/lib/ld-linux-x86-64.so.2" --library-path "$1/lib" "$1/bin/$2" "${@:3}"
}

# ---------------------------------------------------------------------------------------------------------------
# DIR/run.sh: on the machine to measure (bash, coreutils and the prepared folder)
# ---------------------------------------------------------------------------------------------------------------
# run.sh's options: sets profile, out, work (and keep_work when --work is given); dies on anything else.
parse_run_args() {
    profile="" out="" work="" keep_work=0
    while [[ $# -gt 0 ]]; do
        case "$1" in
            --small | --large | --smoke) profile=${1#--}; shift ;;
            --out) [[ $# -ge 2 ]] || die "--out needs a directory"; out=$2; shift 2 ;;
            --work) [[ $# -ge 2 ]] || die "--work needs a directory"; work=$2; keep_work=1; shift 2 ;;
            *) die "unknown option '$1' (--small, --large, --smoke, --out OUT, --work TMP; --help)" ;;
        esac
    done
}

measure() {
    local dir=$HERE profile out work keep_work
    parse_run_args "$@"
    local cores
    cores=$(nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
    [[ -n $profile ]] || { ((cores >= 8)) && profile=large || profile=small; }
    out=${out:-$dir/out}
    if [[ -z $work ]]; then
        work=$(mktemp -d "${TMPDIR:-/tmp}/qp-manycore.XXXXXX")
    fi
    mkdir -p "$out" "$work"
    out=$(cd "$out" && pwd)
    # The sizes: particles and rain traces (warm-up + timed steps as bench/parallel.py's quick replay), timed rounds,
    # the circles search's time cap per thread count, the frames' steps.
    local particles=100000 rain=65536 repeats=5 circles_cap=20 frame_steps=300
    case $profile in
        small) particles=20000 rain=16384 ;;
        smoke) particles=2000 rain=1000 repeats=1 circles_cap=2 frame_steps=20 ;;
    esac
    local threads=() t
    for t in 1 2 4 8 16; do ((t <= cores)) && threads+=("$t"); done
    ((cores > threads[-1] && cores < 16)) && threads+=("$cores")
    ((cores < 2)) && threads+=(2) # one core: 2 threads still show what a second thread costs there
    local max=${threads[-1]} jobs=$((cores - 1 > 2 ? cores - 1 : 2))

    rm -f "$out"/*.jsonl "$out"/run.log "$out"/timing.txt "$out"/mismatch.txt
    local log=$out/run.log
    {
        echo "profile $profile"
        echo "cores $cores"
        echo "threads ${threads[*]}"
        echo "job_workers $jobs"
        echo "particles $particles"
        echo "rain $rain"
        echo "repeats $repeats"
        echo "circles_cap_s $circles_cap"
        echo "frame_steps $frame_steps"
        echo "cpu $(while IFS=: read -r k v; do [[ $k == model\ name* ]] && { echo "${v# }"; break; }; done </proc/cpuinfo)"
        echo "kernel $(uname -r 2>/dev/null || echo '?')"
        echo "loadavg_start $(cut -d' ' -f1-3 /proc/loadavg)"
        echo "omp_env $(env | grep -E '^G?OMP_' | tr '\n' ' ' || true)"
        echo "started $(date -u +%Y-%m-%dT%H:%M:%SZ)"
        command -v lscpu >/dev/null && lscpu | sed 's/^/lscpu /'
    } >"$out/machine.txt"
    cp "$dir/build.json" "$out/build.json"
    # The defaults as a game runs them: OpenMP's own thread count (the replay and the circles set theirs).
    unset OMP_NUM_THREADS
    echo "manycore: $profile profile on $cores CPUs: threads ${threads[*]}; raw results in $out, traces in $work" >&2

    local t0 part_start
    t0=$(now)
    part() { # KEY WHAT: a part starts; the previous one's seconds go to timing.txt, how busy the machine is now (the
        # other processes: nothing of the run's is running) to machine.txt
        [[ -n ${part_key:-} ]] && echo "$part_key $(($(now) - part_start))" >>"$out/timing.txt"
        [[ -n $1 ]] || return 0
        echo "busy_before_$1 $(cpus_busy "$cores")" >>"$out/machine.txt"
        part_key=$1 part_start=$(now)
        echo "manycore: [$(($(now) - t0)) s] $2" >&2
    }
    tool() { # TOOL ARG...: runs a tool of the folder; its output goes to run.log
        echo "\$ $*" >>"$log"
        exe "$dir" "$@" >>"$log" 2>&1
    }

    exe "$dir" qp-replay --print-config >>"$out/machine.txt" || die "qp-replay does not run on this machine"

    part record "recording the traces"
    local scene size warmup trace traces=()
    for scene in particles rain; do
        size=$particles warmup=60
        [[ $scene == rain ]] && size=$rain warmup=120
        trace=$work/$scene-$size-w$warmup-s30.qptrace
        tool qp-record --scene "$scene" --size "$size" --seed 1 --warmup "$warmup" --steps 30 --out "$trace" ||
            die "qp-record $scene $size failed (see $log)"
        traces+=("$trace")
    done

    part check "checking pair sets against stock's (1 and $max threads) and timing stock"
    local code
    for trace in "${traces[@]}"; do
        tool qp-replay --engine stock --trace "$trace" --repeats 1 --check first --hashes-out "$trace.stock.hash" \
            --json "$out/replay.jsonl" --label "replay|stock" || die "qp-replay --engine stock failed (see $log)"
        code=0
        tool qp-replay --trace "$trace" --repeats 0 --check all --compare-hashes "$trace.stock.hash" \
            --config "threads=1" --config "threads=$max" --json "$out/replay.jsonl" --label "check" || code=$?
        ((code == 0)) || echo "$(basename "$trace") exit $code" >>"$out/mismatch.txt"
        ((code == 0 || code == 3)) || die "qp-replay --check failed with code $code (see $log)"
    done

    part replay "replaying at ${threads[*]} threads ($repeats rounds)"
    local configs=()
    for t in "${threads[@]}"; do configs+=(--config "threads=$t"); done
    for trace in "${traces[@]}"; do
        tool qp-replay --trace "$trace" --repeats "$repeats" --check none "${configs[@]}" \
            --json "$out/replay.jsonl" --label "replay" || die "qp-replay failed (see $log)"
    done

    part circles "the paper's protocol at ${threads[*]} threads"
    local circles=(--depth auto --max-seconds "$circles_cap" --frames 5 --warmup 10 --start 4000 --precision 0.1
        --json "$out/circles.jsonl" --label circles)
    tool qp-circles --engine stock "${circles[@]}" || die "qp-circles failed (see $log)"
    for t in "${threads[@]}"; do
        tool qp-circles --engine quadtree --threads "$t" "${circles[@]}" || die "qp-circles failed (see $log)"
    done

    part frames "frames ($frame_steps steps from the first), the process's CPU time beside wall time"
    local engines=("stock|stock|" "1 thread|quadtree|--threads 1" "defaults|quadtree|--threads default"
        "job system|quadtree|--threads default --jobs $jobs")
    local e name build opts busy
    for scene in "particles 20000" "particles 50000" "pyramid 50" "rain 4000"; do
        for busy in "" --busy; do
            for e in "${engines[@]}"; do
                IFS='|' read -r name build opts <<<"$e"
                # shellcheck disable=SC2086 # scene, opts: words
                tool "qp-step-$build" --scene ${scene% *} --size ${scene#* } --seed 1 --warmup 0 --steps "$frame_steps" \
                    $opts $busy --json "$out/frames.jsonl" --label "frames|$name|round=0" ||
                    die "qp-step-$build $scene $name $busy failed (see $log)"
            done
        done
    done
    part "" ""
    echo "total $(($(now) - t0))" >>"$out/timing.txt"
    # The tools' user and system time, from the builtin's second line, "1m2.5s 0m0.1s" (run in this shell: in a
    # command substitution it would count the subshell's children only).
    local tools_cpu
    times >"$work/times"
    { read -r _ && read -r tools_cpu; } <"$work/times"
    echo "tools_cpu $tools_cpu" >>"$out/timing.txt"
    echo "loadavg_end $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/machine.txt"
    ((keep_work)) || rm -rf "$work"
    [[ ! -s $out/mismatch.txt ]] || echo "manycore: PAIR SETS DIFFER FROM STOCK'S: $(cat "$out/mismatch.txt")" >&2
    echo "manycore: done in $(($(now) - t0)) s; raw results in $out (bench/manycore.sh --report $out" \
        "writes the report)" >&2
}

# ---------------------------------------------------------------------------------------------------------------
mode=all
[[ -f $HERE/manycore.env ]] && mode=run # a prepared folder's run.sh
case "${1:-}" in
    -h | --help) usage; exit 0 ;;
    --prepare)
        [[ $mode == all ]] || die "--prepare runs in the repository (it builds): bench/manycore.sh --prepare DIR"
        [[ $# -eq 2 ]] || die "usage: bench/manycore.sh --prepare DIR"
        prepare "$2" ;;
    --report)
        [[ $mode == all ]] || die "--report runs in the repository (it needs Python): bench/manycore.sh --report OUT"
        [[ $# -ge 2 ]] || die "usage: bench/manycore.sh --report OUT [--results DIR]"
        exec /usr/bin/python3 "$HERE/manycore.py" "${@:2}" ;;
    *)
        if [[ $mode == run ]]; then
            measure "$@"
        else
            parse_run_args "$@" # before the build: a wrong option must not cost one
            build=${BUILD_DIR:-build-bench}
            [[ $build == /* ]] || build=$(cd "$HERE/.." && pwd)/$build
            (prepare "$build/manycore")
            out=${out:-$build/manycore-out}
            "$build/manycore/run.sh" "$@" --out "$out"
            exec /usr/bin/python3 "$HERE/manycore.py" "$out"
        fi ;;
esac
