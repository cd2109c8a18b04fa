#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# wine-run.sh PROGRAM.exe [ARG...]: runs a Windows program under Wine, with its exit status. The emulator of
# cmake/toolchains/mingw-w64-x86_64.cmake (CMAKE_CROSSCOMPILING_EMULATOR).
#
# The program's standard output comes with Unix line ends: its C runtime writes "\r\n" to a pipe (text mode), and
# Catch2's test discovery (catch_discover_tests) would keep the "\r" in every test name.
#
# Environment: WINE (default: wine), WINEPREFIX (Wine's state; Wine's default ~/.wine when unset), WINEDEBUG (default
# -all: no Wine diagnostics among the program's output).
set -o pipefail
export WINEDEBUG=${WINEDEBUG:--all}
"${WINE:-wine}" "$@" | sed 's/\r$//'
