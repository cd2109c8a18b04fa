#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install the Debian/Ubuntu packages a command of this repository needs, and nothing else.
#
#   scripts/install-deps.sh                       # every purpose but real-game, deb-check, no-openmp and web: what CI
#                                                 # (.ci/run) and the scripts in scripts/ and bench/ use together
#   scripts/install-deps.sh --for test            # one purpose (repeat --for for several)
#   scripts/install-deps.sh --for bench python3-matplotlib   # extra package names are installed too
#   scripts/install-deps.sh --list [--for PURPOSE]           # print the packages, install nothing
#
# Purposes (each includes "core": compiler, ccache, CMake, Catch2, cairo, and what fetches Box2D's source):
#   test         scripts/test.sh: + ffmpeg (configuring the project builds the tests, which need Catch2, and
#                quadphase-scene, which needs cairo; its tests write a GIF and an MP4 through ffmpeg), abigail-tools
#                (tests/abi compares libbox2d.so.2's ABI with stock's by abidiff)
#   demo         scripts/demo.sh: + python3 (the demo runs the bench tools through support/tools/python)
#   render       scripts/render.sh: + ffmpeg (GIF/MP4)
#   testbed      scripts/testbed-screenshot.sh: + X11/GL dev packages for Box2D's testbed, Xvfb, Mesa, xdotool, ffmpeg
#   bench        bench/*.sh, scripts/soak.sh: + Chipmunk2D, Bullet, python3
#   race         scripts/race-check.sh: + clang-14 with LLVM's libomp and archer
#   no-openmp    scripts/test-no-openmp.sh: + clang-14 and LLVM's libc++ (Apple's toolchain without OpenMP), ffmpeg
#                and abigail-tools as test
#   web          scripts/test-web.sh: + Emscripten and Node.js (the tests run under node)
#   sanitize     scripts/sanitize.sh: + ffmpeg and abigail-tools, as test (the same suite under GCC's sanitizers)
#   fuzz         scripts/fuzz.sh: + clang-14's libFuzzer and sanitizer runtimes, libomp
#   real-game    scripts/real-game.sh: + CaveExpress's build dependencies, Debian's caveexpress package, Xvfb,
#                Mesa, xdotool, imagemagick
#   deb          scripts/deb.sh: + debhelper, dpkg-dev, lintian (Debian packages of quadphase's libbox2d)
#   deb-check    scripts/deb-check.sh: + Xvfb, Mesa (its round trip installs and removes caveexpress itself)
#   arm64        scripts/test-arm64.sh: + Debian's aarch64 cross g++ (with its libstdc++, libgomp and glibc), qemu-user to
#                run the tests, abigail-tools (tests/abi's abidiff)
#   windows      scripts/test-windows.sh: + MinGW-w64's g++ (POSIX threads flavour: std::thread, OpenMP), Wine (64-bit)
#                to run the tests
# Idempotent: does nothing (and no `apt-get update`) when everything is installed. Runs as root, or through sudo.
set -euo pipefail

core=(
    cmake g++ make
    catch2                  # Catch2 2.x (find_package(Catch2 2))
    libcli11-dev            # command lines of the tools (support/tools, find_package(CLI11))
    nlohmann-json3-dev      # JSON of the tools (support/tools, find_package(nlohmann_json 3))
    libcairo2-dev fonts-dejavu-core  # quadphase-scene (examples/scene_cli): PNG frames and their text
    pkg-config              # cairo; tests/package: a game finding Box2D through pkg-config box2d
    ca-certificates xz-utils
    debian-archive-keyring  # verifies the Debian archive when CMake fetches Box2D's source
    ccache                  # every build compiles through it (scripts/lib/build.sh)
)
clang_omp=(
    clang-14                # race checker and fuzzer
    libomp-dev libomp-14-dev  # LLVM's libomp and archer (OpenMP support of ThreadSanitizer) for clang-14
)
xvfb=(xvfb xauth libgl1-mesa-dri xdotool)  # virtual X server, Mesa software GL, key presses and clicks

