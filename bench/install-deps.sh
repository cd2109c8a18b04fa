#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Install what bench/ needs on Debian/Ubuntu: scripts/install-deps.sh --for bench (Chipmunk2D, Bullet, python3) plus
# matplotlib (the plots) and valgrind (callgrind.h: instruction counts of the replay's timed steps). Idempotent.
set -euo pipefail
exec "$(dirname "${BASH_SOURCE[0]}")/../scripts/install-deps.sh" --for bench python3-matplotlib valgrind "$@"
