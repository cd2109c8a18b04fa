#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Render a scene to PNG frames and an animation: install dependencies (scripts/install-deps.sh), configure + build
# (Release) quadphase-scene and its two worker programs, then run it.
#
#   scripts/render.sh                        # rain, 3000 bodies, 300 steps: build/render/frames/*.png,
#                                            # build/render/animation.gif and build/render/animation.mp4
#   scripts/render.sh --scene shooter --size 400 --steps 600 --every 4
#   scripts/render.sh --scene mixed --broadphase stock     # the same scene with Box2D's b2DynamicTree
#   scripts/render.sh --scene churn --png out/churn --gif out/churn.gif   # your own outputs
#   scripts/render.sh --help                 # every option of quadphase-scene, and the scenes
#
# The arguments are quadphase-scene's (see --help). Unless you give --png, --gif or --mp4 yourself, the script
# adds --png $OUT_DIR/frames --gif $OUT_DIR/animation.gif --mp4 $OUT_DIR/animation.mp4 and clears old frames
# first. Without any argument it renders --scene rain --size 3000 --steps 300 --every 5.
#
# Environment:
#   OUT_DIR                     where the default outputs go (default: $BUILD_DIR/render)
#   QUADPHASE_SKIP_DEPS=1       do not run scripts/install-deps.sh
#   BUILD_DIR                   build directory (default: build)
#   JOBS                        parallel build jobs (default: nproc)
#   QUADPHASE_BOX2D_SOURCE_DIR  unpacked Box2D 2.4.1 source (default: fetched by CMake)
#   QUADPHASE_BOX2D_TARBALL     local box2d_2.4.1.orig.tar.gz (default: fetched by CMake)
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for render
build_dir=${BUILD_DIR:-build}
out_dir=${OUT_DIR:-$build_dir/render}
qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release -DQUADPHASE_BUILD_EXAMPLES=ON
qp_build "$build_dir" quadphase-scene quadphase-scene-quadtree quadphase-scene-stock
scene=$(qp_exe "$build_dir/examples/scene_cli/quadphase-scene")

args=("$@")
if [[ ${#args[@]} -eq 0 ]]; then
    args=(--scene rain --size 3000 --steps 300 --every 5)
fi
own_outputs=0
for arg in "${args[@]}"; do
    case "$arg" in
        --png|--png=*|--gif|--gif=*|--mp4|--mp4=*|--help|-h) own_outputs=1 ;;
    esac
done
if [[ $own_outputs == 0 ]]; then
    mkdir -p "$out_dir/frames"
    rm -f "$out_dir"/frames/frame_*.png "$out_dir/animation.gif" "$out_dir/animation.mp4"
    args+=(--png "$out_dir/frames" --gif "$out_dir/animation.gif" --mp4 "$out_dir/animation.mp4")
fi
exec "$scene" "${args[@]}"
