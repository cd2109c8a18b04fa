# SPDX-License-Identifier: MIT
# QuadphaseInstall.cmake -- install rules: quadphase's CMake package, and Box2D's own package names.
#
# Layout under the install prefix (`cmake --install <build> --prefix P`):
#   include/box2d/*.h                        Box2D 2.4.1's headers with quadphase's b2_broad_phase.h (stock's ABI):
#                                            the headers of libbox2d and of quadphase::box2d
#   include/quadphase/*.h                    the public headers: <quadphase/box2d.h> (the extras) and the core headers
#                                            it stands on (settings, statistics, error hook, task system); the
#                                            internals stay beside their sources (plugin/*/src), not installed
#   include/quadphase-box2d-stock/box2d/*.h  stock Box2D headers (quadphase::box2d_stock)
#   lib/libbox2d.so.2.4.1 (soname libbox2d.so.2), libbox2d.so.2, libbox2d.so, libbox2d.a
#                                            Box2D with the quadtree, the adapter and the core in one library
#   lib/pkgconfig/box2d.pc                   pkg-config box2d (Cflags as Debian's: -I${includedir} -I${includedir}/box2d)
#   lib/cmake/box2d/box2dConfig{,Version}.cmake   find_package(box2d) -> box2d::box2d (the shared library)
#   lib/libquadphase_*.a, lib/cmake/quadphase/...  find_package(quadphase) -> quadphase::core, ::box2d, ::box2d_stock
#
# `cmake --install <build> --prefix S --component box2d_stock` writes the same Box2D names (include/box2d,
# libbox2d.so.2.4.1, libbox2d.a, box2d.pc, box2dConfig.cmake) for stock Box2D 2.4.1 built from the same source with
# the same flags: the baseline a game is compared against. It is not part of the default install.

include_guard(GLOBAL)
include(CMakePackageConfigHelpers)

set(QUADPHASE_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/quadphase" CACHE STRING
    "Install directory (relative to the prefix) of the quadphase CMake package files")
mark_as_advanced(QUADPHASE_INSTALL_CMAKEDIR)

install(TARGETS quadphase_core quadphase_box2d quadphase_box2d_stock
    EXPORT quadphaseTargets
    ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}"
    RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}")

