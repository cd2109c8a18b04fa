# SPDX-License-Identifier: MIT
# RunConsumer.cmake -- cmake -P driver for the package tests (see tests/CMakeLists.txt).
#
# Required -D arguments:
#   MODE                 find_package | add_subdirectory
#   QUADPHASE_ROOT       quadphase repository root
#   QUADPHASE_BUILD_DIR  the quadphase build tree under test (find_package: installed from)
#   CONSUMER_DIR         the consumer CMake project
#   WORK_DIR             scratch directory (wiped first)
# Optional:
#   CONFIG               build configuration (default Release)
#   BOX2D_SRC            Box2D source root to reuse (add_subdirectory mode)
#   GENERATOR, CXX_COMPILER, CXX_FLAGS_RELEASE, JOBS
#   CXX_FLAGS, EXE_LINKER_FLAGS  the build's own (e.g. -stdlib=libc++): the consumers are compiled with them too
#   OPENMP, PC_LIBS              QUADPHASE_OPENMP, and box2d.pc's expected Libs.private (OpenMP's runtime, threads)
#                                (find_package: the installed libbox2d.so needs an OpenMP runtime exactly when ON)

cmake_minimum_required(VERSION 3.20)

foreach(var MODE QUADPHASE_ROOT QUADPHASE_BUILD_DIR CONSUMER_DIR WORK_DIR)
    if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
        message(FATAL_ERROR "RunConsumer.cmake: -D${var}=... is required")
    endif()
endforeach()
if(NOT CONFIG)
    set(CONFIG Release)
endif()
if(NOT JOBS)
    set(JOBS 2)
endif()

# run(<step> COMMAND ...): run a command, echo it, fail the test if it fails.
function(run step)
    cmake_parse_arguments(PARSE_ARGV 1 R "" "WORKING_DIRECTORY" "COMMAND")
    if(NOT R_WORKING_DIRECTORY)
        set(R_WORKING_DIRECTORY "${WORK_DIR}")
    endif()
    string(REPLACE ";" " " pretty "${R_COMMAND}")
    message(STATUS "[${MODE}] ${step}: ${pretty}")
    execute_process(COMMAND ${R_COMMAND}
        WORKING_DIRECTORY "${R_WORKING_DIRECTORY}"
        RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "[${MODE}] ${step} failed (${rc})")
    endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

set(consumer_build "${WORK_DIR}/build")
set(configure_args -S "${CONSUMER_DIR}" -B "${consumer_build}" "-DCMAKE_BUILD_TYPE=${CONFIG}")
if(GENERATOR)
    list(APPEND configure_args -G "${GENERATOR}")
endif()
if(CXX_COMPILER)
    list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
endif()
if(DEFINED CXX_FLAGS_RELEASE)
    list(APPEND configure_args "-DCMAKE_CXX_FLAGS_RELEASE=${CXX_FLAGS_RELEASE}")
endif()
if(CXX_FLAGS)
    list(APPEND configure_args "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}")
endif()
if(EXE_LINKER_FLAGS)
    list(APPEND configure_args "-DCMAKE_EXE_LINKER_FLAGS=${EXE_LINKER_FLAGS}")
endif()
separate_arguments(cxx_flags UNIX_COMMAND "${CXX_FLAGS} ${EXE_LINKER_FLAGS}")

if(MODE STREQUAL "find_package")
    set(prefix "${WORK_DIR}/prefix")
    run("install" COMMAND "${CMAKE_COMMAND}" --install "${QUADPHASE_BUILD_DIR}" --config "${CONFIG}" --prefix "${prefix}")
    file(GLOB_RECURSE config_files "${prefix}/quadphaseConfig.cmake")
    if(NOT config_files)
        message(FATAL_ERROR "[${MODE}] install did not produce quadphaseConfig.cmake under ${prefix}")
    endif()
    foreach(f include/box2d/box2d.h include/box2d/b2_broad_phase.h include/quadphase/box2d.h
              include/quadphase-box2d-stock/box2d/b2_broad_phase.h
              lib/libbox2d.so.2.4.1 lib/libbox2d.so.2 lib/libbox2d.so lib/libbox2d.a
              lib/pkgconfig/box2d.pc lib/cmake/box2d/box2dConfig.cmake lib/cmake/box2d/box2dConfigVersion.cmake)
        if(NOT EXISTS "${prefix}/${f}")
            message(FATAL_ERROR "[${MODE}] install is missing ${prefix}/${f}")
        endif()
    endforeach()
    # The installed b2_broad_phase.h must be ours, not Box2D's.
    file(SHA256 "${prefix}/include/box2d/b2_broad_phase.h" ours)
    file(SHA256 "${QUADPHASE_ROOT}/plugin/box2d/include/box2d/b2_broad_phase.h" expected)
    if(NOT ours STREQUAL expected)
        message(FATAL_ERROR "[${MODE}] installed include/box2d/b2_broad_phase.h "
                            "is not plugin/box2d/include/box2d/b2_broad_phase.h")
    endif()
    # An OpenMP runtime among the shared library's DT_NEEDED entries exactly when it was built with OpenMP, and in
    # box2d.pc's Libs.private for static consumers.
    if(DEFINED OPENMP)
        find_program(READELF NAMES readelf llvm-readelf REQUIRED)
        execute_process(COMMAND "${READELF}" -d "${prefix}/lib/libbox2d.so.2.4.1"
            OUTPUT_VARIABLE dynamic RESULT_VARIABLE rc)
        if(NOT rc EQUAL 0)
            message(FATAL_ERROR "[${MODE}] readelf -d failed on the installed libbox2d.so.2.4.1")
        endif()
        string(REGEX MATCH "\\(NEEDED\\)[^\n]*lib(gomp|omp|iomp5)\\.so[.0-9]*" needs_omp "${dynamic}")
        string(REGEX MATCH "lib[a-z0-9]+\\.so[.0-9]*$" needs_omp "${needs_omp}") # the library's name alone
        file(STRINGS "${prefix}/lib/pkgconfig/box2d.pc" libs_private REGEX "^Libs.private:")
        string(REGEX REPLACE "^Libs.private: *" "" libs_private "${libs_private}")
        if(OPENMP AND NOT needs_omp)
            message(FATAL_ERROR "[${MODE}] built with OpenMP, but libbox2d.so.2.4.1 needs no OpenMP runtime:\n${dynamic}")
        elseif(NOT OPENMP AND needs_omp)
            message(FATAL_ERROR "[${MODE}] built without OpenMP, but libbox2d.so.2.4.1 needs one: ${needs_omp}")
        endif()
        if(NOT libs_private STREQUAL "${PC_LIBS}")
            message(FATAL_ERROR "[${MODE}] box2d.pc's Libs.private is '${libs_private}', expected '${PC_LIBS}'")
        endif()
        message(STATUS "[${MODE}] OpenMP ${OPENMP}: libbox2d.so.2.4.1 needs '${needs_omp}', box2d.pc's "
                       "Libs.private '${libs_private}'")
    endif()
    # The stock component: the same Box2D names for stock Box2D, in its own prefix.
    set(stock_prefix "${WORK_DIR}/prefix-stock")
    run("install stock" COMMAND "${CMAKE_COMMAND}" --install "${QUADPHASE_BUILD_DIR}" --config "${CONFIG}"
        --prefix "${stock_prefix}" --component box2d_stock)
    file(SHA256 "${stock_prefix}/include/box2d/b2_broad_phase.h" stock_header)
    file(SHA256 "${BOX2D_SRC}/include/box2d/b2_broad_phase.h" pristine)
    if(NOT stock_header STREQUAL pristine)
        message(FATAL_ERROR "[${MODE}] the box2d_stock component's b2_broad_phase.h is not Box2D's")
    endif()
    list(APPEND configure_args "-DCMAKE_PREFIX_PATH=${prefix}")
    set(programs consumer_quadphase consumer_stock consumer_box2d_package)
