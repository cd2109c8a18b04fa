// SPDX-License-Identifier: MIT
// Catch2's main() for the robustness test programs; every other file holds only test cases or helpers.
#define CATCH_CONFIG_MAIN
#include <catch2/catch.hpp>
