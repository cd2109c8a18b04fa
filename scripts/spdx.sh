#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The licence line of every source file of ours: `SPDX-License-Identifier: MIT` within a file's first 3 lines.
#
#   scripts/spdx.sh --check   lists the files that lack it, one per line; exits 1 when there is one, 0 otherwise
#   scripts/spdx.sh --fix     inserts it into each of them and lists them; running it again changes nothing
#
# Source files of ours: the files git tracks in this checkout that are C++ (.h .hpp .cpp .cc), CMake
# (CMakeLists.txt, .cmake, .cmake.in), Python (.py) or shell (.sh), and files without an extension whose first line
# is a shell or Python shebang (.ci/run). Not the fuzzers' data (tests/fuzz/corpus, seeds, regressions) nor the
# benchmark's results (bench/results). --fix writes `// SPDX-License-Identifier: MIT` in C++ and
# `# SPDX-License-Identifier: MIT` elsewhere, as line 1, or after a `#!` line and after a Python `-*- coding` line
# (both must stay first). Exit status 2: bad arguments, or not a git checkout.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

readonly tag='SPDX-License-Identifier: MIT'

usage() {
    sed -n '2,/^set -euo/{/^# SPDX-License-Identifier: MIT$/!p}' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'
}

mode=
case "${1:-}" in
    --check | --fix) mode=$1 ;;
    -h | --help) usage; exit 0 ;;
    *) echo "spdx: give --check or --fix (got '${1:-}'); --help says more" >&2; exit 2 ;;
esac
if [[ $# -gt 1 ]]; then
    echo "spdx: one argument, --check or --fix (got $#)" >&2
    exit 2
fi
if ! git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
    echo "spdx: $PWD is not a git checkout: the files checked are the ones git tracks" >&2
    exit 2
fi

# The comment that starts the licence line in FILE (// or #), or nothing when FILE is not a source file of ours.
comment_of() {
    local file=$1 name first
    case "$file" in
        tests/fuzz/corpus/* | tests/fuzz/seeds/* | tests/fuzz/regressions/* | bench/results/*) return ;;
    esac
    name=${file##*/}
    case "$name" in
        *.h | *.hpp | *.cpp | *.cc) echo '//' ;;
        CMakeLists.txt | *.cmake | *.cmake.in | *.py | *.sh) echo '#' ;;
        *.*) ;;
        *)
            IFS= read -r first < "$file" || true
            if [[ "$first" =~ ^\#!(/usr/bin/env[[:space:]]+|/[^[:space:]]*/)(bash|sh|dash|python3?)([[:space:]]|$) ]]; then
                echo '#'
            fi
            ;;
    esac
}

# How many lines of FILE must stay above the licence line: a #! line, then a Python coding line.
lines_above() {
    local file=$1 above=0 line
    local -a head=()
    mapfile -t -n 2 head < "$file"
    line=${head[0]:-}
    if [[ "$line" == '#!'* ]]; then
        above=1
        line=${head[1]:-}
    fi
    if [[ "$line" =~ ^[[:space:]]*#.*-\*-.*coding[:=] ]]; then
        above=$((above + 1))
    fi
    echo "$above"
}

missing=()
while IFS= read -r -d '' file; do
    [[ -f "$file" && ! -L "$file" ]] || continue
    comment=$(comment_of "$file")
    [[ -n "$comment" ]] || continue
    if head -n 3 -- "$file" | grep -qF -- "$tag"; then
        continue
    fi
    missing+=("$file")
    if [[ "$mode" == --fix ]]; then
        above=$(lines_above "$file")
        if [[ ! -s "$file" ]]; then
            printf '%s %s\n' "$comment" "$tag" > "$file"
        elif [[ "$above" -eq 0 ]]; then
            sed -i "1i $comment $tag" -- "$file"
        else
            sed -i "${above}a $comment $tag" -- "$file"
        fi
    fi
done < <(git ls-files -z)

if [[ ${#missing[@]} -gt 0 ]]; then
    printf '%s\n' "${missing[@]}"
fi
if [[ "$mode" == --fix ]]; then
    echo "spdx: added the licence line to ${#missing[@]} files" >&2
    exit 0
fi
if [[ ${#missing[@]} -gt 0 ]]; then
    echo "spdx: ${#missing[@]} source files lack '$tag' in their first 3 lines; scripts/spdx.sh --fix adds it" >&2
    exit 1
fi
echo "spdx: every source file carries '$tag'" >&2
