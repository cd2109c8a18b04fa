#!/usr/bin/env bash
# Configure + build (Release) and run the quadphase demo: scripts/demo.sh [demo args...]
# Environment: BUILD_DIR (default: build), JOBS (default: nproc).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
demo="$build_dir/examples/quadphase-demo"

if [[ ! -f examples/CMakeLists.txt ]]; then
    echo "demo: examples/CMakeLists.txt does not exist yet, so there is no quadphase-demo to run." >&2
    exit 1
fi

cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_EXAMPLES=ON >&2
if ! cmake --build "$build_dir" -j "$jobs" --target quadphase-demo >&2; then
    echo "demo: building the quadphase-demo target failed (see above)." >&2
    exit 1
fi

if [[ ! -x "$demo" ]]; then
    echo "demo: $demo does not exist after the build." >&2
    exit 1
fi
exec "$demo" "$@"
