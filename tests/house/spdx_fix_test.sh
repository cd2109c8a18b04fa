#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# scripts/spdx.sh on a scratch git repository: which files --check lists, where --fix puts the line (line 1, after a
# #! line, after a Python coding line), that a second --fix changes nothing, and that data files are left alone.
#   spdx_fix_test.sh SPDX_SCRIPT WORK_DIR
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 SPDX_SCRIPT WORK_DIR" >&2; exit 2; }
script=$(realpath "$1")
work=$(realpath -m "$2")
rm -rf "$work"
mkdir -p "$work/scripts" "$work/src" "$work/tests/fuzz/corpus/core" "$work/bench/results" "$work/.ci" "$work/debian"
cp "$script" "$work/scripts/spdx.sh"
cd "$work"
fail() { echo "spdx_fix_test: $*" >&2; exit 1; }

printf '// A.\nint a;\n' > src/a.cpp
printf '#pragma once\n' > src/b.h
printf '// SPDX-License-Identifier: MIT\nint c;\n' > src/c.cc
printf 'project(x)\n' > CMakeLists.txt
printf '#!/usr/bin/env bash\necho run\n' > .ci/run
printf '#!/bin/sh\n' > src/only-shebang
printf '#!/usr/bin/python3\n# -*- coding: utf-8 -*-\n"""Doc."""\n' > src/tool.py
printf '"""Doc."""\n' > src/mod.py
printf '#!/usr/bin/make -f\nall:\n' > debian/rules
printf 'int not_ours;\n' > tests/fuzz/corpus/core/input.cpp
printf '#!/bin/sh\n' > tests/fuzz/corpus/core/0123abcd
printf 'a,b\n' > bench/results/x.csv
printf 'no newline at the end' > src/d.sh
chmod +x .ci/run src/only-shebang
: > src/empty.py
git init -q . && git add -A

expected='.ci/run
CMakeLists.txt
src/a.cpp
src/b.h
src/d.sh
src/empty.py
src/mod.py
src/only-shebang
src/tool.py'
status=0
listed=$(bash scripts/spdx.sh --check 2> /dev/null | LC_ALL=C sort) || status=$?
[[ $status -eq 1 ]] || fail "--check exited $status on files that lack the line, not 1"
[[ "$listed" == "$expected" ]] || fail "--check listed:
$listed
expected:
$expected"

bash scripts/spdx.sh --fix > /dev/null 2>&1 || fail "--fix failed"
want() { # FILE CONTENT
    [[ "$(cat "$1"; echo .)" == "$2." ]] || fail "$1 after --fix:
$(cat "$1")"
}
want src/a.cpp $'// SPDX-License-Identifier: MIT\n// A.\nint a;\n'
want src/b.h $'// SPDX-License-Identifier: MIT\n#pragma once\n'
want src/c.cc $'// SPDX-License-Identifier: MIT\nint c;\n'
want CMakeLists.txt $'# SPDX-License-Identifier: MIT\nproject(x)\n'
want .ci/run $'#!/usr/bin/env bash\n# SPDX-License-Identifier: MIT\necho run\n'
want src/only-shebang $'#!/bin/sh\n# SPDX-License-Identifier: MIT\n'
want src/tool.py $'#!/usr/bin/python3\n# -*- coding: utf-8 -*-\n# SPDX-License-Identifier: MIT\n"""Doc."""\n'
want src/mod.py $'# SPDX-License-Identifier: MIT\n"""Doc."""\n'
want src/empty.py $'# SPDX-License-Identifier: MIT\n'
want src/d.sh $'# SPDX-License-Identifier: MIT\nno newline at the end'
want debian/rules $'#!/usr/bin/make -f\nall:\n'
want tests/fuzz/corpus/core/input.cpp $'int not_ours;\n'
want tests/fuzz/corpus/core/0123abcd $'#!/bin/sh\n'
want bench/results/x.csv $'a,b\n'
[[ -x .ci/run && -x src/only-shebang ]] || fail "--fix lost the executable bit"

git add -A
bash scripts/spdx.sh --check > /dev/null 2>&1 || fail "--check fails after --fix"
bash scripts/spdx.sh --fix > /dev/null 2>&1 || fail "the second --fix failed"
git diff --quiet || fail "the second --fix changed files: $(git diff --stat)"

status=0
(cd / && bash "$work/scripts/spdx.sh" --bogus) > /dev/null 2>&1 || status=$?
[[ $status -eq 2 ]] || fail "a bad argument exited $status, not 2"
rm -rf .git
status=0
GIT_CEILING_DIRECTORIES=$(dirname "$work") bash scripts/spdx.sh --check > /dev/null 2>&1 || status=$?
[[ $status -eq 2 ]] || fail "outside a git checkout --check exited $status, not 2"
echo "spdx_fix_test: ok"
