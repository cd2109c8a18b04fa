#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates tests/fuzz/seeds/box2d: one short recorded trace per scene of the scene library (bench/'s qp-record:
# scene creation, 2 warm-up steps, 10 steps; size 8, pyramid 4, tiles 100, the smallest it takes), converted by
# qp_trace_to_input into inputs of the Box2D-level fuzz target, cut at 2 KB (short inputs keep the fuzzer fast),
# with the target's first byte cycling through automatic depth / validation mode / 2 threads / parallel paths
# from 2 proxies / fixed depth.
#
# usage: tests/fuzz/make_trace_seeds.sh BUILD_DIR     (a configured build of this repository, bench included)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
build=${1:?usage: tests/fuzz/make_trace_seeds.sh BUILD_DIR}
cmake --build "$build" -j "${JOBS:-2}" --target qp-record qp_trace_to_input
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=tests/fuzz/seeds/box2d
rm -f "$out"/trace-*
mkdir -p "$out"
configs=(0 3 12 28 140)
i=0
for scene in bullets churn mixed openworld particles pyramid rain shooter sparse terrain tiles tumbler; do
    size=8
    [[ $scene == pyramid ]] && size=4
    [[ $scene == tiles ]] && size=100
    "$build/bench/qp-record" --scene "$scene" --size "$size" --warmup 2 --steps 10 --out "$work/$scene.qptrace" >/dev/null
    "$build/tests/fuzz/qp_trace_to_input" "$work/$scene.qptrace" "$out/trace-$scene" \
        --config "${configs[$((i % ${#configs[@]}))]}" --max-bytes 2048
    i=$((i + 1))
done
