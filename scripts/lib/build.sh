# SPDX-License-Identifier: MIT
# scripts/lib/build.sh: the preamble every build script shares (scripts/*.sh, bench/*.sh). Source it:
#
#   source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"      # from scripts/; bench/ uses ../scripts/lib/build.sh
#
# Sourcing it sets `set -euo pipefail`, cds to the repository root and sets
#   QP_NAME   the calling script's name without .sh (for messages)
#   QP_JOBS   parallel build jobs: $JOBS, default nproc
# and offers:
#   qp_deps [SCRIPT [PKG...]]     run SCRIPT (default scripts/install-deps.sh) with PKG... unless QUADPHASE_SKIP_DEPS=1
#   qp_configure DIR [ARG...]     cmake -S . -B DIR ARG... plus the Box2D source options from the environment
#                                 (QUADPHASE_BOX2D_SOURCE_DIR, QUADPHASE_BOX2D_TARBALL); exits 1 with a message on failure
#   qp_configure_cross DIR TOOLCHAIN [ARG...]
#                                 qp_configure for a cross target's suite: the toolchain file, Release, no benchmarks,
#                                 package tests or install rules
#   qp_build DIR [TARGET...]      cmake --build DIR -j QP_JOBS [--target TARGET...]; exits 1 with a message on failure
#   qp_ctest DIR LOG LABEL [ARG...]
#                                 ctest --test-dir DIR --output-on-failure -j QP_JOBS ARG..., its output also in LOG;
#                                 then prints "QP_NAME: LABEL: <ctest's summary line>" last and returns ctest's status
#   qp_exe DIR/PATH               DIR/PATH, or DIR/<dir of PATH>/Release/<name> (multi-config generators); exits 1 if
#                                 neither is executable
# With QP_LOG=1, qp_configure and qp_build write DIR/configure.log and DIR/build.log and show only their tails on
# failure; otherwise their output goes to stderr.
#
# Every CMake build configured after sourcing it (its own, Box2D's, the package tests', a game's) compiles through
# ccache when ccache is installed: CI builds the same sources with the same flags on every push, and several scripts
# build Box2D again. Paths are hashed relative to the repository (CCACHE_BASEDIR), so a fresh clone elsewhere hits
# the cache too. QUADPHASE_CCACHE=0 turns it off; a CMAKE_<LANG>_COMPILER_LAUNCHER already set is kept.
set -euo pipefail
QP_NAME=$(basename "${BASH_SOURCE[1]:-$0}" .sh)
QP_JOBS=${JOBS:-$(nproc 2>/dev/null || echo 2)}
cd "$(dirname "${BASH_SOURCE[0]}")/../.."

if [[ "${QUADPHASE_CCACHE:-1}" != 0 ]] && command -v ccache >/dev/null 2>&1; then
    export CMAKE_C_COMPILER_LAUNCHER=${CMAKE_C_COMPILER_LAUNCHER:-ccache}
    export CMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}
    export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
    export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}  # -g's working directory: not part of the hash
    # dpkg-buildpackage gives debhelper a scratch HOME; keep the one cache.
    CCACHE_DIR=${CCACHE_DIR:-$(ccache -k cache_dir 2>/dev/null || true)}
    [[ -n "$CCACHE_DIR" ]] && export CCACHE_DIR
fi

qp_deps() {
    if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
        "${1:-scripts/install-deps.sh}" "${@:2}" >&2
    fi
}

_qp_run() { # LOG-NAME DIR WHAT COMMAND...
    local log=$2/$1.log
    mkdir -p "$2"
    if [[ "${QP_LOG:-0}" == 1 ]]; then
        "${@:4}" >"$log" 2>&1 || { tail -n 40 "$log" >&2; echo "$QP_NAME: $3 failed (full log $log)." >&2; exit 1; }
    else
        "${@:4}" >&2 || { echo "$QP_NAME: $3 failed (see above)." >&2; exit 1; }
    fi
}

qp_configure() {
    local dir=$1 box2d=()
    [[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]] && box2d+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
    [[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]] && box2d+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")
    _qp_run configure "$dir" "configuring $dir" cmake -S . -B "$dir" "${box2d[@]}" "${@:2}"
}

qp_configure_cross() {
    qp_configure "$1" "-DCMAKE_TOOLCHAIN_FILE=$2" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_BENCH=OFF \
        -DQUADPHASE_PACKAGE_TESTS=OFF -DQUADPHASE_INSTALL=OFF "${@:3}"
}

qp_build() { # no TARGET: the default target
    local targets=()
    [[ $# -gt 1 ]] && targets=(--target "${@:2}")
    _qp_run build "$1" "building${2:+ ${*:2}} in $1" cmake --build "$1" -j "$QP_JOBS" "${targets[@]}"
}

qp_ctest() {
    local rc=0
    set -x
    ctest --test-dir "$1" --output-on-failure -j "$QP_JOBS" "${@:4}" 2>&1 | tee "$2" || rc=$?
    { set +x; } 2>/dev/null
    echo "$QP_NAME: $3: $(grep -E 'tests passed|tests failed' "$2" | tail -n 1)"
    return "$rc"
}

qp_exe() {
    local alt
    alt="$(dirname "$1")/Release/$(basename "$1")"
    for candidate in "$1" "$alt"; do
        [[ -x "$candidate" ]] && { echo "$candidate"; return 0; }
    done
    echo "$QP_NAME: $1 not found after the build." >&2
    exit 1
}
