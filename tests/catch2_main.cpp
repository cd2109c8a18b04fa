// SPDX-License-Identifier: MIT
// Catch2's main(), compiled once into quadphase_catch2_main for every Catch2 program of tests/: it is the slowest
// file of the suite to compile (about 20 s), and the programs' own files hold only test cases.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
