// The NLopt driver of the optimize study on problems with known answers:
// every algorithm (native constraints, AUGLAG wrapper, finite-difference
// gradients), the evaluation budget, multi-start, and failures that must
// become stop reasons without losing what the other starts found.
#include <gtest/gtest.h>

#include <cmath>
#include <nlopt.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "optim/search.h"

namespace camdyn::optim {
namespace {

// min (x − 0.7)² + (y − 0.2)²  s.t.  x + y ≤ 0.6, box [0, 1]²: the optimum is
// the projection of (0.7, 0.2) on the line, (0.55, 0.05), with f* = 0.045.
constexpr double kOptimum = 0.045;

SearchProblem projection_problem(long* calls = nullptr) {
  SearchProblem p;
  p.lower = {0.0, 0.0};
  p.upper = {1.0, 1.0};
  p.x0 = {0.1, 0.1};
  p.constraint_count = 1;
  p.evaluate = [calls](const std::vector<double>& x, int, PointKind) {
    if (calls) ++*calls;
    PointValue v;
    v.objective = (x[0] - 0.7) * (x[0] - 0.7) + (x[1] - 0.2) * (x[1] - 0.2);
    v.residuals = {x[0] + x[1] - 0.6};
    v.feasible = v.residuals[0] <= 0.0;
    return v;
  };
  return p;
}

double objective_at(const std::vector<double>& x) { return (x[0] - 0.7) * (x[0] - 0.7) + (x[1] - 0.2) * (x[1] - 0.2); }

bool known_reason(const std::string& r) {
  for (int code = -5; code <= 6; ++code)
    if (code != 0 && r == nlopt_result_name(code)) return true;
  return false;
}

class EveryAlgorithm : public ::testing::TestWithParam<std::string> {};

// Local algorithms reach the optimum to their tolerance; the global ones, with
// a budget this small, only come near it. Either way the chosen point holds
// the constraint, the budget is respected and the stop reason is a name.
TEST_P(EveryAlgorithm, FindsTheConstrainedOptimumWithinTheBudget) {
  const std::string algorithm = GetParam();
  const bool global = algorithm.rfind("GN_", 0) == 0;
  SearchSettings config;
  config.algorithm = algorithm;
  config.max_evaluations = global ? 2000 : 400;
  config.xtol_rel = 1e-6;
  long calls = 0;
  const SearchResult r = run_search(projection_problem(&calls), config);
  EXPECT_TRUE(known_reason(r.stop_reason)) << r.stop_reason;
  EXPECT_EQ(r.evaluations, calls);
  EXPECT_LE(r.evaluations, config.max_evaluations);
  ASSERT_FALSE(r.candidates.empty());
  EXPECT_GE(r.feasible_candidates, 1);
  const std::vector<double>& x = r.candidates.front();
  EXPECT_LE(x[0] + x[1], 0.6);
  const double tolerance = global ? 5e-3 : 1e-4;  // absolute on f, f* = 0.045
  EXPECT_NEAR(objective_at(x), kOptimum, tolerance) << algorithm << " stopped with " << r.stop_reason;
  const bool wrapped =
      algorithm == "LN_BOBYQA" || algorithm == "LN_SBPLX" || algorithm == "GN_CRS2_LM" || algorithm == "GN_DIRECT_L";
  EXPECT_EQ(r.method, wrapped ? "AUGLAG(" + algorithm + ")" : algorithm);
}

INSTANTIATE_TEST_SUITE_P(Search, EveryAlgorithm, ::testing::ValuesIn(optimize_algorithms()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(Search, FiniteDifferenceProbesCountAgainstTheBudget) {
  SearchSettings config;
  config.algorithm = "LD_MMA";
  config.max_evaluations = 31;  // n + 1 = 3 evaluations per gradient
  config.xtol_rel = 0.0;        // only the budget stops it
  const SearchResult r = run_search(projection_problem(), config);
  EXPECT_LE(r.evaluations, 31);
  EXPECT_EQ(r.stop_reason, "maxeval_reached");
}

TEST(Search, MultiStartIsReproducibleAndSharesTheBudget) {
  SearchSettings config;
  config.algorithm = "LN_COBYLA";
  config.starts = 4;
  config.max_evaluations = 203;
  config.seed = 7;
  const SearchResult a = run_search(projection_problem(), config);
  const SearchResult b = run_search(projection_problem(), config);
  ASSERT_EQ(a.starts.size(), 4u);
  long total = 0;
  for (std::size_t s = 0; s < a.starts.size(); ++s) {
    EXPECT_LE(a.starts[s].evaluations, 203 / 4 + 1);
    EXPECT_EQ(a.starts[s].x0, b.starts[s].x0) << "start " << s;
    EXPECT_EQ(a.starts[s].best_x, b.starts[s].best_x) << "start " << s;
    total += a.starts[s].evaluations;
  }
  EXPECT_EQ(total, a.evaluations);
  EXPECT_EQ(a.starts[0].x0, (std::vector<double>{0.1, 0.1}));  // the given start first
  EXPECT_NE(a.starts[1].x0, a.starts[2].x0);
  config.seed = 8;
  EXPECT_NE(run_search(projection_problem(), config).starts[1].x0, a.starts[1].x0);
}

// A start whose evaluations throw ends with a stop reason; the others go on
// and the best point overall is still found.
TEST(Search, AFailedStartDoesNotLoseTheOthers) {
  SearchProblem p = projection_problem();
  const auto inner = p.evaluate;
  p.evaluate = [inner](const std::vector<double>& x, int start, PointKind kind) {
    if (start == 1) throw std::runtime_error("simulated crash in start 1");
    if (start == 2 && x[0] > 0.3) throw nlopt::forced_stop();
    return inner(x, start, kind);
  };
  SearchSettings config;
  config.algorithm = "LN_COBYLA";
  config.starts = 3;
  config.max_evaluations = 300;
  config.xtol_rel = 1e-6;
  const SearchResult r = run_search(p, config);
  ASSERT_EQ(r.starts.size(), 3u);
  EXPECT_EQ(r.starts[1].stop_reason, "failure");
  EXPECT_FALSE(r.starts[1].found);
  EXPECT_EQ(r.starts[2].stop_reason, "forced_stop");
  EXPECT_TRUE(known_reason(r.starts[0].stop_reason));
  ASSERT_FALSE(r.candidates.empty());
  // COBYLA, stopped by xtol_rel or its budget, lands near the constrained
  // optimum, where |∇f| ≈ 0.4 does not vanish.
  constexpr double kNearOptimum = 1e-4;
  EXPECT_NEAR(objective_at(r.candidates.front()), kOptimum, kNearOptimum);
  EXPECT_EQ(r.stop_reason, r.starts[0].stop_reason);  // the start that found the chosen point
}

// Points that cannot be evaluated (an undercut cam, a simulation that gave
// up) are counted and never chosen.
TEST(Search, InvalidPointsAreCountedAndNeverChosen) {
  SearchProblem p = projection_problem();
  const auto inner = p.evaluate;
  p.evaluate = [inner](const std::vector<double>& x, int start, PointKind kind) {
    PointValue v = inner(x, start, kind);
    if (x[1] < 0.08) {  // the optimum's neighbourhood is partly invalid
      v.valid = false;
      v.feasible = false;
      v.objective = 1e3;
      v.residuals = {100.0};
    }
    return v;
  };
  SearchSettings config;
  config.algorithm = "LN_COBYLA";
  config.max_evaluations = 200;
  const SearchResult r = run_search(p, config);
  EXPECT_GT(r.invalid_evaluations, 0);
  ASSERT_FALSE(r.candidates.empty());
  for (const auto& x : r.candidates) EXPECT_GE(x[1], 0.08);
}

TEST(Search, StatusNamesCoverEveryNloptResult) {
  EXPECT_EQ(nlopt_result_name(NLOPT_XTOL_REACHED), "xtol_reached");
  EXPECT_EQ(nlopt_result_name(NLOPT_ROUNDOFF_LIMITED), "roundoff_limited");
  EXPECT_EQ(nlopt_result_name(NLOPT_FORCED_STOP), "forced_stop");
  EXPECT_EQ(nlopt_result_name(NLOPT_MAXTIME_REACHED), "maxtime_reached");
  for (int code = -5; code <= 6; ++code) {
    if (code == 0) continue;
    EXPECT_EQ(nlopt_result_name(code).find("unknown"), std::string::npos) << code;
  }
}

}  // namespace
}  // namespace camdyn::optim
