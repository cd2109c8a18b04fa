# QuadphaseInstall.cmake -- install rules and the quadphase CMake package.
#
# Layout under the install prefix:
#   include/quadphase/...                     core headers          (quadphase::core)
#   include/quadphase-box2d/box2d/*.h         assembled Box2D tree  (quadphase::box2d)
#   include/quadphase-box2d/quadphase/...     adapter headers       (quadphase::box2d)
#   include/quadphase-box2d-stock/box2d/*.h   stock Box2D headers   (quadphase::box2d_stock)
#   lib/libquadphase_*.a
#   lib/cmake/quadphase/quadphase{Config,ConfigVersion,Targets}.cmake, QuadphaseVariant.cmake

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

# Headers.
install(DIRECTORY "${PROJECT_SOURCE_DIR}/plugin/core/include/"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}")
install(DIRECTORY "${QUADPHASE_BOX2D_ASSEMBLED_INCLUDE_DIR}/box2d"
    DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/quadphase-box2d")
if(EXISTS "${PROJECT_SOURCE_DIR}/plugin/box2d/include/quadphase")
    install(DIRECTORY "${PROJECT_SOURCE_DIR}/plugin/box2d/include/quadphase"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/quadphase-box2d")
endif()
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

# Box2D's licence travels with the binaries built from it.
install(FILES "${QUADPHASE_BOX2D_SRC}/LICENSE"
    DESTINATION "${CMAKE_INSTALL_DATADIR}/doc/quadphase"
    RENAME LICENSE.box2d
    OPTIONAL)
