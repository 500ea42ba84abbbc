// Whether gnuplot runs, for the tests that draw a figure (scripts/setup.sh
// installs it): one definition for every test file (a unity build compiles
// a test executable's files as one).
#pragma once

#include <gtest/gtest.h>

#include "cli_run.h"
#include "required_tool.h"

namespace camdyn::test {

inline bool gnuplot_available() {
  static const bool available = runs_ok({"gnuplot", "--version"});
  return available;
}

}  // namespace camdyn::test

#define REQUIRE_GNUPLOT() REQUIRE_TOOL(camdyn::test::gnuplot_available(), "gnuplot")
