# SPDX-License-Identifier: MIT
# Building quadphase for WebAssembly with Debian's Emscripten, the tests run under Node.js.
#
#   cmake -S . -B build-web -DCMAKE_TOOLCHAIN_FILE=cmake/toolchains/emscripten.cmake
#
# Debian packages: emscripten (3.1.6; it brings clang-14, lld-14, binaryen and node-acorn) and nodejs
# (scripts/install-deps.sh --for web; scripts/test-web.sh does everything). Emscripten's own toolchain file does the
# rest; this one only sets what it leaves open. There is no OpenMP (QUADPHASE_OPENMP is OFF) and no pthread: the
# library runs serially, as Config::threads says.
#
# ctest and catch_discover_tests start every test program (a .js file beside its .wasm) through
# CMAKE_CROSSCOMPILING_EMULATOR, node, which Emscripten's toolchain file finds.

execute_process(COMMAND em-config EMSCRIPTEN_ROOT
    OUTPUT_VARIABLE _quadphase_emscripten_root OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _quadphase_rc)
if(NOT _quadphase_rc EQUAL 0 OR NOT EXISTS "${_quadphase_emscripten_root}/cmake/Modules/Platform/Emscripten.cmake")
    message(FATAL_ERROR "quadphase: Emscripten not found (em-config EMSCRIPTEN_ROOT failed); install Debian's "
                        "emscripten (scripts/install-deps.sh --for web).")
endif()

# Header-only packages (Catch2, CLI11, nlohmann-json) come from the build machine: Emscripten has no builds of them,
# and their headers are the same for every target. Their include directory is /usr/include, which also holds
# glibc's headers, so it is searched after Emscripten's own (-idirafter): the compiler then reports it among the
# directories it searches by itself, and CMake does not pass it again as -isystem, which would put it first.
# (Set before Emscripten's file, which keeps a mode already set.) CMake learns the compiler's own directories by
# running it, which Emscripten's file skips unless EMSCRIPTEN_FORCE_COMPILERS is off.
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
set(EMSCRIPTEN_FORCE_COMPILERS OFF)
# C++ exceptions as WebAssembly exceptions (Node.js 16 and later, current browsers): quadphase reports bad_alloc and
# invalid_argument by throwing, and the tests catch them. Emscripten's default aborts at the first throw.
set(CMAKE_CXX_FLAGS_INIT "-idirafter /usr/include -fwasm-exceptions")
# WASM_ASYNC_COMPILATION=0: the program instantiates its .wasm synchronously; asynchronously, Emscripten 3.1.6
#   fetches it with fetch(), which Node.js 18 and later have, and which rejects a file path.
# ALLOW_MEMORY_GROWTH: the scenes and the tests need more than the initial 16 MiB.
# NODERAWFS: the program sees the real file system under Node.js (tests that write logs and read their corpus).
# EXIT_RUNTIME: main's return value is node's exit status, and the program's output is flushed before it ends.
set(CMAKE_EXE_LINKER_FLAGS_INIT
    "-sWASM_ASYNC_COMPILATION=0 -sALLOW_MEMORY_GROWTH=1 -sNODERAWFS=1 -sEXIT_RUNTIME=1")

include("${_quadphase_emscripten_root}/cmake/Modules/Platform/Emscripten.cmake")
