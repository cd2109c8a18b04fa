#!/usr/bin/env bash
# Install what bench/ needs on Debian/Ubuntu: the build tools, python3 with matplotlib (the figure), and what
# CMake needs to fetch Box2D's source. Idempotent: does nothing (and no `apt-get update`) when all are installed.
# Runs as root, or through sudo when available.
set -euo pipefail

packages=(
    cmake
    g++
    make
    python3
    python3-matplotlib      # bench/parallel.py draws bench/results/parallel.png
    ca-certificates
    xz-utils
    debian-archive-keyring  # verifies the Debian archive when CMake fetches Box2D's source
)

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
    echo "bench/install-deps: this script needs apt-get/dpkg (Debian or Ubuntu)." >&2
    echo "bench/install-deps: install by hand: ${packages[*]}" >&2
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
    echo "bench/install-deps: all packages already installed"
    exit 0
fi

if [[ $(id -u) -eq 0 ]]; then
    as_root=()
elif command -v sudo >/dev/null 2>&1; then
    as_root=(sudo)
else
    echo "bench/install-deps: missing packages (${missing[*]}) and not root; sudo is not available." >&2
    exit 1
fi

export DEBIAN_FRONTEND=noninteractive
echo "bench/install-deps: missing: ${missing[*]}"
"${as_root[@]}" apt-get update
"${as_root[@]}" apt-get install -y --no-install-recommends "${missing[@]}"
echo "bench/install-deps: done"
