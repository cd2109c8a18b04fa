# SPDX-License-Identifier: MIT
# QuadphaseVariant.cmake -- build the same program against either Box2D build.
#
#   quadphase_link_box2d_variant(<target> <variant> [PRIVATE|PUBLIC|INTERFACE])
#
#   <variant> "quadphase": link quadphase::box2d (Box2D 2.4.1 with the quadtree
#                          broadphase) and define QUADPHASE_VARIANT_QUADPHASE=1;
#   <variant> "stock":     link quadphase::box2d_stock (untouched Box2D 2.4.1)
#                          and define QUADPHASE_VARIANT_STOCK=1.
#
# The scope defaults to PRIVATE.  Never link both variants into one program:
# they define the same symbols with different class layouts.
#
# This file is used in the build tree and installed next to quadphaseConfig.cmake,
# so consumers of find_package(quadphase) get the function too.

include_guard(GLOBAL)

function(quadphase_link_box2d_variant target variant)
    set(scope PRIVATE)
    if(ARGC GREATER 2)
        set(scope "${ARGV2}")
    endif()
    if(NOT scope MATCHES "^(PRIVATE|PUBLIC|INTERFACE)$")
        message(FATAL_ERROR "quadphase_link_box2d_variant(${target} ${variant} ${scope}): "
                            "scope must be PRIVATE, PUBLIC or INTERFACE")
    endif()
    if(variant STREQUAL "quadphase")
        target_link_libraries(${target} ${scope} quadphase::box2d)
        target_compile_definitions(${target} ${scope} QUADPHASE_VARIANT_QUADPHASE=1)
    elseif(variant STREQUAL "stock")
        target_link_libraries(${target} ${scope} quadphase::box2d_stock)
        target_compile_definitions(${target} ${scope} QUADPHASE_VARIANT_STOCK=1)
    else()
        message(FATAL_ERROR "quadphase_link_box2d_variant(${target} ${variant}): "
                            "variant must be \"quadphase\" or \"stock\"")
    endif()
endfunction()
