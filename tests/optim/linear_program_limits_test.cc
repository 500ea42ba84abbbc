// The LP wrapper's guard (optim/linear_program.h): a number CLP cannot take
// (a coefficient or an impossible bound at or beyond 1e29, where CLP asserts
// and aborts the process) comes back as a failed solve naming it, never a
// signal; a huge bound on the side that always holds is no bound.
#include <gtest/gtest.h>

#include <string>
#include <utility>

#include "optim/linear_program.h"

namespace {

using camdyn::optim::LinearProgram;
using camdyn::optim::LpStatus;

/// max x subject to lower ≤ x ≤ upper (as a row), 0 ≤ x.
LinearProgram one_row(double lower, double upper) {
  LinearProgram lp;
  const int x = lp.add_column(0.0, camdyn::optim::kLpInfinity, -1.0);
  lp.add_row({{x, 1.0}}, lower, upper);
  return lp;
}

constexpr double kInf = camdyn::optim::kLpInfinity;

TEST(LinearProgramLimits, OrdinaryBoundSolves) {
  const auto sol = camdyn::optim::solve(one_row(-kInf, 3.0));
  ASSERT_EQ(sol.status, LpStatus::optimal) << sol.message;
  EXPECT_NEAR(sol.x[0], 3.0, 1e-12);
}

// The side that cannot hold (x ≥ 1e308, x ≤ −1e308): a failed solve naming it.
TEST(LinearProgramLimits, ImpossibleHugeBoundFailsNamingItInsteadOfAborting) {
  for (const auto& [lower, upper] : {std::pair{1e308, kInf}, std::pair{-kInf, -1e308}, std::pair{1e30, kInf}}) {
    const auto sol = camdyn::optim::solve(one_row(lower, upper));
    EXPECT_EQ(sol.status, LpStatus::failed) << lower << " " << upper;
    EXPECT_NE(sol.message.find("row"), std::string::npos) << sol.message;
    EXPECT_NE(sol.message.find("beyond what CLP solves"), std::string::npos) << sol.message;
  }
}

// A huge bound on the side that always holds is no bound: x ≤ 1e308 with
// x maximised is unbounded, x ≥ −1e308 with x ≤ 3 solves.
TEST(LinearProgramLimits, HarmlessHugeBoundIsNoBound) {
  EXPECT_EQ(camdyn::optim::solve(one_row(-kInf, 1e308)).status, LpStatus::unbounded);
  const auto sol = camdyn::optim::solve(one_row(-1e308, 3.0));
  ASSERT_EQ(sol.status, LpStatus::optimal) << sol.message;
  EXPECT_NEAR(sol.x[0], 3.0, 1e-12);
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
