# SPDX-License-Identifier: MIT
# src/libs/CMakeLists.txt for CaveExpress 2.5.2 built from Debian's orig tarball (scripts/real-game.sh copies it
# there). Debian's tarball ships no src/libs (the bundled copies of glm, yajl and googletest), but the game's
# top-level CMakeLists.txt still calls add_subdirectory(src/libs). Like Debian's package, take all three from the
# system instead, through the game's own find modules (cmake/Find*.cmake): glm header-only (libglm-dev, nothing to
# link), yajl (libyajl-dev) and googletest for tests_caveexpress (libgtest-dev).
find_package(glm REQUIRED)
find_package(yajl REQUIRED)
if(UNITTESTS)
    # The game's Findgtest.cmake looks for gtest.h itself, not gtest/gtest.h, and pkg-config's gtest.pc names no
    # include directory (it is /usr/include): give it the directory that holds gtest/, which its sources include.
    find_path(GTEST_INCLUDE_DIRS gtest/gtest.h)
    find_package(gtest REQUIRED)
endif()
