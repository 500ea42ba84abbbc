// Tests that need an outside program (gnuplot, Chromium, util-linux's
// script): where it is missing such a test is skipped, except in CI
// (CAMDYN_CI, which scripts/test.sh sets), where the set-up installs every
// one of them, so a missing program is a failure, not a silent skip.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string_view>

namespace camdyn::test {

/// Whether this run is CI's (scripts/test.sh exports CAMDYN_CI=1).
inline bool in_ci() {
  const char* value = std::getenv("CAMDYN_CI");
  return value != nullptr && *value != '\0' && std::string_view(value) != "0";
}

}  // namespace camdyn::test

/// Skips the test (fails it in CI) unless `available`; `what` names the program.
#define REQUIRE_TOOL(available, what)                                                            \
  do {                                                                                           \
    if (!(available)) {                                                                          \
      if (camdyn::test::in_ci())                                                                 \
        GTEST_FAIL() << what << " is not installed; CI needs it (scripts/setup.sh installs it)"; \
      else                                                                                       \
        GTEST_SKIP() << what << " is not installed (scripts/setup.sh installs it)";              \
    }                                                                                            \
  } while (false)
