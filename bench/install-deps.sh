#!/usr/bin/env bash
# Install what bench/ needs on Debian/Ubuntu: the project's dependencies (scripts/install-deps.sh) plus python3
# with matplotlib (the plots) and valgrind (callgrind.h: instruction counts of the replay's timed steps). Idempotent.
set -euo pipefail
exec "$(dirname "${BASH_SOURCE[0]}")/../scripts/install-deps.sh" python3-matplotlib valgrind "$@"
