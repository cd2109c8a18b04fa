# SPDX-License-Identifier: MIT
# Cross-compiling quadphase for ARM64 Linux with Debian's cross toolchain, running the tests under qemu-user.
#
#   cmake -S . -B build-arm64 -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/aarch64-linux-gnu.cmake
#
# Debian packages: g++-aarch64-linux-gnu (its libgomp1-arm64-cross brings the OpenMP runtime), qemu-user
# (scripts/install-deps.sh --for arm64; scripts/test-arm64.sh does everything).
#
# ctest and catch_discover_tests start every test program through CMAKE_CROSSCOMPILING_EMULATOR: qemu-aarch64 with
# the cross toolchain's sysroot for the dynamic loader and the shared libraries (libstdc++, libgomp).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(QUADPHASE_CROSS_TRIPLE aarch64-linux-gnu)
set(QUADPHASE_CROSS_SYSROOT "/usr/${QUADPHASE_CROSS_TRIPLE}")

set(CMAKE_C_COMPILER "${QUADPHASE_CROSS_TRIPLE}-gcc")
set(CMAKE_CXX_COMPILER "${QUADPHASE_CROSS_TRIPLE}-g++")

find_program(QUADPHASE_QEMU_AARCH64 qemu-aarch64)
if(NOT QUADPHASE_QEMU_AARCH64)
    message(FATAL_ERROR "quadphase: qemu-aarch64 not found; the ARM64 tests run under it (Debian: qemu-user, "
                        "scripts/install-deps.sh --for arm64).")
endif()
set(CMAKE_CROSSCOMPILING_EMULATOR "${QUADPHASE_QEMU_AARCH64};-L;${QUADPHASE_CROSS_SYSROOT}")

# Target libraries from the cross sysroot only; header-only packages (Catch2, CLI11, nlohmann-json) and programs
# from the build machine.
set(CMAKE_FIND_ROOT_PATH "${QUADPHASE_CROSS_SYSROOT}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE BOTH)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
# pkg-config: the target's .pc files (Debian multiarch -dev packages of arm64), never the build machine's.
set(ENV{PKG_CONFIG_LIBDIR} "/usr/lib/${QUADPHASE_CROSS_TRIPLE}/pkgconfig:/usr/share/pkgconfig")
