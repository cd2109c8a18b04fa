# SPDX-License-Identifier: MIT
# Adds the target caveexpress-physics (caveexpress_physics.cpp beside this file) to CaveExpress 2.5.2's own build
# without editing any of its files: scripts/real-game.sh configures the game with
#   -DCMAKE_PROJECT_caveproductions_INCLUDE=<this file>
# CMake includes it right after the game's top-level project(caveproductions); the target is defined once the
# whole top-level CMakeLists.txt has run (cmake_language(DEFER), CMake >= 3.19), so the game's own static
# libraries, include directories and flags exist and apply to it exactly as to the game's tests_caveexpress.

set(QUADPHASE_REAL_GAME_DRIVER_SOURCE "${CMAKE_CURRENT_LIST_DIR}/caveexpress_physics.cpp")

function(quadphase_add_caveexpress_physics)
    if(NOT TARGET caveexpress-server)
        message(FATAL_ERROR "physics_driver.cmake: the game defined no caveexpress-server target")
    endif()
    # CaveExpress.cpp holds the game class and its registration, as in the game's tests_caveexpress.
    add_executable(caveexpress-physics "${QUADPHASE_REAL_GAME_DRIVER_SOURCE}"
                   "${CMAKE_SOURCE_DIR}/src/caveexpress/main/CaveExpress.cpp")
    target_link_libraries(caveexpress-physics PUBLIC caveexpress-client caveexpress-server caveexpress-shared)
endfunction()

cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL quadphase_add_caveexpress_physics)
