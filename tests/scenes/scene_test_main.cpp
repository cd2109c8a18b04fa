// SPDX-License-Identifier: MIT
// Catch2's main() for quadphase_scene_tests (and the programs of tests/parallel and tests/accuracy); the other files
// hold only test cases.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