# Headers: the public ones only (plugin/*/include; docs/design.md, "Public surface").
install(DIRECTORY "${PROJECT_SOURCE_DIR}/plugin/core/include/"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(DIRECTORY "${QUADPHASE_BOX2D_ASSEMBLED_INCLUDE_DIR}/box2d"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/plugin/box2d/include/quadphase"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(DIRECTORY "${QUADPHASE_BOX2D_SRC}/include/box2d"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/quadphase-box2d-stock")

# CMake package.
install(EXPORT quadphaseTargets
    NAMESPACE quadphase::
    FILE quadphaseTargets.cmake
    DESTINATION "${QUADPHASE_INSTALL_CMAKEDIR}")

configure_package_config_file(
    "${PROJECT_SOURCE_DIR}/cmake/quadphaseConfig.cmake.in"
    "${PROJECT_BINARY_DIR}/quadphaseConfig.cmake"
    INSTALL_DESTINATION "${QUADPHASE_INSTALL_CMAKEDIR}")
write_basic_package_version_file(
    "${PROJECT_BINARY_DIR}/quadphaseConfigVersion.cmake"
    VERSION "${PROJECT_VERSION}"
    COMPATIBILITY SameMinorVersion)

install(FILES
    "${PROJECT_BINARY_DIR}/quadphaseConfig.cmake"
    "${PROJECT_BINARY_DIR}/quadphaseConfigVersion.cmake"
    "${PROJECT_SOURCE_DIR}/cmake/QuadphaseVariant.cmake"
    DESTINATION "${QUADPHASE_INSTALL_CMAKEDIR}")

# The licences travel with the binaries: quadphase's (MIT) and Box2D's (MIT, its own copyright).
install(FILES "${PROJECT_SOURCE_DIR}/LICENSE" DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/quadphase")
install(FILES "${QUADPHASE_BOX2D_SRC}/LICENSE"
    DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/quadphase"
    RENAME LICENSE.box2d
    OPTIONAL)

# --- Box2D's own package names -----------------------------------------------------------------------------------
# quadphase_box2d_package(<flavour-target-prefix> <export> [COMPONENT <c> EXCLUDE_FROM_ALL])
# Installs libbox2d.so.2.4.1 and libbox2d.a, box2dConfig.cmake (exported as box2d::box2d, like Box2D's own build,
# whose export file is named box2dConfig.cmake too), box2dConfigVersion.cmake and box2d.pc.
function(quadphase_box2d_package prefix export)
    cmake_parse_arguments(PARSE_ARGV 2 P "EXCLUDE_FROM_ALL" "COMPONENT;PC_FILE" "")
    set(component COMPONENT "${P_COMPONENT}")
    set(exclude "")
    if(P_EXCLUDE_FROM_ALL)
        set(exclude EXCLUDE_FROM_ALL)
    endif()
    install(TARGETS ${prefix}_shared EXPORT ${export}
        LIBRARY DESTINATION "${CMAKE_INSTALL_LIBDIR}" ${component} ${exclude}
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" ${component} ${exclude})
    install(TARGETS ${prefix}_static
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" ${component} ${exclude})
    install(EXPORT ${export}
        FILE box2dConfig.cmake
        NAMESPACE box2d::
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/box2d"
        ${component} ${exclude})
    install(FILES "${PROJECT_BINARY_DIR}/box2d-package/box2dConfigVersion.cmake"
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/cmake/box2d"
        ${component} ${exclude})
    install(FILES "${P_PC_FILE}"
        DESTINATION "${CMAKE_INSTALL_LIBDIR}/pkgconfig"
        ${component} ${exclude})
endfunction()

write_basic_package_version_file(
    "${PROJECT_BINARY_DIR}/box2d-package/box2dConfigVersion.cmake"
    VERSION 2.4.1
    COMPATIBILITY SameMajorVersion)
# box2d.pc: relocatable (${pcfiledir}), so that a prefix given at install time (cmake --install --prefix) works.
file(RELATIVE_PATH _box2d_pc_to_prefix "/p/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/p")
string(REGEX REPLACE "/$" "" _box2d_pc_to_prefix "${_box2d_pc_to_prefix}")
set(QUADPHASE_PC_PREFIX "\${pcfiledir}/${_box2d_pc_to_prefix}")
set(QUADPHASE_PC_LIBS_PRIVATE "${QUADPHASE_PC_LIBS}") # OpenMP (if built with it) and the pool's threads
configure_file("${PROJECT_SOURCE_DIR}/cmake/box2d.pc.in" "${PROJECT_BINARY_DIR}/box2d-package/quadphase/box2d.pc" @ONLY)
set(QUADPHASE_PC_LIBS_PRIVATE "")
configure_file("${PROJECT_SOURCE_DIR}/cmake/box2d.pc.in" "${PROJECT_BINARY_DIR}/box2d-package/stock/box2d.pc" @ONLY)

quadphase_box2d_package(quadphase_libbox2d box2dConfig COMPONENT box2d
    PC_FILE "${PROJECT_BINARY_DIR}/box2d-package/quadphase/box2d.pc")
quadphase_box2d_package(quadphase_libbox2d_stock box2dStockConfig COMPONENT box2d_stock EXCLUDE_FROM_ALL
    PC_FILE "${PROJECT_BINARY_DIR}/box2d-package/stock/box2d.pc")
install(DIRECTORY "${QUADPHASE_BOX2D_SRC}/include/box2d"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}"
    COMPONENT box2d_stock EXCLUDE_FROM_ALL)
