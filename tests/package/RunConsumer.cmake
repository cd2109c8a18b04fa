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

if(MODE STREQUAL "find_package")
    set(prefix "${WORK_DIR}/prefix")
    run("install" COMMAND "${CMAKE_COMMAND}" --install "${QUADPHASE_BUILD_DIR}" --config "${CONFIG}" --prefix "${prefix}")
    file(GLOB_RECURSE config_files "${prefix}/quadphaseConfig.cmake")
    if(NOT config_files)
        message(FATAL_ERROR "[${MODE}] install did not produce quadphaseConfig.cmake under ${prefix}")
    endif()
    foreach(f include/quadphase-box2d/box2d/box2d.h include/quadphase-box2d/box2d/b2_broad_phase.h
              include/quadphase-box2d-stock/box2d/b2_broad_phase.h)
        if(NOT EXISTS "${prefix}/${f}")
            message(FATAL_ERROR "[${MODE}] install is missing ${prefix}/${f}")
        endif()
    endforeach()
    # The installed adapter header must be ours, not Box2D's.
    file(SHA256 "${prefix}/include/quadphase-box2d/box2d/b2_broad_phase.h" ours)
    file(SHA256 "${QUADPHASE_ROOT}/plugin/box2d/include/box2d/b2_broad_phase.h" expected)
    if(NOT ours STREQUAL expected)
        message(FATAL_ERROR "[${MODE}] installed include/quadphase-box2d/box2d/b2_broad_phase.h "
                            "is not plugin/box2d/include/box2d/b2_broad_phase.h")
    endif()
    list(APPEND configure_args "-DCMAKE_PREFIX_PATH=${prefix}")
    set(programs consumer_quadphase consumer_stock)
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

message(STATUS "[${MODE}] package test passed")
