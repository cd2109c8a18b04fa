#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# A real Box2D 2.4.1 game on quadphase: Debian's CaveExpress 2.5.2 (C++11, finds Box2D with `pkg-config box2d`).
#
#   scripts/real-game.sh                      # everything below, into build-real-game/
#   scripts/real-game.sh --skip-binary        # no Xvfb run of Debian's binary package
#   scripts/real-game.sh --help
#
# Phases (each can be skipped; the summary at the end says what ran):
#   deps      scripts/install-deps.sh --for real-game (idempotent)
#   prefixes  configure and build this repository (Release), then `cmake --install` it twice:
#               WORK/prefix-quadphase                               quadphase's libbox2d under Box2D's own names
#               WORK/prefix-stock (--component box2d_stock)         stock Box2D 2.4.1, same source, same flags
#   source    Debian's source package caveexpress 2.5.2 through a private apt configuration
#             (cmake/DebianSource.cmake), orig tarball checked against its SHA-256, unpacked once per build, with
#             the build fixes of Debian's packaging (README.md, "Use it in an existing game")
#   build     the game built twice, unchanged, -std=c++11 as it sets it, once with PKG_CONFIG_PATH and
#             CMAKE_PREFIX_PATH on each prefix; the Box2D each build found, its compile flags and the library its
#             programs load (ldd) are checked against the prefix. Also builds examples/real_game's physics driver
#             inside the game's build (physics_driver.cmake).
#   tests     the game's test suite (tests_caveexpress, googletest) on both builds, QUADPHASE_VALIDATE=1 on
#             quadphase's; the passed and failed lists must be the same (WORK/tests-*.txt, diffed)
#   physics   caveexpress-physics plays MAPS for SECONDS simulated seconds on both builds: b2World::Step times
#             (median of b2Profile::step), then once more on quadphase with QUADPHASE_VALIDATE=1: 0 mismatches
#   binary    Debian's binary package caveexpress, unmodified, under Xvfb with LD_LIBRARY_PATH=WORK/prefix-quadphase/lib
#             and QUADPHASE_VALIDATE=1, started on a map (-map): its /proc/PID/maps line for libbox2d.so.2, a
#             screenshot, and the validation count when it quits
#
# Options:
#   --work-dir DIR          where everything goes (default: build-real-game)
#   --jobs N                parallel build jobs (default: 2)
#   --maps "A B C"          maps for the physics phase (default: ice-01 third-ice-20 wind-04: 35, 162 and 572 bodies)
#   --seconds S             simulated seconds per map (default: 60)
#   --binary-map NAME       map the binary starts on (default: ice-01)
#   --binary-seconds S      wall seconds the binary plays its map before the screenshot (default: 6; the player,
#                           idle, is caught by a pterodactyl on ice-01 after about 10 s)
#   --screenshot FILE       also copy the binary's screenshot to FILE (e.g. docs/images/real-game-caveexpress.png)
#   --quadphase-prefix DIR  use this installed prefix instead of installing one (implies --skip-prefixes for it)
#   --stock-prefix DIR      the same for the stock prefix
#   --skip-deps --skip-prefixes --skip-source --skip-build --skip-tests --skip-physics --skip-binary
#                           skip a phase (a skipped phase's outputs in WORK are used as they are)
# Relative paths are taken from the repository's root.
# Environment: QUADPHASE_BOX2D_SOURCE_DIR or QUADPHASE_BOX2D_TARBALL (Box2D 2.4.1's source, else fetched by CMake),
# QUADPHASE_SKIP_DEPS=1 (as --skip-deps).
# Exit status: 0 when every phase that ran passed its checks, 1 otherwise, 2 on bad arguments.
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
source "$(dirname "${BASH_SOURCE[0]}")/lib/caveexpress.sh"
root=$PWD

readonly caveexpress_version=2.5.2
readonly caveexpress_debian_version=2.5.2-1
readonly caveexpress_tarball=caveexpress_${caveexpress_version}.orig.tar.xz
readonly caveexpress_sha256=ae375d7fd7370863b57eb6700049d8236fc6ff17346e7137da655f90ab69e04c
readonly variants=(quadphase stock)

