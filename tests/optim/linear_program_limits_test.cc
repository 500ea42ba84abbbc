// The LP wrapper's guard (optim/linear_program.h): a number CLP cannot take
// (a bound or coefficient at or beyond 1e29, where CLP asserts and aborts the
// process) comes back as a failed solve naming it, never a signal.
#include <gtest/gtest.h>

#include <string>

#include "optim/linear_program.h"

namespace {

using camdyn::optim::LinearProgram;
using camdyn::optim::LpStatus;

/// max x subject to x ≤ bound (as a row), 0 ≤ x.
LinearProgram one_row(double bound) {
  LinearProgram lp;
  const int x = lp.add_column(0.0, camdyn::optim::kLpInfinity, -1.0);
  lp.add_row({{x, 1.0}}, -camdyn::optim::kLpInfinity, bound);
  return lp;
}

TEST(LinearProgramLimits, OrdinaryBoundSolves) {
  const auto sol = camdyn::optim::solve(one_row(3.0));
  ASSERT_EQ(sol.status, LpStatus::optimal) << sol.message;
  EXPECT_NEAR(sol.x[0], 3.0, 1e-12);
}

TEST(LinearProgramLimits, HugeBoundFailsNamingItInsteadOfAborting) {
  for (const double bound : {1e308, -1e308, 1e30}) {
    const auto sol = camdyn::optim::solve(one_row(bound));
    EXPECT_EQ(sol.status, LpStatus::failed) << bound;
    EXPECT_NE(sol.message.find("row bound"), std::string::npos) << sol.message;
    EXPECT_NE(sol.message.find("beyond what CLP solves"), std::string::npos) << sol.message;
  }
}

TEST(LinearProgramLimits, HugeCoefficientOrCostFails) {
  LinearProgram lp;
  const int x = lp.add_column(0.0, 1.0, -1e300);
  lp.add_row({{x, 1.0}}, -camdyn::optim::kLpInfinity, 1.0);
  const auto sol = camdyn::optim::solve(lp);
  EXPECT_EQ(sol.status, LpStatus::failed);
  EXPECT_NE(sol.message.find("cost"), std::string::npos) << sol.message;
}

}  // namespace
