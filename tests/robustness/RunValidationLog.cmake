# SPDX-License-Identifier: MIT
# cmake -P driver of robustness_validation_log: QUADPHASE_VALIDATE_LOG keeps what validation found in a program
# that never exits normally.   -DCHILD=<validation_log_child> -DWORK_DIR=<scratch> [-DEMULATOR=<command>: starts
# the child where the build machine cannot, as CMAKE_CROSSCOMPILING_EMULATOR does for ctest]
# For each ending (abort, SIGKILL, strict mode's abort at the first mismatch), the child runs with
# QUADPHASE_VALIDATE=1, QUADPHASE_VALIDATE_LOG=<file>, QUADPHASE_VALIDATE_LOG_EVERY=50 and must die; the file
# must then hold its mismatches as they were found and the running summaries, in order. A second run appends.
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run_child mode count log)
    execute_process(
        COMMAND "${CMAKE_COMMAND}" -E env QUADPHASE_VALIDATE=1 "QUADPHASE_VALIDATE_LOG=${log}"
                QUADPHASE_VALIDATE_LOG_EVERY=50 ${EMULATOR} "${CHILD}" ${mode} ${count}
        OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    if(rc EQUAL 0 OR rc EQUAL 2)
        message(FATAL_ERROR "the ${mode} child did not die (${rc}):\n${out}\n${err}")
    endif()
endfunction()

include("${CMAKE_CURRENT_LIST_DIR}/../../cmake/ScriptLines.cmake") # lines_matching

# abort and SIGKILL after 120 UpdatePairs: 12 desynchronising moves, summaries at 50 and 100.
foreach(mode IN ITEMS abort kill)
    set(log "${WORK_DIR}/${mode}.log")
    run_child(${mode} 120 "${log}")
    if(NOT EXISTS "${log}")
        message(FATAL_ERROR "${mode}: no log file")
    endif()
    file(READ "${log}" text)
    lines_matching(mismatches "^quadphase\\[[0-9]+\\]: validation: mismatch: " "${text}")
    lines_matching(summaries "^quadphase\\[[0-9]+\\]: validation: [0-9]+ UpdatePairs checked, [0-9]+ mismatches$" "${text}")
    list(LENGTH mismatches n_mismatches)
    message(STATUS "${mode}: ${n_mismatches} mismatch lines; summaries: ${summaries}")
    if(n_mismatches LESS 12)
        message(FATAL_ERROR "${mode}: ${n_mismatches} mismatch lines, at least 12 expected:\n${text}")
    endif()
    list(LENGTH summaries n_summaries)
    if(NOT n_summaries EQUAL 2)
        message(FATAL_ERROR "${mode}: ${n_summaries} running summaries, 2 expected (at 50 and 100 checks):\n${text}")
    endif()
    list(GET summaries 1 last)
    if(NOT last MATCHES ": 100 UpdatePairs checked, ([0-9]+) mismatches$" OR CMAKE_MATCH_1 LESS 10)
        message(FATAL_ERROR "${mode}: the summary at 100 checks is wrong: ${last}")
    endif()
endforeach()

# Strict mode: the first mismatch aborts at once; its line is in the file. A second run appends to the same file.
set(log "${WORK_DIR}/strict.log")
run_child(strict 120 "${log}")
run_child(strict 120 "${log}")
file(READ "${log}" text)
lines_matching(mismatches "^quadphase\\[[0-9]+\\]: validation: mismatch: " "${text}")
list(LENGTH mismatches n)
if(NOT n EQUAL 2)
    message(FATAL_ERROR "strict: ${n} mismatch lines after two runs, 2 expected (one each, appended):\n${text}")
endif()
message(STATUS "strict: one mismatch line per run, appended")
