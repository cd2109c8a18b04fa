// SPDX-License-Identifier: MIT
// Catch2's main() for quadphase_core_tests; every other file holds only test cases.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
