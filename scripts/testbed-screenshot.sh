#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Start Box2D 2.4.1's testbed, built against quadphase (-DQUADPHASE_TESTBED=ON), on a virtual X server (Xvfb)
# with Mesa's software OpenGL (llvmpipe), open one sample, let it run, and save a screenshot (ffmpeg x11grab).
#
#   scripts/testbed-screenshot.sh                          # "Tiles" -> $OUT_DIR/testbed-tiles-quadtree.png
#   scripts/testbed-screenshot.sh "Add Pair" "Tumbler"     # one screenshot per sample
#   scripts/testbed-screenshot.sh --list                   # the samples, in the testbed's order
#   BROADPHASE=stock scripts/testbed-screenshot.sh Tiles   # the same testbed on Box2D's b2DynamicTree
#   XDOTOOL="mousemove 40 137 click 1 mousemove 40 183 click 1" scripts/testbed-screenshot.sh "Ray Cast"
#                                                          # click the sample's buttons first (here: add shapes)
#
# A sample is picked by writing its index into settings.ini in a scratch working directory (the testbed reads
# its current sample from there). The testbed runs for SECONDS wall seconds before the screenshot; under
# llvmpipe on a small machine that is a few hundred steps. The testbed's console output is kept next to each
# screenshot (.log). The script exits non-zero when the testbed does not start or dies before the screenshot.
#
# Environment:
#   OUT_DIR                     screenshots (default: $BUILD_DIR/testbed-screenshots)
#   SECONDS_BEFORE_SHOT         wall seconds to let the sample run (default 20)
#   SIZE                        screen size WxH (default 1280x800)
#   XDOTOOL                     an xdotool command chain run 2 s after the start (mouse clicks on the samples'
#                               buttons, keys such as "key z" to zoom out); see xdotool(1)
#   BROADPHASE                  quadtree (default) or stock
#   QUADPHASE_SKIP_DEPS=1       do not run scripts/install-deps.sh
#   QUADPHASE_SKIP_BUILD=1      do not configure/build (use the testbed already in BUILD_DIR)
#   BUILD_DIR                   build directory (default: build-testbed)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
root=$PWD

build_dir=${BUILD_DIR:-build-testbed}
out_dir=${OUT_DIR:-$build_dir/testbed-screenshots}
wait_seconds=${SECONDS_BEFORE_SHOT:-20}
screen=${SIZE:-1280x800}
broadphase=${BROADPHASE:-quadtree}
case "$broadphase" in
    quadtree) target=quadphase-testbed ;;
    stock) target=quadphase-testbed-stock ;;
    *) echo "testbed-screenshot: BROADPHASE must be quadtree or stock, got '$broadphase'" >&2; exit 2 ;;
esac
if [[ ! "$screen" =~ ^[0-9]+x[0-9]+$ ]]; then
    echo "testbed-screenshot: SIZE must be WIDTHxHEIGHT, got '$screen'" >&2
    exit 2
fi
if [[ ! "$wait_seconds" =~ ^[0-9]+$ ]]; then
    echo "testbed-screenshot: SECONDS_BEFORE_SHOT must be a whole number, got '$wait_seconds'" >&2
    exit 2
fi

qp_deps scripts/install-deps.sh --for testbed
if [[ "${QUADPHASE_SKIP_BUILD:-0}" != 1 ]]; then
    qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_TESTBED=ON -DQUADPHASE_BUILD_EXAMPLES=ON
    qp_build "$build_dir" "$target"
