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
