#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Windows x86-64: cross-build quadphase with Debian's MinGW-w64 (cmake/toolchains/mingw-w64-x86_64.cmake) and run its
# tests under Wine (cmake/toolchains/wine-run.sh, through CMAKE_CROSSCOMPILING_EMULATOR): box2d.dll and its import
# library libbox2d.dll.a, quadphase's and stock's; the core tests against the brute-force reference, the Box2D adapter
# tests against stock Box2D built for Windows (every scene in validation mode, query and ray-cast answers, parallel
# determinism and threads, robustness, the fuzz corpora, the accuracy checker, the DLLs' export tables against
# stock's), Box2D's own unit tests against both builds, and the examples quadphase-headless and quadphase-jobs.
#
# Left out: the benchmarks, quadphase-scene and its tests (cairo and ffmpeg of the build machine:
# QUADPHASE_TEST_HOST_ONLY is OFF in a cross build), the package tests, the debug error hook test (it forks),
# abi_swap_probe and abi_abidiff (ELF libraries). parallel_determinism steps each scene 120 times instead of 600
# (QUADPHASE_DETERMINISM_STEPS, as scripts/test-arm64.sh does): at 600 it alone took 523 s under Wine.
#
# Environment: as scripts/test.sh (QUADPHASE_SKIP_DEPS, JOBS, QUADPHASE_BOX2D_SOURCE_DIR, QUADPHASE_BOX2D_TARBALL);
# BUILD_DIR (default build-windows); WINEPREFIX (Wine's state, default BUILD_DIR/wine, made by the first run).
# Compiles through ccache when it is installed. Extra arguments are passed to the CMake configure step. Prints
# ctest's summary line last; exits with ctest's status.
source "$(dirname "${BASH_SOURCE[0]}")/lib/build.sh"
qp_deps scripts/install-deps.sh --for windows
build_dir=${BUILD_DIR:-build-windows}
qp_configure_cross "$build_dir" cmake/toolchains/mingw-w64-x86_64.cmake "$@"

# Wine makes its prefix at first use, which takes a while: once here, before the build's test discovery starts
# several programs at once.
export WINEPREFIX=${WINEPREFIX:-$PWD/$build_dir/wine}
export WINEDEBUG=${WINEDEBUG:--all}
if [[ ! -f "$WINEPREFIX/system.reg" ]]; then
    wineboot --init >/dev/null 2>&1 || true
    wineserver --wait
fi
[[ -f "$WINEPREFIX/system.reg" ]] || { echo "$QP_NAME: Wine could not make its prefix $WINEPREFIX." >&2; exit 1; }

qp_build "$build_dir"

# One Wine server for the whole run, with Wine's own services (services.exe, winedevice.exe, rpcss.exe, ...) started
# once, here, and stopped at the end. Left to itself the server exits a few seconds after the last Windows program
# ends and starts again, services and all, with the next one: a test started in that moment failed in 0.02 s with no
# output in a CI run. wineboot starts the services with no terminal or pipe of a test's: a service started by a test
# would keep that test's output pipe open, and ctest would wait for it to close until the server is stopped.
wineserver -p
trap 'wineserver -k >/dev/null 2>&1 || true' EXIT
wine wineboot </dev/null >/dev/null 2>&1 || true

export QUADPHASE_DETERMINISM_STEPS=${QUADPHASE_DETERMINISM_STEPS:-120}
qp_ctest "$build_dir" "$build_dir/ctest-windows.log" "Windows x86-64 under Wine"
