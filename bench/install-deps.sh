#!/usr/bin/env bash
# Install what bench/ needs on Debian/Ubuntu: scripts/install-deps.sh --for bench (Chipmunk2D, Bullet, python3) plus
# matplotlib, which bench/parallel.py uses to draw bench/results/parallel.png. Idempotent.
set -euo pipefail
exec "$(dirname "${BASH_SOURCE[0]}")/../scripts/install-deps.sh" --for bench python3-matplotlib "$@"
