# SPDX-License-Identifier: MIT
# Runs a query/ray-cast dump program and, when REFERENCE is given, requires its output to equal REFERENCE
# byte for byte:
#   cmake -D PROGRAM=<exe> [-D ARGS="<args>"] -D OUTPUT=<file> [-D REFERENCE=<file>] [-D EMULATOR=<command>]
#         -P CompareDumps.cmake
# EMULATOR (a list: program and arguments) starts PROGRAM where the build machine cannot, as
# CMAKE_CROSSCOMPILING_EMULATOR does for ctest.
#
# On a difference it prints the first 6000 characters of `diff -U1 REFERENCE OUTPUT` and fails.  The program's
# stderr (per-scene summary, self-check failures) is always shown.
cmake_minimum_required(VERSION 3.20)

foreach(_var IN ITEMS PROGRAM OUTPUT)
    if(NOT DEFINED ${_var} OR "${${_var}}" STREQUAL "")
        message(FATAL_ERROR "CompareDumps.cmake: -D ${_var}=... is required")
    endif()
endforeach()

get_filename_component(_dir "${OUTPUT}" DIRECTORY)
file(MAKE_DIRECTORY "${_dir}")
file(REMOVE "${OUTPUT}")
separate_arguments(_args UNIX_COMMAND "${ARGS}")

execute_process(
    COMMAND ${EMULATOR} "${PROGRAM}" "${OUTPUT}" ${_args}
    RESULT_VARIABLE _rc
    ERROR_VARIABLE _err)
message("${_err}")
# A program that failed its self-checks still wrote its answers: compare them too, then fail.
set(_program_failed "")
if(NOT _rc STREQUAL "0")
    set(_program_failed "${PROGRAM} ${ARGS} failed (exit ${_rc}); see the messages above")
endif()
if(NOT EXISTS "${OUTPUT}")
    message(FATAL_ERROR "${PROGRAM} wrote no ${OUTPUT}. ${_program_failed}")
endif()

if(NOT DEFINED REFERENCE OR "${REFERENCE}" STREQUAL "")
    if(_program_failed)
        message(FATAL_ERROR "${_program_failed}")
    endif()
    return()
endif()
if(NOT EXISTS "${REFERENCE}")
    message(FATAL_ERROR "reference ${REFERENCE} does not exist (did the stock dump run?). ${_program_failed}")
endif()

execute_process(
    COMMAND "${CMAKE_COMMAND}" -E compare_files "${REFERENCE}" "${OUTPUT}"
    RESULT_VARIABLE _same)
if(_same STREQUAL "0")
    file(SIZE "${OUTPUT}" _size)
    message("same answers: ${OUTPUT} == ${REFERENCE} (${_size} bytes)")
    if(_program_failed)
        message(FATAL_ERROR "${_program_failed}")
    endif()
    return()
endif()

find_program(_diff diff)
set(_excerpt "")
if(_diff)
    execute_process(
        COMMAND "${_diff}" -U1 "${REFERENCE}" "${OUTPUT}"
        OUTPUT_VARIABLE _excerpt)
    string(LENGTH "${_excerpt}" _length)
    if(_length GREATER 6000)
        string(SUBSTRING "${_excerpt}" 0 6000 _excerpt)
        string(APPEND _excerpt "\n... (diff cut at 6000 characters)")
    endif()
else()
    file(SIZE "${REFERENCE}" _ref_size)
    file(SIZE "${OUTPUT}" _out_size)
    set(_excerpt "(no diff program for an excerpt) ${REFERENCE}: ${_ref_size} bytes, "
                 "${OUTPUT}: ${_out_size} bytes")
endif()
# Plain message(): printed as is (FATAL_ERROR would re-wrap the diff's lines).
message("${_excerpt}")
message(FATAL_ERROR "QueryAABB/RayCast answers differ between the stock and the quadphase build "
                    "(diff above). ${_program_failed}")
