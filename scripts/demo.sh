#!/usr/bin/env bash
# Install dependencies (scripts/install-deps.sh), configure + build (Release) and run
# the quadphase demo: scripts/demo.sh [demo args...]
# Environment: BUILD_DIR (default: build), JOBS (default: nproc),
#              QUADPHASE_SKIP_DEPS=1 (do not run scripts/install-deps.sh).
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Dependencies first (a no-op when everything is installed).
if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    scripts/install-deps.sh >&2
fi

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
    # Not at the usual place (e.g. built in examples/demo/): look for it.
    found=$(find "$build_dir/examples" -type f -name quadphase-demo -perm -u+x 2>/dev/null | head -n 1)
    if [[ -z "$found" ]]; then
        echo "demo: $demo does not exist after the build." >&2
        exit 1
    fi
    demo=$found
fi
exec "$demo" "$@"
