# SPDX-License-Identifier: MIT
# QuadphaseOpenMP.cmake -- whether the core's parallel pair generation can run on OpenMP (Executor::OpenMP).
#
#   QUADPHASE_OPENMP (option)  ON by default when the C++ compiler has OpenMP (find_package(OpenMP)); OFF by default
#                              where it has none (Apple's clang, Emscripten) or where OpenMP is not looked for
#                              (-DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=TRUE). OFF: the library makes no OpenMP call and
#                              links no OpenMP runtime; pair generation still runs in parallel on the library's own
#                              pool (the default executor) or the game's TaskSystem, and Executor::OpenMP serially
#                              (Config::threads says so). ON without OpenMP is an error.
#
# After inclusion, for the targets and sources of our own code (never Box2D's sources, which compile as in stock):
#   QUADPHASE_OPENMP_LIBRARIES     OpenMP::OpenMP_CXX, or empty
#   QUADPHASE_OPENMP_OPTIONS       OpenMP's compile options as a list (per-source COMPILE_OPTIONS), or empty
#   QUADPHASE_OPENMP_INCLUDE_DIRS  omp.h's directory where the compiler needs one, or empty
#   QUADPHASE_OPENMP_PC_LIBS       OpenMP's runtime for box2d.pc's Libs.private (-lgomp -lpthread with GCC), or empty

include_guard(GLOBAL)

if(NOT DEFINED QUADPHASE_OPENMP OR QUADPHASE_OPENMP)
    find_package(OpenMP COMPONENTS CXX)
endif()
option(QUADPHASE_OPENMP "Offer OpenMP as an executor of pair generation (OFF: Executor::OpenMP runs serially)"
    ${OpenMP_CXX_FOUND})

set(QUADPHASE_OPENMP_LIBRARIES "")
set(QUADPHASE_OPENMP_OPTIONS "")
set(QUADPHASE_OPENMP_INCLUDE_DIRS "")
set(QUADPHASE_OPENMP_PC_LIBS "")
if(QUADPHASE_OPENMP)
    if(NOT OpenMP_CXX_FOUND)
        message(FATAL_ERROR "quadphase: QUADPHASE_OPENMP is ON but the C++ compiler ${CMAKE_CXX_COMPILER} has no "
                            "OpenMP (find_package(OpenMP) found none). Install its OpenMP runtime (GCC: libgomp, "
                            "clang: libomp-dev), or configure with -DQUADPHASE_OPENMP=OFF: pair generation then runs "
                            "on the library's own pool or the game's TaskSystem, and Executor::OpenMP serially.")
    endif()
    set(QUADPHASE_OPENMP_LIBRARIES OpenMP::OpenMP_CXX)
    separate_arguments(QUADPHASE_OPENMP_OPTIONS NATIVE_COMMAND "${OpenMP_CXX_FLAGS}")
    set(QUADPHASE_OPENMP_INCLUDE_DIRS "${OpenMP_CXX_INCLUDE_DIRS}")
    foreach(_quadphase_omp_lib IN LISTS OpenMP_CXX_LIB_NAMES)
        string(APPEND QUADPHASE_OPENMP_PC_LIBS " -l${_quadphase_omp_lib}")
    endforeach()
    string(STRIP "${QUADPHASE_OPENMP_PC_LIBS}" QUADPHASE_OPENMP_PC_LIBS)
    message(STATUS "quadphase: parallel pair generation on OpenMP (${OpenMP_CXX_FLAGS})")
else()
    message(STATUS "quadphase: built without OpenMP: pair generation runs on the library's pool or the game's "
                   "TaskSystem, Executor::OpenMP serially")
endif()
