# SPDX-License-Identifier: MIT
# Cross-compiling quadphase for 64-bit Windows with Debian's MinGW-w64, the tests run under Wine.
#
#   cmake -S . -B build-windows -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/mingw-w64-x86_64.cmake
#
# Debian packages: g++-mingw-w64-x86-64-posix (the POSIX threads flavour: std::thread and OpenMP need it), wine and
# wine64 (scripts/install-deps.sh --for windows; scripts/test-windows.sh does everything).
#
# ctest and catch_discover_tests start every test program through CMAKE_CROSSCOMPILING_EMULATOR, wine-run.sh beside
# this file (Wine, with Unix line ends on standard output). Wine keeps its state in WINEPREFIX (~/.wine when unset).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)

set(QUADPHASE_CROSS_TRIPLE x86_64-w64-mingw32)
set(CMAKE_C_COMPILER "${QUADPHASE_CROSS_TRIPLE}-gcc-posix")
set(CMAKE_CXX_COMPILER "${QUADPHASE_CROSS_TRIPLE}-g++-posix")
set(CMAKE_RC_COMPILER "${QUADPHASE_CROSS_TRIPLE}-windres")

# The C++ runtime, libgcc, winpthreads and OpenMP's libgomp linked statically into every program and into
# box2d.dll: they run, and ship, without MinGW-w64's DLLs beside them (the DLL and the programs each have their own
# copy; both allocate from msvcrt.dll's heap).
foreach(_kind IN ITEMS EXE SHARED MODULE)
    set(CMAKE_${_kind}_LINKER_FLAGS_INIT "-static")
endforeach()
# FindOpenMP links the library it finds by its full path, which -static does not change: it would take libgomp's
# import library (libgomp.dll.a) before the archive.
execute_process(COMMAND "${CMAKE_CXX_COMPILER}" -print-file-name=libgomp.a
    OUTPUT_VARIABLE _quadphase_libgomp OUTPUT_STRIP_TRAILING_WHITESPACE)
set(OpenMP_gomp_LIBRARY "${_quadphase_libgomp}" CACHE FILEPATH "libgomp, linked statically")

# Target libraries and headers from MinGW-w64's tree only; programs from the build machine.
set(CMAKE_FIND_ROOT_PATH "/usr/${QUADPHASE_CROSS_TRIPLE}")
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
# Header-only packages (Catch2, CLI11, nlohmann-json) come from the build machine: Debian has no MinGW-w64 builds of
# them, and their headers are the same for every target. Their include directory is /usr/include, which also holds
# glibc's headers, so it is searched after MinGW-w64's own (-idirafter): the compiler then reports it among the
# directories it searches by itself, and CMake does not pass it again as -isystem, which would put it first.
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(CMAKE_CXX_FLAGS_INIT "-idirafter /usr/include")
# Windows' file names ignore case, and code written there includes <Windows.h> (Box2D's doctest does); MinGW-w64 has
# windows.h. A Windows.h in the build tree, searched last, includes it.
set(_quadphase_case_dir "${CMAKE_BINARY_DIR}/mingw-w64-case")
file(CONFIGURE OUTPUT "${_quadphase_case_dir}/Windows.h" CONTENT "#include <windows.h>\n")
string(APPEND CMAKE_CXX_FLAGS_INIT " -idirafter ${_quadphase_case_dir}")

set(CMAKE_CROSSCOMPILING_EMULATOR "${CMAKE_CURRENT_LIST_DIR}/wine-run.sh")
