# SPDX-License-Identifier: MIT
# QuadphaseHelpers.cmake -- small helpers shared by the quadphase build.
#
#   quadphase_target_warnings(<target>)
#       Our own code (core, adapter sources, tests, examples, bench): -Wall
#       -Wextra -Wpedantic (or /W4 for MSVC).  PRIVATE, no -Werror.
#
#   quadphase_warning_options(<out-var>)
#       The same options as a list (for per-source COMPILE_OPTIONS).
#
#   quadphase_cxx17(<target>)
#       cxx_std_17 compile feature (PUBLIC for libraries, so consumers get at least
#       C++17) plus CXX_STANDARD 17 / no extensions: the target itself is compiled
#       with exactly -std=c++17.
#
#   quadphase_box2d_source_options(<out-var>)
#       Compile options for Box2D's own sources (warnings off).  Applied
#       identically to the stock and the quadphase builds of Box2D.
#
#   quadphase_box2d_target_properties(<target>)
#       Properties every Box2D build gets (identical for stock and quadphase):
#       quadphase_cxx17() and hidden visibility like Box2D's own build.
#
# quadphase_link_box2d_variant() lives in QuadphaseVariant.cmake (it is also
# installed with the package).

include_guard(GLOBAL)

function(quadphase_warning_options out_var)
    if(MSVC)
        set(${out_var} /W4 PARENT_SCOPE)
    else()
        set(${out_var} -Wall -Wextra -Wpedantic PARENT_SCOPE)
    endif()
endfunction()

function(quadphase_target_warnings target)
    quadphase_warning_options(opts)
    target_compile_options(${target} PRIVATE ${opts})
endfunction()

function(quadphase_box2d_source_options out_var)
    if(MSVC)
        set(${out_var} /w PARENT_SCOPE)
    else()
        set(${out_var} -w PARENT_SCOPE)
    endif()
endfunction()

function(quadphase_cxx17 target)
    get_target_property(type ${target} TYPE)
    if(type STREQUAL "EXECUTABLE")
        target_compile_features(${target} PRIVATE cxx_std_17)
    else()
        target_compile_features(${target} PUBLIC cxx_std_17)
    endif()
    # Explicit -std=c++17 (not the compiler's default gnu++17) for our own builds.
    set_target_properties(${target} PROPERTIES
        CXX_STANDARD 17
        CXX_STANDARD_REQUIRED ON
        CXX_EXTENSIONS OFF)
endfunction()

function(quadphase_box2d_target_properties target)
    quadphase_cxx17(${target})
    set_target_properties(${target} PROPERTIES
        CXX_VISIBILITY_PRESET hidden
        VISIBILITY_INLINES_HIDDEN ON)
endfunction()

# quadphase_box2d_swap(<sources_var> <include_var> HEADERS <header>...)
#       Box2D 2.4.1 with another broadphase swapped in (plugin/box2d's quadphase::box2d, bench/accuracy's paper
#       build). <sources_var>: every Box2D source but src/collision/b2_broad_phase.cpp, with Box2D's compile
#       options set on them in the calling directory (source properties are per directory). <include_var>: an
#       include tree assembled in the calling directory's build tree, box2d-include/box2d/: copies of Box2D's
#       include/box2d/*.h with each of HEADERS in place of the file of the same name (b2_broad_phase.h must be
#       among them). Box2D includes its siblings with quotes, so the swapped header has to sit in the same folder.
function(quadphase_box2d_swap sources_var include_var)
    cmake_parse_arguments(PARSE_ARGV 2 arg "" "" "HEADERS")
    set(src "${QUADPHASE_BOX2D_SRC}")
    file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${src}/src/*.cpp")
    list(SORT sources)
    set(broad_phase_cpp "${src}/src/collision/b2_broad_phase.cpp")
    if(NOT broad_phase_cpp IN_LIST sources)
        message(FATAL_ERROR "quadphase: ${broad_phase_cpp} not among the Box2D sources")
    endif()
    list(REMOVE_ITEM sources "${broad_phase_cpp}")
    quadphase_box2d_source_options(opts)
    set_source_files_properties(${sources} PROPERTIES COMPILE_OPTIONS "${opts}")

    set(ours "")
    foreach(h IN LISTS arg_HEADERS)
        get_filename_component(name "${h}" NAME)
        list(APPEND ours "${name}")
    endforeach()
    if(NOT "b2_broad_phase.h" IN_LIST ours)
        message(FATAL_ERROR "quadphase: quadphase_box2d_swap needs a b2_broad_phase.h among HEADERS")
    endif()
    set(assembled "${CMAKE_CURRENT_BINARY_DIR}/box2d-include")
    file(GLOB box2d_headers "${src}/include/box2d/*.h")
    foreach(h IN LISTS box2d_headers)
        get_filename_component(name "${h}" NAME)
        if(name IN_LIST ours)
            if(NOT name STREQUAL "b2_broad_phase.h")
                message(STATUS "quadphase: ${name} of ${CMAKE_CURRENT_SOURCE_DIR} replaces Box2D's ${name}")
            endif()
        else()
            configure_file("${h}" "${assembled}/box2d/${name}" COPYONLY)
        endif()
    endforeach()
    foreach(h IN LISTS arg_HEADERS)
        # configure_file() re-runs on edits of the input, so changes to our headers are re-copied.
        get_filename_component(name "${h}" NAME)
        configure_file("${h}" "${assembled}/box2d/${name}" COPYONLY)
    endforeach()
    # Remove stale copies (a header deleted from HEADERS).
    file(GLOB present RELATIVE "${assembled}/box2d" "${assembled}/box2d/*")
    foreach(name IN LISTS present)
        get_filename_component(stock "${src}/include/box2d/${name}" ABSOLUTE)
        if(NOT name IN_LIST ours AND NOT EXISTS "${stock}")
            file(REMOVE "${assembled}/box2d/${name}")
        endif()
    endforeach()
    set(${sources_var} ${sources} PARENT_SCOPE)
    set(${include_var} "${assembled}" PARENT_SCOPE)
endfunction()
