# SPDX-License-Identifier: MIT
# cmake -P driver of abi_exports and abi_abidiff: quadphase's libbox2d.so.2 against stock's, built from the same
# source with the same flags.
#   -DMODE=exports|abidiff -DSTOCK=<stock libbox2d.so.2> -DQUADPHASE=<quadphase's> -DNM=<nm>
#   -DEXPECTED=<quadphase_exports.txt> -DABIDIFF=<abidiff> -DSUPPRESSIONS=<abidiff.suppr>
#   -DOBJDUMP=<objdump> instead of NM: the libraries are Windows DLLs (box2d.dll), whose export tables objdump -p reads
# exports: every dynamic symbol stock's library defines, quadphase's defines too; beyond them, exactly the extras
#          EXPECTED lists (quadphase's public API, and b2BroadPhase's functions that are out of line here, inline or
#          absent in stock): an extra not listed (an internal that leaked) fails, and so does a listed one that is
#          gone. Prints the counts.
# abidiff: abidiff finds no removed or changed function or variable and no changed type beyond the reviewed
#          suppressions (added symbols are the exports check's); without the suppressions it must report the
#          b2BroadPhase change, or it read no debug information and proved nothing.
cmake_minimum_required(VERSION 3.20)

if(MODE STREQUAL "exports")
    function(dynamic_symbols out lib)
        if(OBJDUMP)
            # The export table's name pointer lines, "\t[   3] name", as nm's " T name" (a DLL has no weak exports).
            execute_process(COMMAND "${OBJDUMP}" -p "${lib}" OUTPUT_VARIABLE text RESULT_VARIABLE rc)
            string(REGEX MATCHALL "\n\t\\[ *[0-9]+\\] [^\n]+" lines "${text}")
            list(TRANSFORM lines REPLACE "^\n\t\\[ *[0-9]+\\]" " T")
        else()
            execute_process(COMMAND "${NM}" -D --defined-only "${lib}" OUTPUT_VARIABLE text RESULT_VARIABLE rc)
            string(REGEX MATCHALL "[^\n]+" lines "${text}")
        endif()
        if(NOT rc EQUAL 0)
            message(FATAL_ERROR "reading the exports of ${lib} failed (${rc})")
        endif()
        set(names "")
        set(weak "")
        foreach(line IN LISTS lines)
            # The linker's own markers of the data segment's end: it exports them from a library when one the
            # library links exports them (libc++.so.1 does), and no program refers to another object's.
            if(line MATCHES " (__bss_start|_edata|_end)$")
                continue()
            endif()
            if(line MATCHES " ([A-Za-z]) ([^ ]+)$")
                set(type "${CMAKE_MATCH_1}")
                set(name "${CMAKE_MATCH_2}")
                list(APPEND names "${name}")
                if(type STREQUAL "W" OR type STREQUAL "V")
                    list(APPEND weak "${name}")
                endif()
            endif()
        endforeach()
        list(REMOVE_DUPLICATES names)
        set(${out} "${names}" PARENT_SCOPE)
        set(${out}_weak "${weak}" PARENT_SCOPE)
    endfunction()
    # The list: the first word of each line that is not blank or a comment.
    file(STRINGS "${EXPECTED}" expected_lines)
    set(expected "")
    foreach(line IN LISTS expected_lines)
        if(line MATCHES "^([^# \t]+)")
            list(APPEND expected "${CMAKE_MATCH_1}")
        endif()
    endforeach()
    list(LENGTH expected n_expected)
    if(n_expected EQUAL 0)
        message(FATAL_ERROR "${EXPECTED} lists no symbol")
    endif()
    dynamic_symbols(stock "${STOCK}")
    dynamic_symbols(ours "${QUADPHASE}")
    list(LENGTH stock n_stock)
    list(LENGTH ours n_ours)
    set(missing "")
    foreach(s IN LISTS stock)
        # A weak (vague-linkage) template instance stock's compiler chose not to inline, such as
        # b2BroadPhase::UpdatePairs<b2ContactManager> in an -O1 build, is one a program instantiates itself.
        if(NOT s IN_LIST ours AND NOT s IN_LIST stock_weak)
            list(APPEND missing "${s}")
        endif()
    endforeach()
    set(extras "")
    set(unexpected "")
    foreach(s IN LISTS ours)
        if(s IN_LIST stock)
            continue()
        endif()
        list(APPEND extras "${s}")
        if(NOT s IN_LIST expected)
            list(APPEND unexpected "${s}")
        endif()
    endforeach()
    set(gone "")
    foreach(s IN LISTS expected)
        if(NOT s IN_LIST extras)
            list(APPEND gone "${s}")
        endif()
    endforeach()
    list(LENGTH extras n_extras)
    message(STATUS "exported symbols: stock ${n_stock}, quadphase ${n_ours} (stock's + ${n_extras} extras; "
                   "${n_expected} listed)")
    if(n_stock LESS 400)
        message(FATAL_ERROR "stock's library exports only ${n_stock} symbols: nm or objdump read nothing useful")
    endif()
    if(missing)
        string(REPLACE ";" "\n" text "${missing}")
        message(FATAL_ERROR "quadphase's library lacks symbols stock's exports:\n${text}")
    endif()
    if(unexpected)
        string(REPLACE ";" "\n" text "${unexpected}")
        message(FATAL_ERROR "quadphase's library exports symbols beyond stock's and the extras listed in "
                            "${EXPECTED} (an internal made visible; a new public function goes into that list):\n"
                            "${text}")
    endif()
    if(gone)
        string(REPLACE ";" "\n" text "${gone}")
        message(FATAL_ERROR "quadphase's library lacks extras listed in ${EXPECTED}:\n${text}")
    endif()
elseif(MODE STREQUAL "abidiff")
    execute_process(COMMAND "${ABIDIFF}" --no-added-syms "${STOCK}" "${QUADPHASE}"
        OUTPUT_VARIABLE raw RESULT_VARIABLE raw_rc)
    if(raw_rc EQUAL 0 OR NOT raw MATCHES "b2ContactManager")
        message(FATAL_ERROR "abidiff without suppressions did not see b2BroadPhase's private members change "
                            "(no debug information?):\n${raw}")
    endif()
    execute_process(COMMAND "${ABIDIFF}" --no-added-syms --suppressions "${SUPPRESSIONS}" "${STOCK}" "${QUADPHASE}"
        OUTPUT_VARIABLE out RESULT_VARIABLE rc)
    message(STATUS "abidiff (exit ${rc}):\n${out}")
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "abidiff reports ABI differences beyond ${SUPPRESSIONS}")
    endif()
else()
    message(FATAL_ERROR "MODE must be exports or abidiff")
endif()
