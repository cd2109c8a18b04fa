#!/usr/bin/env bash
# Side-by-side demo: install dependencies (scripts/install-deps.sh), configure + build (Release) the demo and
# its two worker programs, then run build/examples/demo/quadphase-demo with the given arguments.
#
#   scripts/demo.sh                                  # rain, 16000 bodies, 300 steps
#   scripts/demo.sh --scene particles --size 20000 --repeat 3
#   scripts/demo.sh --help                           # all options and scenes
#
# Environment:
#   QUADPHASE_SKIP_DEPS=1       do not run scripts/install-deps.sh
#   BUILD_DIR                   build directory (default: build)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
set -euo pipefail

cd "$(dirname "${BASH_SOURCE[0]}")/.."

# Dependencies first (a no-op when everything is installed).
if [[ "${QUADPHASE_SKIP_DEPS:-0}" != 1 ]]; then
    scripts/install-deps.sh --for demo >&2
fi

build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}

configure_args=(-S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_EXAMPLES=ON)
if [[ -n "${QUADPHASE_BOX2D_SOURCE_DIR:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_SOURCE_DIR=$QUADPHASE_BOX2D_SOURCE_DIR")
fi
if [[ -n "${QUADPHASE_BOX2D_TARBALL:-}" ]]; then
    configure_args+=("-DQUADPHASE_BOX2D_TARBALL=$QUADPHASE_BOX2D_TARBALL")
fi

# Configure (cheap when already configured; keeps the build Release with the examples on).
if ! cmake "${configure_args[@]}" >&2; then
    echo "demo: configuring $build_dir failed (see above)." >&2
    exit 1
fi
if ! cmake --build "$build_dir" -j "$jobs" \
        --target quadphase-demo-stock quadphase-demo-quadtree quadphase-demo >&2; then
    echo "demo: building quadphase-demo and its worker programs failed (see above)." >&2
    exit 1
fi

# Single-config generators put it in examples/demo/; multi-config ones in examples/demo/Release/.
demo=""
for candidate in "$build_dir/examples/demo/quadphase-demo" "$build_dir/examples/demo/Release/quadphase-demo"; do
    if [[ -x "$candidate" ]]; then
        demo=$candidate
        break
    fi
done
if [[ -z "$demo" ]]; then
    echo "demo: quadphase-demo not found under $build_dir/examples/demo after the build." >&2
    exit 1
fi
status=0
"$demo" "$@" || status=$?
cat >&2 <<'MSG'

demo: this was one scene. The benchmark (issue 4) steps every scene in both builds, replays identical broadphase
demo: traces through stock, quadphase, brute force, the paper's design, Chipmunk2D and Bullet, and runs the paper's
demo: 20 ms protocol:  bench/run.sh  (quick profile, under 5 minutes; --full for the committed bench/RESULTS.md)
MSG
exit "$status"
