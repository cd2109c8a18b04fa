# SPDX-License-Identifier: MIT
# cmake -P driver of abi_swap_probe_*: the binary swap, as a user does it with LD_LIBRARY_PATH.
#   -DPROBE=<swap_probe built against stock headers and libbox2d.so.2>  -DSTOCK_LIB_DIR= -DQUADPHASE_LIB_DIR=
#   -DNM=<nm>  -DINTERPOSING=0|1  -DTEMPLATES=0|1 (the probe has its template scene)  -DWORK_DIR=<scratch>
#   [-DEMULATOR=<command>: starts the probe where the build machine cannot (CMAKE_CROSSCOMPILING_EMULATOR); the
#   dynamic loader's variables below reach the program's loader through it]
# 1. On the stock library (LD_BIND_NOW=1): the probe must load, say "stock" and pass its inline checks.
# 2. On quadphase's (LD_LIBRARY_PATH, QUADPHASE_VALIDATE=1, LD_BIND_NOW=1, LD_DEBUG=bindings): it must say
#    "quadphase", pass its inline checks, give the same "sensors" lines (contacts at every step, query and ray-cast
#    hashes, inline counts) and "edges" lines (stock's inline readers right after each kind of call), and report
#    0 validation mismatches over more than 100 checked UpdatePairs.
# 2b. On quadphase's with QUADPHASE_STOCK_TREE=1: every line (contacts, inline readers, stock's templates on a
#    b2BroadPhase of the program's own, tree statistics) must be stock's, with 0 validation mismatches.
# 3. No Box2D function of quadphase's library may be bound to the probe's own copies (vtables and typeinfo are
#    data, copy-relocated into executables by design; sanitizer runtimes' symbols are not Box2D's). For the interposing build, the probe must really export copies of
#    stock's inline b2BroadPhase functions, or step 3 would prove nothing.
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run_probe name libdir extra_env)
    execute_process(
        COMMAND "${CMAKE_COMMAND}" -E env "LD_LIBRARY_PATH=${libdir}" ${extra_env} ${EMULATOR} "${PROBE}"
        OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
    file(WRITE "${WORK_DIR}/${name}.out" "${out}")
    file(WRITE "${WORK_DIR}/${name}.err" "${err}")
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "probe on ${name} failed (${rc}):\n${out}\n${err}")
    endif()
    set(${name}_out "${out}" PARENT_SCOPE)
    set(${name}_err "${err}" PARENT_SCOPE)
endfunction()

include("${CMAKE_CURRENT_LIST_DIR}/../../cmake/ScriptLines.cmake") # lines_matching

# The probe's `prefix` lines on stock's library and on run `other`: at least `min` of them, and the same.
function(expect_same_lines prefix other min what)
    lines_matching(a "^${prefix} " "${stock_out}")
    lines_matching(b "^${prefix} " "${${other}_out}")
    list(LENGTH a n)
    if(n LESS min)
        message(FATAL_ERROR "the probe printed only ${n} ${prefix} lines")
    endif()
    if(NOT a STREQUAL b)
        string(REPLACE ";" "\n" a "${a}")
        string(REPLACE ";" "\n" b "${b}")
        message(FATAL_ERROR "${what}:\nstock:\n${a}\n${other}:\n${b}")
    endif()
    message(STATUS "${n} ${prefix} lines identical on stock's library and in the ${other} run")
endfunction()

# LD_BIND_NOW: a symbol the stock library lacks (the reverse build) fails at load, not at its first call.
run_probe(stock "${STOCK_LIB_DIR}" "LD_BIND_NOW=1")
run_probe(quadphase "${QUADPHASE_LIB_DIR}"
    "QUADPHASE_VALIDATE=1;LD_BIND_NOW=1;LD_DEBUG=bindings;LD_DEBUG_OUTPUT=${WORK_DIR}/bindings")

# Stock-tree mode: a real b2DynamicTree beside the quadtree, so that stock's templates compiled into the program
# find what stock's would.
run_probe(stocktree "${QUADPHASE_LIB_DIR}" "QUADPHASE_STOCK_TREE=1;QUADPHASE_VALIDATE=1;LD_BIND_NOW=1")

