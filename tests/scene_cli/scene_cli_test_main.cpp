// SPDX-License-Identifier: MIT
// Catch2's main() for quadphase_scene_cli_tests; the other files hold only test cases.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