elseif(MODE STREQUAL "add_subdirectory")
    list(APPEND configure_args "-DQUADPHASE_ROOT=${QUADPHASE_ROOT}")
    if(BOX2D_SRC)
        list(APPEND configure_args "-DQUADPHASE_BOX2D_SOURCE_DIR=${BOX2D_SRC}")
    endif()
    set(programs consumer_quadphase)
else()
    message(FATAL_ERROR "RunConsumer.cmake: unknown MODE '${MODE}'")
endif()

run("configure" COMMAND "${CMAKE_COMMAND}" ${configure_args})
run("build" COMMAND "${CMAKE_COMMAND}" --build "${consumer_build}" --config "${CONFIG}" --parallel "${JOBS}")

foreach(program IN LISTS programs)
    set(exe "")
    foreach(candidate "${consumer_build}/${program}" "${consumer_build}/${CONFIG}/${program}"
                      "${consumer_build}/${program}.exe" "${consumer_build}/${CONFIG}/${program}.exe")
        if(EXISTS "${candidate}")
            set(exe "${candidate}")
            break()
        endif()
    endforeach()
    if(NOT exe)
        message(FATAL_ERROR "[${MODE}] built program ${program} not found in ${consumer_build}")
    endif()
    run("run ${program}" COMMAND "${exe}")
endforeach()

# pkg-config box2d, as Debian's caveexpress finds Box2D: C++11, shared and static, on both prefixes.
if(MODE STREQUAL "find_package")
    find_program(PKG_CONFIG NAMES pkg-config pkgconf REQUIRED)
    foreach(flavour IN ITEMS quadphase stock)
        if(flavour STREQUAL "quadphase")
            set(p "${prefix}")
        else()
            set(p "${stock_prefix}")
        endif()
        foreach(linkage IN ITEMS shared static)
            set(static_arg "")
            if(linkage STREQUAL "static")
                set(static_arg --static)
            endif()
            execute_process(COMMAND "${CMAKE_COMMAND}" -E env "PKG_CONFIG_PATH=${p}/lib/pkgconfig"
                "${PKG_CONFIG}" --cflags --libs ${static_arg} box2d
                OUTPUT_VARIABLE flags OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE rc)
            if(NOT rc EQUAL 0)
                message(FATAL_ERROR "[${MODE}] pkg-config box2d failed on ${p}")
            endif()
            separate_arguments(flags UNIX_COMMAND "${flags}")
            if(linkage STREQUAL "static")
                list(TRANSFORM flags REPLACE "^-lbox2d$" "-l:libbox2d.a")
                list(APPEND flags -rdynamic) # so that the consumer's dlsym sees what the archive brought in
            endif()
            set(exe "${WORK_DIR}/pkgconfig_${flavour}_${linkage}")
            run("pkg-config ${flavour} ${linkage}" COMMAND "${CXX_COMPILER}" ${cxx_flags} -std=c++11 -Wall -Wextra
                -Wpedantic -Werror -DQUADPHASE_VARIANT_BOX2D_PACKAGE=1 "-DEXPECT_LIBRARY=\"${flavour}\""
                "${CONSUMER_DIR}/../common/consumer.cpp" ${flags} -ldl -o "${exe}")
            run("run pkg-config ${flavour} ${linkage}" COMMAND "${CMAKE_COMMAND}" -E env "LD_LIBRARY_PATH=${p}/lib"
                "${exe}")
        endforeach()
    endforeach()
endif()

message(STATUS "[${MODE}] package test passed")
