#!/usr/bin/env bash
# Install the build/test dependencies of quadphase on Debian/Ubuntu.
# Idempotent: does nothing (and no `apt-get update`) when everything is installed.
# Extra package names given as arguments are installed too (bench/install-deps.sh adds matplotlib).
# Runs as root, or through sudo when available.
set -euo pipefail

packages=(
    cmake
    g++
    make
    catch2                  # Catch2 2.x (find_package(Catch2 2))
    libomp-dev              # LLVM OpenMP, for clang builds (gcc uses libgomp)
    clang-14                # race checker (scripts/race-check.sh) and sanitizer builds
    libomp-14-dev           # libomp and archer (OpenMP support of ThreadSanitizer) for clang-14
    libclang-rt-14-dev      # clang-14's sanitizer runtimes
    ca-certificates
    python3
    pkg-config              # tests/package: a game finding Box2D through pkg-config box2d
    xz-utils
    debian-archive-keyring  # verifies the Debian archive when CMake fetches Box2D's source
    libcairo2-dev fonts-dejavu-core  # PNG frames of quadphase-scene (examples/scene_cli) and their text
    ffmpeg                  # GIF/MP4 animations of quadphase-scene; screenshots of the testbed (x11grab)
    libgl-dev libx11-dev libxrandr-dev libxinerama-dev libxcursor-dev libxi-dev  # Box2D testbed's glfw (-DQUADPHASE_TESTBED=ON)
    xvfb xauth libgl1-mesa-dri xdotool  # scripts/testbed-screenshot.sh: virtual X server, Mesa software GL, key presses
    libchipmunk-dev libbullet-dev  # bench/: Chipmunk2D's spatial hash and BB tree, Bullet's btDbvtBroadphase (replay comparison)
    "$@"
)

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
    echo "install-deps: all packages already installed: ${packages[*]}"
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
echo "install-deps: missing: ${missing[*]}"
echo "install-deps: running: ${as_root[*]:+${as_root[*]} }apt-get update"
"${as_root[@]}" apt-get update
echo "install-deps: running: ${as_root[*]:+${as_root[*]} }apt-get install -y --no-install-recommends ${missing[*]}"
"${as_root[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
echo "install-deps: done"