work=build-real-game
jobs=2
maps=(ice-01 third-ice-20 wind-04)
seconds=60
binary_map=ice-01
binary_seconds=6
screenshot_copy=""
declare -A prefix=()
declare -A skip=()

usage() { sed -n '2,/^source /{/^# SPDX-License-Identifier: MIT$/!p}' "$root/scripts/real-game.sh" | sed '$d; s/^# \{0,1\}//'; }
die() { echo "real-game: $*" >&2; exit 1; }
need_value() { [[ $# -ge 2 && -n "$2" ]] || { echo "real-game: $1 needs a value" >&2; exit 2; }; }
whole_number() { [[ "$2" =~ ^[1-9][0-9]*$ ]] || { echo "real-game: $1 must be a whole number > 0, got '$2'" >&2; exit 2; }; }

while [[ $# -gt 0 ]]; do
    case "$1" in
        --work-dir) need_value "$@"; work=$2; shift 2 ;;
        --jobs) need_value "$@"; whole_number "$1" "$2"; jobs=$2; shift 2 ;;
        --maps) need_value "$@"; read -r -a maps <<<"$2"; shift 2 ;;
        --seconds) need_value "$@"; whole_number "$1" "$2"; seconds=$2; shift 2 ;;
        --binary-map) need_value "$@"; binary_map=$2; shift 2 ;;
        --binary-seconds) need_value "$@"; whole_number "$1" "$2"; binary_seconds=$2; shift 2 ;;
        --screenshot) need_value "$@"; screenshot_copy=$2; shift 2 ;;
        --quadphase-prefix) need_value "$@"; prefix[quadphase]=$(cd "$2" && pwd); shift 2 ;;
        --stock-prefix) need_value "$@"; prefix[stock]=$(cd "$2" && pwd); shift 2 ;;
        --skip-deps | --skip-prefixes | --skip-source | --skip-build | --skip-tests | --skip-physics | --skip-binary)
            skip[${1#--skip-}]=1; shift ;;
        -h | --help) usage; exit 0 ;;
        *) echo "real-game: unknown argument '$1' (see --help)" >&2; exit 2 ;;
    esac
done
for map in "${maps[@]}" "$binary_map"; do
    [[ "$map" =~ ^[a-z0-9-]+$ ]] || { echo "real-game: bad map name '$map'" >&2; exit 2; }