packages_for() {
    case "$1" in
        demo) echo python3 ;;
        test | sanitize) echo ffmpeg abigail-tools ;;  # tests/scene_cli writes a GIF and an MP4; tests/abi: abidiff
        render) echo ffmpeg ;;
        testbed)
            echo libgl-dev libx11-dev libxrandr-dev libxinerama-dev libxcursor-dev libxi-dev  # the testbed's glfw
            echo "${xvfb[@]}" ffmpeg  # screenshots (x11grab)
            ;;
        bench) echo libchipmunk-dev libbullet-dev python3 ;;  # replay comparison; the drivers are Python
        race) echo "${clang_omp[@]}" ;;
        no-openmp) echo clang-14 libc++-14-dev libc++abi-14-dev ffmpeg abigail-tools ;;
        web) echo emscripten nodejs ;;
        fuzz) echo "${clang_omp[@]}" libclang-rt-14-dev ;;
        real-game)
            # CaveExpress 2.5.2's build dependencies as Debian's source package lists them (caveexpress_2.5.2-1.dsc),
            # less libbox2d-dev (the game is built against quadphase's and stock's prefixes) and liblua5.2-dev
            # (Debian's game links Lua 5.4), plus the game itself for the binary swap.
            echo libglm-dev libgtest-dev liblua5.4-dev libncurses-dev libsdl2-dev libsdl2-image-dev \
                libsdl2-mixer-dev libsdl2-net-dev libsqlite3-dev libtinyxml2-dev libyajl-dev zlib1g-dev
            echo caveexpress "${xvfb[@]}" imagemagick
            ;;
        deb) echo debhelper dpkg-dev lintian ;;
        deb-check) echo "${xvfb[@]}" ;;
        arm64) echo g++-aarch64-linux-gnu qemu-user abigail-tools ;;
        windows) echo g++-mingw-w64-x86-64-posix wine wine64 ;;
        *) return 1 ;;
    esac
}
all_purposes=(test demo render testbed bench race sanitize fuzz deb arm64 windows)

usage() {
    sed -n '2,/^set -euo/{/^# SPDX-License-Identifier: MIT$/!p}' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'
}

purposes=()
extra=()
list_only=0
while [[ $# -gt 0 ]]; do
    case "$1" in
        --for)
            [[ $# -ge 2 ]] || { echo "install-deps: --for needs a purpose" >&2; exit 2; }
            packages_for "$2" >/dev/null || {
                echo "install-deps: unknown purpose '$2' (one of: ${all_purposes[*]} real-game deb-check no-openmp web)" >&2
                exit 2
            }
            purposes+=("$2")
            shift 2
            ;;
        --for=*)
            set -- --for "${1#--for=}" "${@:2}"
            ;;
        --list) list_only=1; shift ;;
        -h | --help) usage; exit 0 ;;
        -*) echo "install-deps: unknown option '$1' (see --help)" >&2; exit 2 ;;
        *) extra+=("$1"); shift ;;
    esac
done
[[ ${#purposes[@]} -eq 0 ]] && purposes=("${all_purposes[@]}")

packages=("${core[@]}")
for purpose in "${purposes[@]}"; do
    read -r -a more <<<"$(packages_for "$purpose" | tr '\n' ' ')"
    packages+=("${more[@]}")
done
packages+=("${extra[@]}")
# Each package once, in first-seen order.
mapfile -t packages < <(printf '%s\n' "${packages[@]}" | awk 'NF && !seen[$0]++')

if [[ $list_only -eq 1 ]]; then
    printf '%s\n' "${packages[@]}"
    exit 0
fi

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "install-deps: this script needs apt-get/dpkg (Debian or Ubuntu)." >&2
    echo "install-deps: install by hand: ${packages[*]}" >&2
    exit 1
fi

missing=()
for pkg in "${packages[@]}"; do
    status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
    if [[ "$status" != *"install ok installed"* ]]; then
        missing+=("$pkg")
    fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
    echo "install-deps: all packages for ${purposes[*]} already installed (${#packages[@]})"
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    as_root=()
elif command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
else
    echo "install-deps: missing packages (${missing[*]}) and not root; sudo is not available." >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
echo "install-deps: for ${purposes[*]}, missing: ${missing[*]}"
echo "install-deps: running: ${as_root[*]:+${as_root[*]} }apt-get update"
"${as_root[@]}" apt-get update
echo "install-deps: running: ${as_root[*]:+${as_root[*]} }apt-get install -y --no-install-recommends ${missing[*]}"
"${as_root[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
echo "install-deps: done"