lines_matching(stock_library "^library " "${stock_out}")
lines_matching(quadphase_library "^library " "${quadphase_out}")
message(STATUS "stock run:     ${stock_library}")
message(STATUS "quadphase run: ${quadphase_library}")
if(NOT stock_library MATCHES "^library ${STOCK_LIB_DIR}/libbox2d\\.so\\.2 stock$")
    message(FATAL_ERROR "the first run did not run on the stock library: ${stock_library}")
endif()
if(NOT quadphase_library MATCHES "^library ${QUADPHASE_LIB_DIR}/libbox2d\\.so\\.2 quadphase$")
    message(FATAL_ERROR "the second run did not run on quadphase's library: ${quadphase_library}")
endif()

# Contact sets per step, query and ray-cast hashes, inline reads.
expect_same_lines(sensors quadphase 30 "contacts, queries or inline reads differ between the libraries")
# Stock's inline readers right after each kind of proxy change (EdgeScene): the exact fat AABBs and overlaps.
expect_same_lines(edges quadphase 50 "stock's inline readers read other values right after a call")

# Stock-tree mode gives stock's answers everywhere, stock's templates and tree statistics included; the default
# mode gives them everywhere but there (documented: the templates find nothing, the statistics read 0).
foreach(prefix IN ITEMS sensors edges templates)
    set(min 1)
    if(prefix STREQUAL "templates" AND NOT TEMPLATES)
        set(min 0)
    endif()
    expect_same_lines(${prefix} stocktree ${min} "QUADPHASE_STOCK_TREE=1: ${prefix} lines differ from stock's")
endforeach()
if(NOT stocktree_err MATCHES "quadphase: validation: ([0-9]+) UpdatePairs checked, 0 mismatches")
    message(FATAL_ERROR "QUADPHASE_STOCK_TREE=1: validation found mismatches or did not run:\n${stocktree_err}")
endif()
lines_matching(a "^templates " "${quadphase_out}")
string(REPLACE ";" "\n" a "${a}")
message(STATUS "default mode, stock's templates (documented to find nothing):\n${a}")

if(NOT quadphase_err MATCHES "quadphase: validation: ([0-9]+) UpdatePairs checked, ([0-9]+) mismatches")
    message(FATAL_ERROR "no validation summary from quadphase's library:\n${quadphase_err}")
endif()
set(checks "${CMAKE_MATCH_1}")
set(mismatches "${CMAKE_MATCH_2}")
message(STATUS "validation: ${checks} UpdatePairs checked, ${mismatches} mismatches")
if(NOT mismatches EQUAL 0 OR checks LESS 100)
    message(FATAL_ERROR "validation: ${checks} checks, ${mismatches} mismatches:\n${quadphase_err}")
endif()

# Bindings from quadphase's libbox2d into the probe executable.
file(GLOB binding_files "${WORK_DIR}/bindings*")
set(function_bindings "")
foreach(f IN LISTS binding_files)
    file(STRINGS "${f}" lines REGEX "binding file .*libbox2d\\.so\\.2 \\[0\\] to .*qp_abi_swap_probe")
    foreach(line IN LISTS lines)
        # Box2D's functions only: vtables and typeinfo are data, and the sanitizer runtimes' own symbols (an ASan
        # build links them into the executable) bind there by design.
        if(line MATCHES "symbol `[^']*b2" AND NOT line MATCHES "`_ZT[VIS]")
            list(APPEND function_bindings "${line}")
        endif()
    endforeach()
endforeach()
if(function_bindings)
    string(REPLACE ";" "\n" text "${function_bindings}")
    message(FATAL_ERROR "quadphase's library calls the probe's own copies of functions (interposition):\n${text}")
endif()
if(INTERPOSING)
    execute_process(COMMAND "${NM}" -D --defined-only "${PROBE}" OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
    foreach(symbol IN ITEMS _ZNK12b2BroadPhase10GetFatAABBEi _ZNK12b2BroadPhase11TestOverlapEii
                            _ZNK12b2BroadPhase11GetUserDataEi _ZNK12b2BroadPhase13GetTreeHeightEv)
        if(NOT symbols MATCHES "${symbol}")
            message(FATAL_ERROR "the interposing probe does not export ${symbol}: the test would prove nothing")
        endif()
    endforeach()
    message(STATUS "the probe exports its own copies of stock's inline b2BroadPhase functions; none is called by the library")
endif()
message(STATUS "abi_swap_probe passed")
