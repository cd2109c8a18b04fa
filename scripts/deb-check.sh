#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The round trip of scripts/deb.sh's packages on this machine, with Debian's caveexpress as the program:
#
#   scripts/deb-check.sh [DEBDIR]        # default build/deb (scripts/deb.sh's OUTDIR); runs as root or through sudo
#
#   1. apt installs Debian's caveexpress and libbox2d2 (if they are not installed yet);
#   2. apt installs DEBDIR's libbox2d2-quadphase and libbox2d-quadphase-dev over them: libbox2d2 goes, caveexpress
#      stays, and a simulated `apt-get full-upgrade` does not bring libbox2d2 back; quadphase-which says
#      caveexpress loads quadphase's library; programs built against the -dev package with `pkg-config box2d`
#      and with CMake's find_package(box2d) load it too;
#      caveexpress (Debian's binary, no LD_LIBRARY_PATH) starts on a map under Xvfb with QUADPHASE_VALIDATE=1: its
#      /proc/PID/maps line shows the package's library, and validation reports 0 mismatches;
#   3. one apt transaction removes both packages and installs Debian's libbox2d2 again; the same start maps Debian's
#      library (dpkg -S, quadphase-which from the package's copy: stock), and `dpkg --verify libbox2d2` is clean.
# Whatever happens (an EXIT trap; also on Ctrl-C, SIGTERM or SIGHUP), the machine is put back as the script found
# it: every package its apt commands installed is purged, every package they removed or changed is installed again
# at its version (with its automatic mark); it says so at the end, or lists what it could not restore. It refuses to start when quadphase's packages
# are installed already. Work files and logs: DEBDIR/check/.
# Environment: QUADPHASE_SKIP_DEPS=1 (no scripts/install-deps.sh --for deb-check).
# Exit status: 0 when every check passed and the machine was restored, 1 otherwise, 2 on bad arguments.
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
source "$(dirname "${BASH_SOURCE[0]}")/lib/caveexpress.sh"

