# SPDX-License-Identifier: MIT
# For the test drivers run with cmake -P (tests/abi, tests/robustness): the lines of a program's output.

# lines_matching(<out_var> <regex> <text>): the lines of `text` that match `regex`, as a list.
function(lines_matching out_var regex text)
    string(REPLACE "\n" ";" lines "${text}")
    list(FILTER lines INCLUDE REGEX "${regex}")
    set(${out_var} "${lines}" PARENT_SCOPE)
endfunction()
