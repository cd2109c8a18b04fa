#!/usr/bin/env bash
# Install what bench/ needs on Debian/Ubuntu: the project's dependencies (scripts/install-deps.sh) plus python3
# with matplotlib, which bench/parallel.py uses to draw bench/results/parallel.png. Idempotent.
set -euo pipefail
exec "$(dirname "${BASH_SOURCE[0]}")/../scripts/install-deps.sh" python3-matplotlib "$@"
