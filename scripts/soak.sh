#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Soak run: 100,000 steps of a churn world (bodies created and destroyed every step) with the quadphase build,
# printing resident memory (VmRSS, VmHWM) at the start, every INTERVAL steps and at the end (qp-step's --interval,
# bench/src/step_bench.cpp: the steps run as its untimed warm-up, and one timed step ends the run).
# Not run by CI (a few minutes on 2 cores). Figures: docs/robustness.md.
#
# Exit status: non-zero when resident memory at the end exceeds the post-warm-up figure by more than 10%, or when
# validation (VALIDATE=1) finds a mismatch.
# Environment: STEPS (default 100000), SIZE (default 250 bodies), INTERVAL (default 10000), SEED (default 1),
#              VALIDATE=1 (shadow-tree validation on every step; doubles the broadphase cost),
#              VARIANT=stock (the same run with stock Box2D, for comparison),
#              BUILD_DIR (default build-soak), JOBS (default nproc), QUADPHASE_SKIP_DEPS=1,
#              QUADPHASE_BOX2D_SOURCE_DIR / QUADPHASE_BOX2D_TARBALL as for scripts/test.sh.
# Extra arguments are passed to qp-step-quadtree / qp-step-stock (e.g. --max-growth PCT, default 10).
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for bench
build_dir=${BUILD_DIR:-build-soak}
target=qp-step-quadtree
[[ "${VARIANT:-quadphase}" == stock ]] && target=qp-step-stock
QP_LOG=1 qp_configure "$build_dir" -DCMAKE_BUILD_TYPE=Release
qp_build "$build_dir" "$target"

args=(--scene churn --size "${SIZE:-250}" --seed "${SEED:-1}" --warmup $((${STEPS:-100000} - 1)) --steps 1
      --interval "${INTERVAL:-10000}" --threads default)
[[ "${VALIDATE:-0}" == 1 ]] && args+=(--validate)
start=$(date +%s)
"$build_dir/bench/$target" "${args[@]}" "$@"
echo "soak: $(( $(date +%s) - start )) s wall"