done
[[ ${#maps[@]} -ge 1 ]] || { echo "real-game: --maps needs at least one map" >&2; exit 2; }

mkdir -p "$work"
work=$(cd "$work" && pwd)
for v in "${variants[@]}"; do
    : "${prefix[$v]:=$work/prefix-$v}"
done
game_src() { echo "$work/src-$1/caveexpress-$caveexpress_version"; }

# --- bookkeeping: phase times, results, failures ------------------------------------------------------------
script_start=$(date +%s)
declare -a phase_lines=()
declare -a failures=()
current_phase=""
phase_start=0
phase() {
    end_phase
    current_phase=$1
    phase_start=$(date +%s)
    echo
    echo "=== real-game: $1"
}
end_phase() {
    if [[ -n "$current_phase" ]]; then
        phase_lines+=("$(printf '%-9s %5d s' "$current_phase" $(($(date +%s) - phase_start)))")
        current_phase=""
    fi
}
fail() {
    echo "real-game: FAIL: $*" >&2
    failures+=("$*")
}
QP_JOBS=$jobs
QP_LOG=1 # qp_configure and qp_build: logs in their build directory, the tail on failure

# --- deps -------------------------------------------------------------------------------------------------------
if [[ -z "${skip[deps]:-}" ]]; then
    phase deps
    qp_deps scripts/install-deps.sh --for real-game
fi

# --- prefixes ---------------------------------------------------------------------------------------------------
if [[ -z "${skip[prefixes]:-}" && ( "${prefix[quadphase]}" == "$work/prefix-quadphase" ||
                                    "${prefix[stock]}" == "$work/prefix-stock" ) ]]; then
    phase prefixes
    qp_tree=$work/quadphase-build
    qp_configure "$qp_tree" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_TESTS=OFF -DQUADPHASE_BUILD_EXAMPLES=OFF \
        -DQUADPHASE_BUILD_BENCH=OFF
    qp_build "$qp_tree"
    if [[ "${prefix[quadphase]}" == "$work/prefix-quadphase" ]]; then
        rm -rf "${prefix[quadphase]}"
        cmake --install "$qp_tree" --prefix "${prefix[quadphase]}" >"$work/install-quadphase.log" ||
            die "cmake --install into ${prefix[quadphase]} failed (see $work/install-quadphase.log)"
    fi
    if [[ "${prefix[stock]}" == "$work/prefix-stock" ]]; then
        rm -rf "${prefix[stock]}"
        cmake --install "$qp_tree" --prefix "${prefix[stock]}" --component box2d_stock \
            >"$work/install-stock.log" ||
            die "cmake --install --component box2d_stock into ${prefix[stock]} failed (see $work/install-stock.log)"
    fi
fi
# Both prefixes must look like a Box2D 2.4.1 installation, and be what their names say: quadphase's library reads
# QUADPHASE_VALIDATE, stock's has no such string.
declare -A is_quadphase=()
for v in "${variants[@]}"; do
    p=${prefix[$v]}
    for f in lib/libbox2d.so.2 lib/pkgconfig/box2d.pc include/box2d/box2d.h include/box2d/b2_broad_phase.h; do
        [[ -e "$p/$f" ]] || die "$v prefix $p has no $f (run without --skip-prefixes, or give --$v-prefix)"
    done
    is_quadphase[$v]=no
    grep -q -a QUADPHASE_VALIDATE "$p/lib/libbox2d.so.2" && is_quadphase[$v]=yes
    echo "real-game: $v prefix $p: $(readlink -f "$p/lib/libbox2d.so.2"), soname" \
         "$(objdump -p "$p/lib/libbox2d.so.2" | awk '$1 == "SONAME" { print $2 }'), quadphase's: ${is_quadphase[$v]};" \
         "pkg-config box2d $(PKG_CONFIG_PATH=$p/lib/pkgconfig pkg-config --modversion box2d):" \
         "$(PKG_CONFIG_PATH=$p/lib/pkgconfig pkg-config --cflags --libs box2d)"
done
[[ ${is_quadphase[quadphase]} == yes ]] || die "${prefix[quadphase]}/lib/libbox2d.so.2 is not quadphase's"
[[ ${is_quadphase[stock]} == no ]] || die "${prefix[stock]}/lib/libbox2d.so.2 is not stock Box2D"

# --- source -----------------------------------------------------------------------------------------------------
if [[ -z "${skip[source]:-}" ]]; then
    phase source
    cmake -D PACKAGE=caveexpress -D VERSION=$caveexpress_debian_version -D FILE=$caveexpress_tarball \
          -D SHA256=$caveexpress_sha256 -D APT_ROOT="$work/apt" -P cmake/DebianSource.cmake \
          >"$work/source-fetch.log" 2>&1 ||
        { cat "$work/source-fetch.log" >&2; die "could not fetch Debian's caveexpress source package"; }
    grep -E 'SHA-256|404' "$work/source-fetch.log" | sed 's/^-- //; s/^/real-game: /' || true
    tarball=$work/apt/src/$caveexpress_tarball
    echo "real-game: $tarball sha256 $(sha256sum "$tarball" | cut -d' ' -f1)"
    fixes=$root/examples/real_game/system_libs.cmake
    stamp_text="$caveexpress_sha256 $(sha256sum "$fixes" | cut -d' ' -f1)"
    for v in "${variants[@]}"; do
        src=$(game_src "$v")
        stamp=$work/src-$v/.unpacked
        # One unpacked tree per build: the game writes its programs into its source root.
        if [[ ! -f "$stamp" || "$(cat "$stamp")" != "$stamp_text" ]]; then
            rm -rf "$work/src-$v" "$work/game-build-$v"
            mkdir -p "$work/src-$v"
            tar -C "$work/src-$v" -xf "$tarball"
            [[ ! -e "$src/src/libs" ]] || die "$src/src/libs exists: not the tarball this script knows"
            # Debian's build fix: the bundled libraries' directory is absent; the system's are used instead.
            mkdir -p "$src/src/libs"
            cp "$fixes" "$src/src/libs/CMakeLists.txt"
            echo "$stamp_text" >"$stamp"
            echo "real-game: unpacked into $src (src/libs/CMakeLists.txt from examples/real_game/system_libs.cmake)"
        else
            echo "real-game: $src already unpacked"
        fi
    done
fi

# --- build ------------------------------------------------------------------------------------------------------
programs=(caveexpress tests_caveexpress caveexpress-physics)
if [[ -z "${skip[build]:-}" ]]; then
    phase build
    for v in "${variants[@]}"; do
        p=${prefix[$v]}
        src=$(game_src "$v")
        b=$work/game-build-$v
        [[ -d "$src" ]] || die "$src missing (run without --skip-source)"
        echo "real-game: building CaveExpress against $v ($p) in $b, -j$jobs"
        start=$(date +%s)
        # Only the environment points the game at a prefix: PKG_CONFIG_PATH for its pkg_check_modules(box2d),
        # CMAKE_PREFIX_PATH for the find_path/find_library that follow it.
        PKG_CONFIG_PATH=$p/lib/pkgconfig CMAKE_PREFIX_PATH=$p \
            cmake -S "$src" -B "$b" -DCMAKE_BUILD_TYPE=Release -DCAVEPACKER=OFF \
                  "-DCMAKE_PROJECT_caveproductions_INCLUDE=$root/examples/real_game/physics_driver.cmake" \
                  >"$work/game-configure-$v.log" 2>&1 ||
            die "configuring CaveExpress against $v failed (see $work/game-configure-$v.log)"
        cmake --build "$b" -j "$jobs" --target "${programs[@]}" >"$work/game-build-$v.log" 2>&1 ||
            die "building CaveExpress against $v failed (see $work/game-build-$v.log)"
        echo "real-game: built in $(($(date +%s) - start)) s"
    done
fi
declare -A found_lib=()
for v in "${variants[@]}"; do
    p=${prefix[$v]}
    src=$(game_src "$v")
    b=$work/game-build-$v
    [[ -f "$b/CMakeCache.txt" ]] || die "$b not configured (run without --skip-build)"
    # What the game's find module found, from its own cache and configure log.
    inc=$(sed -n 's/^BOX2D_INCLUDE_DIRS:[A-Z]*=//p' "$b/CMakeCache.txt")
    lib=$(sed -n 's/^BOX2D_LIBRARIES:[A-Z]*=//p' "$b/CMakeCache.txt")
    found_lib[$v]=$lib
    echo "real-game: $v build: $(grep -m1 -- "--   Found box2d, version" "$work/game-configure-$v.log" |
         sed 's/^-- *//') (pkg-config); BOX2D_INCLUDE_DIRS=$inc BOX2D_LIBRARIES=$lib"
    [[ "$inc" == "$p/include/box2d" ]] || fail "$v build found Box2D's headers in '$inc', not $p/include/box2d"
    [[ "$lib" == "$p/lib/libbox2d.so" ]] || fail "$v build found Box2D's library '$lib', not $p/lib/libbox2d.so"
    # The game's own flags on its physics code: C++11 as it sets it, and this prefix's headers.
    flags=$b/src/modules/physics/CMakeFiles/physics.dir/flags.make
    grep -q -- '-std=c++11' "$flags" || fail "$v build: no -std=c++11 in $flags"
    grep -q -- "-I$p/include/box2d" "$flags" || fail "$v build: $flags does not include $p/include/box2d"
    echo "real-game: $v build: $(grep -o -- '-std=c++11' "$flags" | head -1), $(grep -o -- "-I$p/include/box2d" "$flags" | head -1)"
    for prog in "${programs[@]}"; do
        [[ -x "$src/$prog" ]] || { fail "$v build: $src/$prog missing"; continue; }
        loaded=$(ldd "$src/$prog" | awk '$1 == "libbox2d.so.2" { print $3 }')
        echo "real-game: $v build: ldd $prog: libbox2d.so.2 => $loaded"
        [[ "$(readlink -f "$loaded")" == "$(readlink -f "$p/lib/libbox2d.so.2")" ]] ||
            fail "$v build: $prog loads libbox2d.so.2 from '$loaded', not from $p/lib"
    done
done

# --- tests ------------------------------------------------------------------------------------------------------
declare -A tests_passed=() tests_failed=() tests_validation=()
if [[ -z "${skip[tests]:-}" ]]; then
    phase tests
    for v in "${variants[@]}"; do
        src=$(game_src "$v")
        log=$work/tests-$v.log
        rm -rf "$work/home-tests-$v" && mkdir -p "$work/home-tests-$v"
        validate=()
        [[ $v == quadphase ]] && validate=(QUADPHASE_VALIDATE=1)
        echo "real-game: tests_caveexpress on $v${validate[*]:+ (${validate[*]})}"
        status=0
        # googletest's lines on stdout, quadphase's reports on stderr: kept apart so that neither splits the other.
        (cd "$src" && env HOME="$work/home-tests-$v" "${validate[@]}" ./tests_caveexpress --gtest_color=no) \
            >"$log" 2>"$work/tests-$v.err" || status=$?
        # One line per test that finished: PASSED/FAILED and its name, sorted by name.
        sed -n 's/^\[       OK \] \([^ ]*\) (.*/PASSED \1/p; s/^\[  FAILED  \] \([^ ]*\) (.*/FAILED \1/p' "$log" |
            sort -k2 >"$work/tests-$v.txt"
        tests_passed[$v]=$(grep -c '^PASSED' "$work/tests-$v.txt" || true)
        tests_failed[$v]=$(grep -c '^FAILED' "$work/tests-$v.txt" || true)
        ran=$(sed -n 's/^\[==========\] \([0-9]*\) tests\{0,1\} from .* ran\..*/\1/p' "$log")
        echo "real-game: $v: exit status $status, ${ran:-?} tests ran, ${tests_passed[$v]} passed," \
             "${tests_failed[$v]} failed ($work/tests-$v.txt)"
        [[ -n "$ran" && "$ran" -eq $((tests_passed[$v] + tests_failed[$v])) ]] ||
            fail "$v: tests_caveexpress did not finish (${ran:-no} summary; see $log)"
        if [[ $v == quadphase ]]; then
            read -r mismatches checked <<<"$(qp_validation_counts "$work/tests-$v.err")"
            tests_validation[$v]="$mismatches mismatches, $checked UpdatePairs checked"
            [[ $mismatches -eq 0 ]] ||
                fail "quadphase: $mismatches validation mismatches in the tests (see $work/tests-$v.err)"
        fi
    done
    if diff -u "$work/tests-stock.txt" "$work/tests-quadphase.txt" >"$work/tests.diff"; then
        tests_same=yes
    else
        tests_same=no
        fail "the passed/failed lists differ (see $work/tests.diff)"
        cat "$work/tests.diff" >&2
    fi
fi

# --- physics ----------------------------------------------------------------------------------------------------
declare -A step_stock=() step_quadphase=() map_validation=() map_info=() map_frames=()
if [[ -z "${skip[physics]:-}" ]]; then
    phase physics
    for v in stock quadphase; do
        src=$(game_src "$v")
        out=$work/physics-$v.tsv
        echo "real-game: caveexpress-physics on $v: ${maps[*]}, $seconds s each"
        (cd "$src" && HOME="$work/home-physics" ./caveexpress-physics --seconds "$seconds" "${maps[@]}") \
            >"$out" 2>"$work/physics-$v.err" || fail "$v: caveexpress-physics failed (see $work/physics-$v.err)"
        while IFS=$'\t' read -r tag name steps simulated median p90 mean broadphase tick bodies contacts proxies \
                                 reloads bp_p99 bp_max bp_total step_p99 step_max step_total; do
            [[ "$tag" == map ]] || continue
            map_frames[$v:$name]="$bp_total $bp_max $bp_p99 $step_total $step_max"
            if [[ $v == stock ]]; then step_stock[$name]="$median ($p90)"; else step_quadphase[$name]="$median ($p90)"; fi
            map_info[$v:$name]="$steps steps ($simulated s), step median $median ms (p90 $p90, mean $mean), broadphase median"
            map_info[$v:$name]+=" $broadphase ms, game tick median $tick ms; at the end $bodies bodies,"
            map_info[$v:$name]+=" $contacts contacts, $proxies proxies; $reloads reloads; broadphase p99 $bp_p99 ms,"
            map_info[$v:$name]+=" worst $bp_max ms, total $bp_total ms; step p99 $step_p99 ms, worst $step_max ms,"
            map_info[$v:$name]+=" total $step_total ms"
            echo "real-game:   $v $name: ${map_info[$v:$name]}"
        done <"$out"
    done
    src=$(game_src quadphase)
    for map in "${maps[@]}"; do
        err=$work/physics-validate-$map.err
        (cd "$src" && HOME="$work/home-physics" QUADPHASE_VALIDATE=1 \
            ./caveexpress-physics --seconds "$seconds" "$map") >"$work/physics-validate-$map.tsv" 2>"$err" ||
            fail "quadphase: caveexpress-physics $map with QUADPHASE_VALIDATE=1 failed (see $err)"
        read -r mismatches checked <<<"$(qp_validation_counts "$err")"
        map_validation[$map]="$mismatches mismatches, $checked UpdatePairs checked"
        echo "real-game:   quadphase $map, QUADPHASE_VALIDATE=1: ${map_validation[$map]}"
        [[ $mismatches -eq 0 ]] || fail "quadphase: $mismatches validation mismatches on $map (see $err)"
        [[ "$checked" != 0 ]] || fail "quadphase: validation checked no UpdatePairs on $map"
    done
fi

# --- binary -----------------------------------------------------------------------------------------------------
maps_line="" binary_validation="" binary_status="" screenshot=""
if [[ -z "${skip[binary]:-}" ]]; then
    phase binary
    game=$QP_GAME
    [[ -x "$game" ]] || die "$game missing: Debian's package caveexpress (scripts/install-deps.sh --for real-game)"
    echo "real-game: $(dpkg-query -W -f='${Package} ${Version}' caveexpress), as installed: ldd $game:" \
         "$(ldd "$game" | grep libbox2d)"
    for cmd in Xvfb import; do
        command -v "$cmd" >/dev/null || die "$cmd not found (scripts/install-deps.sh --for real-game)"
    done
    trap qp_x_cleanup EXIT
    qp_xvfb_start "$work/binary-xvfb.log" || die "Xvfb did not start (see $work/binary-xvfb.log)"
    rm -rf "$work/home-binary" && mkdir -p "$work/home-binary"
    log=$work/binary.log
    echo "real-game: LD_LIBRARY_PATH=${prefix[quadphase]}/lib QUADPHASE_VALIDATE=1 $game -map $binary_map" \
         "(Xvfb $QP_DISPLAY)"
    qp_game_start "$log" "$work/home-binary" "$binary_map" LD_LIBRARY_PATH="${prefix[quadphase]}/lib" \
        QUADPHASE_VALIDATE=1 || fail "no map started in the binary within 60 s (see $log)"
    sleep "$binary_seconds"
    if kill -0 "$QP_GAME_PID" 2>/dev/null; then
        maps_line=$(qp_game_maps_line)
        echo "real-game: /proc/$QP_GAME_PID/maps: $maps_line"
        [[ "$maps_line" == *"$(readlink -f "${prefix[quadphase]}/lib/libbox2d.so.2")" ]] ||
            fail "the binary did not load quadphase's libbox2d.so.2 (maps: '$maps_line')"
        ! grep -q "trigger map restart" "$log" || fail "the level ended before the screenshot (see $log)"
        screenshot=$work/binary-$binary_map.png
        DISPLAY="$QP_DISPLAY" import -window root "$screenshot"
        colours=$(identify -format '%k' "$screenshot")
        echo "real-game: screenshot $screenshot ($colours colours)"
        [[ $colours -gt 1000 ]] || fail "the screenshot has $colours colours: no level drawn?"
        if [[ -n "$screenshot_copy" ]]; then
            mkdir -p "$(dirname "$screenshot_copy")"
            cp "$screenshot" "$screenshot_copy"
            echo "real-game: copied to $screenshot_copy"
        fi
        qp_game_stop
        binary_status=$QP_GAME_STATUS
        # Debian's caveexpress aborts in its own exit handlers (std::bad_alloc, status 134) on Debian's libbox2d
        # too; that is the game's and is reported, not failed.
        echo "real-game: the binary exited with status $binary_status"
    else
        qp_game_stop
        binary_status=$QP_GAME_STATUS
        fail "the binary exited (status $binary_status) before the screenshot (see $log)"
    fi
    read -r mismatches checked <<<"$(qp_validation_counts "$log")"
    binary_validation="$mismatches mismatches, $checked UpdatePairs checked"
    echo "real-game: binary validation: $binary_validation"
    [[ $mismatches -eq 0 ]] || fail "the binary reported $mismatches validation mismatches (see $log)"
    qp_x_cleanup
    trap - EXIT
fi
end_phase

# --- summary ----------------------------------------------------------------------------------------------------
echo
echo "=== real-game: summary (work dir $work)"
for line in "${phase_lines[@]}"; do echo "  time  $line"; done
echo "  time  total     $(printf '%5d' $(($(date +%s) - script_start))) s"
for v in "${variants[@]}"; do
    echo "  box2d $v: ${prefix[$v]} (quadphase's: ${is_quadphase[$v]}); the game's build found ${found_lib[$v]}"
done
if [[ -z "${skip[tests]:-}" ]]; then
    for v in "${variants[@]}"; do
        echo "  tests $v: ${tests_passed[$v]} passed, ${tests_failed[$v]} failed${tests_validation[$v]:+; validation: ${tests_validation[$v]}}"
        sed 's/^/          /' "$work/tests-$v.txt"
    done
    echo "  tests lists identical: $tests_same"
fi
if [[ -z "${skip[physics]:-}" ]]; then
    printf '  physics %-14s %20s %20s  %s\n' map "stock ms/step" "quadphase ms/step" "quadphase, QUADPHASE_VALIDATE=1"
    for map in "${maps[@]}"; do
        printf '  physics %-14s %20s %20s  %s\n' "$map" "${step_stock[$map]:-?}" "${step_quadphase[$map]:-?}" \
               "${map_validation[$map]:-?}"
    done
    echo "  physics: median (90th percentile) of b2Profile::step over ${seconds} simulated seconds per map, 60 steps"
    echo "           per second; one run each on a shared machine: rerun to compare"
    printf '  frames  %-14s %24s %24s %24s\n' map "bp total stock/quadphase" "bp worst stock/quadphase" \
           "step total stock/quadph."
    for map in "${maps[@]}"; do
        read -r st_total st_max _ st_step _ <<<"${map_frames[stock:$map]:-? ? ? ? ?}"
        read -r qp_total qp_max _ qp_step _ <<<"${map_frames[quadphase:$map]:-? ? ? ? ?}"
        printf '  frames  %-14s %24s %24s %24s\n' "$map" "$st_total / $qp_total" "$st_max / $qp_max" \
               "$st_step / $qp_step"
    done
    echo "  frames: b2Profile::broadphase and ::step in ms, summed over the run (total) and the largest single step"
    echo "          (worst), at the library's defaults (no environment variable, every core)"
fi
if [[ -z "${skip[binary]:-}" ]]; then
    echo "  binary maps line: ${maps_line:-none}"
    echo "  binary validation: $binary_validation; exit status $binary_status; screenshot ${screenshot:-none}"
fi
if [[ ${#failures[@]} -gt 0 ]]; then
    echo "  FAILED (${#failures[@]}):"
    printf '    %s\n' "${failures[@]}"
    exit 1
fi
echo "  all checks passed"