case "${1:-}" in -h | --help) sed -n '2,/^source /{/^# SPDX-License-Identifier: MIT$/!p}' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;; esac
[[ $# -le 1 ]] || { echo "deb-check: at most one argument, DEBDIR (see --help)" >&2; exit 2; }
debdir=${1:-build/deb}
readonly ours=(libbox2d2-quadphase libbox2d-quadphase-dev)
readonly game_map=ice-01 play_seconds=6
export LC_ALL=C # sort and comm agree on the order; apt's messages parse the same everywhere

die() { echo "deb-check: $*" >&2; exit 1; }
failures=()
fail() { echo "deb-check: FAIL: $*" >&2; failures+=("$*"); }

qp_deps scripts/install-deps.sh --for deb-check
as_root=()
[[ $(id -u) -eq 0 ]] || as_root=(sudo)

debdir=$(cd "$debdir" 2>/dev/null && pwd) || die "no directory ${1:-build/deb} (run scripts/deb.sh first)"
declare -A deb=()
for p in "${ours[@]}"; do
    files=("$debdir/${p}_"*.deb)
    [[ ${#files[@]} -eq 1 && -f "${files[0]}" ]] || die "want one $debdir/${p}_*.deb, found: ${files[*]}"
    deb[$p]=${files[0]}
done
library=/$(dpkg-deb -c "${deb[libbox2d2-quadphase]}" | awk '{ print $6 }' | sed -n 's|^\./||; /libbox2d\.so\.2\.4\.1$/p')
[[ "$library" == /usr/lib/*/libbox2d.so.2.4.1 ]] || die "${deb[libbox2d2-quadphase]} has no /usr/lib/<triplet>/libbox2d.so.2.4.1"
work=$debdir/check
rm -rf "$work" && mkdir -p "$work"
# The package's quadphase-which, kept for after the package is gone.
dpkg-deb -x "${deb[libbox2d2-quadphase]}" "$work/unpacked"
which_tool=$work/unpacked/usr/bin/quadphase-which

installed() { [[ "$(dpkg-query -W -f='${db:Status-Abbrev}' "$1" 2>/dev/null)" == ii* ]]; }
for p in "${ours[@]}"; do
    ! installed "$p" || die "$p is installed: remove it first (apt install libbox2d2), so that the machine the" \
                            "check leaves behind is one without quadphase's packages"
done

# --- the machine's state, and putting it back -------------------------------------------------------------------
# Installed packages as "name<TAB>version" lines, sorted.
snapshot() {
    dpkg-query -W -f='${db:Status-Abbrev}\t${binary:Package}\t${Version}\n' |
        awk -F'\t' '$1 ~ /^ii/ { print $2 "\t" $3 }' | sort >"$1"
}
snapshot "$work/before.txt"
apt-mark showauto | sort >"$work/auto-before.txt"
: >"$work/touched.txt"
apt_log=$work/apt.log
# apt-get -y ARG...; the packages whose state it changed go to touched.txt: only those are put back (other
# sessions may install packages on this machine meanwhile).
apt_running=""
apt_run() {
    local status=0
    snapshot "$work/apt-pre.txt"
    echo "deb-check: apt-get install $*" | tee -a "$apt_log"
    apt_running=1 # a signal during apt-get: restore() records what it changed
    DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get -y -o DPkg::Lock::Timeout=600 --no-install-recommends \
        install "$@" >>"$apt_log" 2>&1 || status=$?
    record_touched
    [[ $status -eq 0 ]] || { tail -n 20 "$apt_log" >&2; echo "deb-check: apt-get failed ($status)" >&2; }
    return $status
}
record_touched() { # the packages changed since apt-pre.txt
    snapshot "$work/apt-post.txt"
    diff "$work/apt-pre.txt" "$work/apt-post.txt" | sed -n 's/^[<>] \([^\t]*\)\t.*/\1/p' >>"$work/touched.txt"
    sort -u -o "$work/touched.txt" "$work/touched.txt"
    apt_running=""
}
# Whether PACKAGE (name or name:arch) is in an `apt-mark showauto` list (which names native packages without arch).
is_auto() { grep -qxF -e "$1" -e "${1%%:*}" "$2"; }
restored=""
restore() {
    set +e
    qp_x_cleanup
    [[ -z "$apt_running" ]] || record_touched
    snapshot "$work/now.txt"
    local changes=() p want have
    while read -r p; do
        want=$(awk -F'\t' -v p="$p" '$1 == p { print $2 }' "$work/before.txt")
        have=$(awk -F'\t' -v p="$p" '$1 == p { print $2 }' "$work/now.txt")
        [[ "$want" == "$have" ]] && continue
        if [[ -z "$want" ]]; then changes+=("$p-"); else changes+=("$p=$want"); fi
    done <"$work/touched.txt"
    if [[ ${#changes[@]} -gt 0 ]]; then
        echo "deb-check: restoring the machine: apt-get install --purge ${changes[*]}"
        # Simulated first: a removal beyond the packages this script installed (say, a package another session
        # installed meanwhile that needs one of them) is not done, but reported.
        local extra
        extra=$(apt-get -s -y --allow-downgrades --purge --no-install-recommends install "${changes[@]}" 2>/dev/null |
                awk '$1 == "Purg" || $1 == "Remv" { print $2 }' | while read -r p; do
                    cut -d: -f1 "$work/touched.txt" | grep -qxF "${p%%:*}" || echo "$p"
                done)
        if [[ -n "$extra" ]]; then
            echo "deb-check: NOT restored: putting the packages back would also remove: $extra" >&2
        else
            DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get -y -o DPkg::Lock::Timeout=600 --allow-downgrades \
                --purge --no-install-recommends install "${changes[@]}" >>"$apt_log" 2>&1 ||
                echo "deb-check: apt-get failed while restoring (see $apt_log)" >&2
        fi
    fi
    # Automatic marks as they were (apt-get install marks what it names as installed by hand).
    while read -r p; do
        is_auto "$p" "$work/auto-before.txt" && "${as_root[@]}" apt-mark auto "$p" >/dev/null
    done < <(comm -12 "$work/touched.txt" <(cut -f1 "$work/before.txt"))
    snapshot "$work/after.txt"
    apt-mark showauto | sort >"$work/auto-after.txt"
    local diffs="" mark_before mark_after
    while read -r p; do
        want=$(awk -F'\t' -v p="$p" '$1 == p { print $2 }' "$work/before.txt")
        have=$(awk -F'\t' -v p="$p" '$1 == p { print $2 }' "$work/after.txt")
        [[ "$want" == "$have" ]] || diffs+="  $p: before ${want:-not installed}, now ${have:-not installed}"$'\n'
        [[ -n "$want" && "$want" == "$have" ]] || continue
        mark_before=manual mark_after=manual
        is_auto "$p" "$work/auto-before.txt" && mark_before=auto
        is_auto "$p" "$work/auto-after.txt" && mark_after=auto
        [[ $mark_before == "$mark_after" ]] || diffs+="  $p: installed $mark_before before, $mark_after now"$'\n'
    done <"$work/touched.txt"
    if [[ -z "$diffs" ]]; then
        restored=yes
        echo "deb-check: machine restored: $(wc -l <"$work/touched.txt") packages touched, each as it was" \
             "($work/before.txt, $work/after.txt)"
    else
        restored=no
        echo "deb-check: machine NOT fully restored:" >&2
        printf %s "$diffs" >&2
    fi
}
summary() {
    local status=$?
    restore
    echo
    echo "=== deb-check: summary ($work)"
    for line in "${summary_lines[@]}"; do echo "  $line"; done
    echo "  time: $(($(date +%s) - start)) s"
    [[ "$restored" == yes ]] || failures+=("the machine was not restored")
    [[ $status -eq 0 || ${#failures[@]} -gt 0 ]] || failures+=("stopped with status $status (see above)")
    if [[ ${#failures[@]} -gt 0 ]]; then
        echo "  FAILED (${#failures[@]}):"
        printf '    %s\n' "${failures[@]}"
        exit 1
    fi
    echo "  all checks passed"
}
start=$(date +%s)
summary_lines=()
trap summary EXIT
trap 'exit 130' INT
trap 'exit 143' TERM HUP # so that the EXIT trap runs

# Starts caveexpress on $game_map with QUADPHASE_VALIDATE=1 and no LD_LIBRARY_PATH; sets run_maps and run_validation.
run_game() { # NAME
    local log=$work/game-$1.log
    rm -rf "$work/home-$1" && mkdir -p "$work/home-$1"
    qp_xvfb_start "$work/xvfb-$1.log" || { fail "$1: Xvfb did not start (see $work/xvfb-$1.log)"; return; }
    echo "deb-check: $1: QUADPHASE_VALIDATE=1 $QP_GAME -map $game_map (no LD_LIBRARY_PATH, Xvfb $QP_DISPLAY)"
    qp_game_start "$log" "$work/home-$1" "$game_map" QUADPHASE_VALIDATE=1 ||
        fail "$1: no map started within 60 s (see $log)"
    sleep "$play_seconds"
    run_maps=$(qp_game_maps_line)
    kill -0 "$QP_GAME_PID" 2>/dev/null || fail "$1: the game exited before its maps were read (see $log)"
    qp_game_stop
    qp_x_cleanup
    read -r mismatches checked <<<"$(qp_validation_counts "$log")"
    run_validation="$mismatches mismatches, $checked UpdatePairs checked; exit status $QP_GAME_STATUS"
    echo "deb-check: $1: maps: $run_maps"
    echo "deb-check: $1: validation: $run_validation"
}
owner() { dpkg-query -S "$1" 2>/dev/null | cut -d: -f1; }

# --- 1. Debian's caveexpress and libbox2d2 ----------------------------------------------------------------------
missing=()
for p in caveexpress libbox2d2; do installed "$p" || missing+=("$p"); done
# (apt-get install would mark an installed package as installed by hand: only the missing ones)
[[ ${#missing[@]} -eq 0 ]] || apt_run "${missing[@]}" || die "could not install Debian's caveexpress and libbox2d2"
echo "deb-check: $(dpkg-query -W -f='${Package} ${Version}, ' caveexpress libbox2d2)$library from $(owner "$library")"

# --- 2. quadphase's packages over them --------------------------------------------------------------------------
apt_run "${deb[libbox2d2-quadphase]}" "${deb[libbox2d-quadphase-dev]}" || die "apt could not install the packages"
for p in "${ours[@]}" caveexpress; do installed "$p" || fail "$p is not installed after apt installed the packages"; done
! installed libbox2d2 || fail "libbox2d2 is still installed next to libbox2d2-quadphase"
[[ "$(owner "$library")" == libbox2d2-quadphase ]] || fail "$library belongs to '$(owner "$library")'"
# apt keeps the package: a full upgrade neither brings Debian's libbox2d2 back nor removes it.
upgrade=$(apt-get -s full-upgrade 2>&1 | grep -E '^(Inst|Remv) (libbox2d|caveexpress)' || true)
[[ -z "$upgrade" ]] || fail "apt-get full-upgrade would change the packages: $upgrade"
echo "deb-check: apt-get -s full-upgrade: ${upgrade:-no change to libbox2d2, caveexpress or the quadphase packages}"
which_line=$(quadphase-which "$QP_GAME") || fail "quadphase-which $QP_GAME failed: $which_line"
echo "deb-check: quadphase-which: $which_line"
[[ "$which_line" == *": quadphase, Box2D 2.4.1, package libbox2d2-quadphase "* ]] ||
    fail "quadphase-which does not say caveexpress loads the package's quadphase library"
summary_lines+=("installed: quadphase-which $which_line")
# The -dev package: a program built as Debian's packaging would, with pkg-config box2d, loads the package's library.
cat >"$work/world.cpp" <<'CPP'
#include <box2d/box2d.h>
#include <cstdio>
int main()
{
    b2World world(b2Vec2(0.0f, -10.0f));
    b2BodyDef def;
    def.type = b2_dynamicBody;
    b2PolygonShape box;
    box.SetAsBox(0.5f, 0.5f);
    for (int i = 0; i < 20; ++i)
    {
        def.position.Set(0.3f * i, 1.1f * i);
        world.CreateBody(&def)->CreateFixture(&box, 1.0f);
    }
    for (int i = 0; i < 120; ++i)
        world.Step(1.0f / 60.0f, 8, 3);
    std::printf("%d contacts\n", world.GetContactCount());
}
CPP
# shellcheck disable=SC2046 # pkg-config's flags are words
if g++ $(pkg-config --cflags box2d) "$work/world.cpp" -o "$work/world" $(pkg-config --libs box2d) 2>"$work/world-build.log"; then
    dev_line=$(QUADPHASE_VALIDATE=1 "$work/world" 2>&1 | tr '\n' ' ')
    dev_which=$(quadphase-which "$work/world") || true
    echo "deb-check: -dev: pkg-config box2d $(pkg-config --modversion box2d): $dev_line; $dev_which"
    [[ "$dev_which" == *": quadphase, "* ]] || fail "a program built with pkg-config box2d does not load quadphase's"
    [[ "$dev_line" == *"quadphase: validation: "*" 0 mismatches"* ]] || fail "-dev program's validation: $dev_line"
    summary_lines+=("-dev: g++ \$(pkg-config --cflags --libs box2d): $dev_line")
else
    fail "a program does not build with pkg-config box2d (see $work/world-build.log)"
fi
# ... and one built with CMake's find_package(box2d) and box2d::box2d.
mkdir -p "$work/cmake-game"
cat >"$work/cmake-game/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.20)
project(world CXX)
find_package(box2d REQUIRED)
add_executable(world ../world.cpp)
target_link_libraries(world PRIVATE box2d::box2d)
CMAKE
if cmake -S "$work/cmake-game" -B "$work/cmake-game/build" >"$work/cmake-game.log" 2>&1 &&
   cmake --build "$work/cmake-game/build" >>"$work/cmake-game.log" 2>&1; then
    cmake_which=$(quadphase-which "$work/cmake-game/build/world") || true
    echo "deb-check: -dev: find_package(box2d) $(sed -n 's/^box2d_DIR:PATH=//p' "$work/cmake-game/build/CMakeCache.txt"): $cmake_which"
    [[ "$cmake_which" == *": quadphase, "* ]] || fail "a program built with find_package(box2d) does not load quadphase's"
else
    fail "a program does not build with find_package(box2d) (see $work/cmake-game.log)"
fi
run_game quadphase
installed_maps=$run_maps
[[ "$installed_maps" == *" $library" ]] || fail "caveexpress did not map $library (maps: '$installed_maps')"
[[ "$run_validation" == "0 mismatches, "[1-9]* ]] || fail "validation on quadphase's library: $run_validation"
summary_lines+=("installed: maps  $installed_maps" "installed: validation: $run_validation")

# --- 3. back to Debian's libbox2d2 ------------------------------------------------------------------------------
back=(libbox2d2)
grep -qE '^libbox2d-dev(:[a-z0-9]+)?	' "$work/before.txt" && back+=(libbox2d-dev)
apt_run --purge "${back[@]}" "${ours[@]/%/-}" || die "apt could not go back to Debian's libbox2d2"
for p in "${ours[@]}"; do ! installed "$p" || fail "$p is still installed"; done
installed caveexpress || fail "caveexpress was removed with quadphase's packages"
[[ "$(owner "$library")" == libbox2d2 ]] || fail "$library belongs to '$(owner "$library")', not libbox2d2"
which_line=$("$which_tool" "$QP_GAME") || fail "quadphase-which $QP_GAME failed: $which_line"
echo "deb-check: quadphase-which (the package's copy): $which_line"
[[ "$which_line" == *": stock, Box2D 2.4.1, package libbox2d2 "* ]] ||
    fail "quadphase-which does not say caveexpress loads Debian's libbox2d2"
run_game stock
[[ "$run_maps" == *" $library" ]] || fail "caveexpress did not map $library (maps: '$run_maps')"
[[ "$run_validation" == "0 mismatches, - UpdatePairs"* ]] || fail "Debian's library reported validation: $run_validation"
verify=$(dpkg --verify libbox2d2 2>&1) || fail "dpkg --verify libbox2d2 failed"
[[ -z "$verify" ]] || fail "dpkg --verify libbox2d2: $verify"
echo "deb-check: dpkg --verify libbox2d2: ${verify:-clean}"
summary_lines+=("removed:   quadphase-which $which_line" "removed:   maps  $run_maps"
                "removed:   validation: $run_validation" "removed:   dpkg --verify libbox2d2: ${verify:-clean}")