fi
testbed="$root/$build_dir/examples/testbed/$target"
[[ "$build_dir" = /* ]] && testbed="$build_dir/examples/testbed/$target"
if [[ ! -x "$testbed" ]]; then
    echo "testbed-screenshot: $testbed not found (build with -DQUADPHASE_TESTBED=ON)" >&2
    exit 1
fi
testbed_dir=$(dirname "$testbed")

# The samples in the testbed's order: RegisterTest("Category", "Name", ...) in testbed/tests/*.cpp, sorted by
# category then name with strcmp (main.cpp's CompareTests), i.e. byte order.
box2d_src=$(sed -n 's/^QUADPHASE_BOX2D_SRC:INTERNAL=//p' "$(dirname "$testbed_dir")/../CMakeCache.txt" 2>/dev/null || true)
if [[ -z "$box2d_src" || ! -d "$box2d_src/testbed/tests" ]]; then
    echo "testbed-screenshot: cannot find Box2D's testbed sources (QUADPHASE_BOX2D_SRC in $build_dir/CMakeCache.txt)" >&2
    exit 1
fi
samples=$(grep -ho 'RegisterTest("[^"]*", *"[^"]*"' "$box2d_src"/testbed/tests/*.cpp |
          sed 's/RegisterTest("\([^"]*\)", *"\([^"]*\)"/\1\t\2/' | LC_ALL=C sort -t $'\t' -k1,1 -k2,2)

if [[ "${1:-}" == "--list" ]]; then
    echo "$samples" | awk -F'\t' '{ printf "%2d  %-12s %s\n", NR - 1, $1, $2 }'
    exit 0
fi
names=("$@")
[[ ${#names[@]} -eq 0 ]] && names=("Tiles")

needed=(Xvfb ffmpeg)
[[ -n "${XDOTOOL:-}" ]] && needed+=(xdotool)
for cmd in "${needed[@]}"; do
    command -v "$cmd" >/dev/null || { echo "testbed-screenshot: $cmd not found (scripts/install-deps.sh --for testbed)" >&2; exit 1; }
done
mkdir -p "$out_dir"
out_dir=$(cd "$out_dir" && pwd)

# One virtual X server for all screenshots; a free display number.
display=99
while [[ -e /tmp/.X11-unix/X$display || -e /tmp/.X$display-lock ]]; do display=$((display + 1)); done
Xvfb ":$display" -screen 0 "${screen}x24" -nolisten tcp >"$out_dir/xvfb.log" 2>&1 &
xvfb_pid=$!
work=$(mktemp -d)
testbed_pid=""
cleanup() {
    [[ -n "$testbed_pid" ]] && kill "$testbed_pid" 2>/dev/null || true
    kill "$xvfb_pid" 2>/dev/null || true
    rm -rf "$work"
}
trap cleanup EXIT
for _ in $(seq 50); do
    [[ -e /tmp/.X11-unix/X$display ]] && break
    sleep 0.1
done
[[ -e /tmp/.X11-unix/X$display ]] || { echo "testbed-screenshot: Xvfb did not start (see $out_dir/xvfb.log)" >&2; exit 1; }

width=${screen%x*}
height=${screen#*x}
status=0
for name in "${names[@]}"; do
    index=$(echo "$samples" | awk -F'\t' -v n="$name" '$2 == n { print NR - 1; exit }')
    if [[ -z "$index" ]]; then
        echo "testbed-screenshot: no sample named '$name' (see --list)" >&2
        status=2
        continue
    fi
    slug=$(echo "$name" | tr 'A-Z ' 'a-z-')
    shot="$out_dir/testbed-$slug-$broadphase.png"
    log="${shot%.png}.log"
    # A scratch working directory: settings.ini selects the sample and the window size (Box2D 2.4.1's
    # Settings::Load reads only testIndex, the window size and a few solver fields); data/ holds the font.
    rm -rf "$work/run" && mkdir -p "$work/run" && cp -r "$testbed_dir/data" "$work/run/"
    cat >"$work/run/settings.ini" <<INI
{
  "testIndex": $index,
  "windowWidth": $width,
  "windowHeight": $height
}
INI
    echo "testbed-screenshot: sample $index '$name' on $broadphase, ${wait_seconds}s under Xvfb :$display" >&2
    (cd "$work/run" && DISPLAY=":$display" LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe exec "$testbed") \
        >"$log" 2>&1 &
    testbed_pid=$!
    if [[ -n "${XDOTOOL:-}" ]]; then
        sleep 2
        # shellcheck disable=SC2086 # one argument per word of the command chain
        DISPLAY=":$display" xdotool ${XDOTOOL} || echo "testbed-screenshot: xdotool failed" >&2
    fi
    sleep "$wait_seconds"
    if ! kill -0 "$testbed_pid" 2>/dev/null; then
        wait "$testbed_pid" || true
        echo "testbed-screenshot: the testbed exited before the screenshot; its output ($log):" >&2
        cat "$log" >&2
        testbed_pid=""
        status=1
        continue
    fi
    ffmpeg -hide_banner -loglevel error -y -f x11grab -video_size "$screen" -i ":$display" -frames:v 1 "$shot"
    kill "$testbed_pid" 2>/dev/null || true
    wait "$testbed_pid" 2>/dev/null || true
    testbed_pid=""
    echo "testbed-screenshot: wrote $shot" >&2
done
exit $status
