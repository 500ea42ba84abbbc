// The any-law jump-speed bound (optim/optimize/jump_bound.h): the linear programme over
// freely sampled lifts against the closed form derived in jump_bound.h for
// rest-to-rest rises and returns, with and without a required contact force,
// gravity and a constant-force spring; and the LP wrapper on small
// programmes with known answers.
#include "optim/optimize/jump_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/constants.h"
#include "geometry/motion_law.h"
#include "optim/linear_program.h"
#include "tolerance.h"

namespace camdyn::optim {
namespace {

constexpr int kGrid = 600;
// The extremal law has a velocity step at the start and the central
// differences smear it over one interval: the bound's relative error is
// O(1/grid). Two intervals' worth covers it.
constexpr double kGridTolerance = 2.0 / kGrid;
// Speeds quoted to the rpm (README.md, the closed forms' comments).
constexpr double kQuotedRpm = 1.0;

/// 20 mm rise over 0–120°, dwell to 180°, return over 180–300°, dwell to 360°.
MotionLaw quickstart_law(SegmentLaw law = SegmentLaw::cycloidal) {
  auto segment = [](SegmentType type, SegmentLaw l, double end_deg, std::optional<double> lift) {
    SegmentConfig s;
    s.type = type;
    s.law = l;
    s.end_deg = end_deg;
    s.lift = lift;
    return s;
  };
  MotionLawConfig c;
  c.segments = {segment(SegmentType::rise, law, 120.0, 0.02), segment(SegmentType::dwell, SegmentLaw::none, 180.0, {}),
                segment(SegmentType::return_, law, 300.0, 0.02),
                segment(SegmentType::dwell, SegmentLaw::none, 360.0, {})};
  return build_motion_law(c, "test.json");
}

/// The quickstart follower: 0.3 kg, 5 kN/m, 40 N preload.
RigidFollower quickstart_follower(double min_force = 0.0) {
  RigidFollower f;
  f.mass = 0.3;
  f.stiffness = 5000.0;
  f.preload = 40.0;
  f.min_force = min_force;
  return f;
}

double rpm(double omega) { return omega * 30.0 / kPi; }

TEST(LinearProgram, SolvesASmallProgrammeWithAKnownVertex) {
  // max x + y s.t. x + 2y ≤ 4, 3x + y ≤ 6, x, y ≥ 0: vertex (1.6, 1.2).
  LinearProgram lp;
  const int x = lp.add_column(0.0, kLpInfinity, -1.0), y = lp.add_column(0.0, kLpInfinity, -1.0);
  lp.add_row({{x, 1.0}, {y, 2.0}}, -kLpInfinity, 4.0);
  lp.add_row({{x, 3.0}, {y, 1.0}}, -kLpInfinity, 6.0);
  const LpSolution s = solve(lp);
  ASSERT_EQ(s.status, LpStatus::optimal) << s.message;
  EXPECT_NEAR(s.x[x], 1.6, test::kAmplifiedRoundoff);
  EXPECT_NEAR(s.x[y], 1.2, test::kAmplifiedRoundoff);
  EXPECT_NEAR(s.objective, -2.8, test::kAmplifiedRoundoff);
}

TEST(LinearProgram, ReportsInfeasibleAndUnboundedProgrammes) {
  LinearProgram infeasible;
  const int x = infeasible.add_column(0.0, 1.0);
  infeasible.add_row({{x, 1.0}}, 2.0, kLpInfinity);
  EXPECT_EQ(solve(infeasible).status, LpStatus::infeasible);

  LinearProgram unbounded;
  const int y = unbounded.add_column(0.0, kLpInfinity, -1.0);
  unbounded.add_row({{y, 1.0}}, 1.0, kLpInfinity);
  EXPECT_EQ(solve(unbounded).status, LpStatus::unbounded);
}

TEST(LinearProgram, AColumnWithoutNonzerosKeepsItsBounds) {
  LinearProgram lp;
  const int a = lp.add_column(0.0, 1.0, 1.0);
  const int b = lp.add_column(-2.0, 3.0, -1.0);  // in no row
  lp.add_row({{a, 1.0}}, 0.5, kLpInfinity);
  const LpSolution s = solve(lp);
  ASSERT_EQ(s.status, LpStatus::optimal) << s.message;
  EXPECT_NEAR(s.x[a], 0.5, test::kAmplifiedRoundoff);
  EXPECT_NEAR(s.x[b], 3.0, test::kAmplifiedRoundoff);
}

TEST(AnyLawJumpBound, ClosedFormOfTheQuickstartIsAbout2000Rpm) {
  // arccos(0.008 / 0.028) = 1.2811 rad; β √(k/M) = 270.4 rad/s ⇒ 211.1 rad/s.
  const RigidFollower f = quickstart_follower();
  EXPECT_NEAR(rpm(any_law_jump_speed_closed_form(f, 0.0, 0.02, 2.0 * kPi / 3.0)), 2015.5, kQuotedRpm);
}

struct BoundCase {
  const char* name;
  double min_force, stiffness, weight;
};

class AnyLawJumpBoundCases : public ::testing::TestWithParam<BoundCase> {};

TEST_P(AnyLawJumpBoundCases, LinearProgrammeMatchesTheClosedForm) {
  const BoundCase c = GetParam();
  RigidFollower f = quickstart_follower(c.min_force);
  f.stiffness = c.stiffness;
  f.weight = c.weight;
  const MotionLaw law = quickstart_law();
  const std::vector<SegmentJumpBound> b = any_law_jump_bounds(law, f, {0, 2}, 100.0, kGrid);
  ASSERT_EQ(b.size(), 2u);
  const double expected = any_law_jump_speed_closed_form(f, 0.0, 0.02, 2.0 * kPi / 3.0);
  for (const SegmentJumpBound& s : b) {
    EXPECT_NEAR(s.omega / expected, 1.0, kGridTolerance)
        << c.name << ", piece " << s.piece << ": " << s.omega << " against " << expected << " rad/s";
    // The bound is an upper bound of what the cycloidal law itself reaches.
    EXPECT_GT(s.omega, 1.05 * 2.0 * kPi / 3.0 * std::sqrt(0.008 * 5000 / 0.3 / (0.02 * 2 * kPi)));
  }
}

INSTANTIATE_TEST_SUITE_P(Followers, AnyLawJumpBoundCases,
                         ::testing::Values(BoundCase{"spring", 0.0, 5000.0, 0.0},
                                           BoundCase{"spring_min_force", 10.0, 5000.0, 0.0},
                                           BoundCase{"spring_gravity", 0.0, 5000.0, 2.943},
                                           BoundCase{"constant_force", 5.0, 0.0, 0.0},
                                           // 50 N wanted, 40 N at the bottom: decelerate from u = 0.
                                           BoundCase{"short_preload", 50.0, 5000.0, 0.0}),
                         [](const auto& param_info) { return std::string(param_info.param.name); });

TEST(AnyLawJumpBound, ADamperHelpsTheRiseAndHurtsTheReturn) {
  // c ω s' pushes the follower onto the cam where s' > 0 and pulls it off
  // where s' < 0, so the two pieces (time reversals of each other) part:
  // the undamped closed form lies between them.
  RigidFollower f = quickstart_follower();
  f.damping = 20.0;
  const std::vector<SegmentJumpBound> b = any_law_jump_bounds(quickstart_law(), f, {0, 2}, 100.0, kGrid / 2);
  const double undamped = any_law_jump_speed_closed_form(f, 0.0, 0.02, 2.0 * kPi / 3.0);
  EXPECT_GT(b[0].omega, undamped * (1.0 + 2.0 * kGridTolerance));
  EXPECT_LT(b[1].omega, undamped * (1.0 - 2.0 * kGridTolerance));
}

TEST(AnyLawJumpBound, TheLawsOwnWorstMarginVanishesAtItsJumpSpeed) {
  // Cycloidal rise: s'' = 2π h/β² sin(2π x): the margin's minimum is 0 at the
  // rigid jump speed, found here by bisection on the sampled law's worst margin.
  const MotionLaw law = quickstart_law();
  const RigidFollower f = quickstart_follower();
  const SampledLaw sampled(law);
  const double w = highest_feasible_speed([&](double om) { return sampled.worst_margin(f, om) >= 0.0; }, 100.0, 1e4);
  EXPECT_NEAR(rpm(w), 1174.0, 2 * kQuotedRpm);  // docs/model.md §9 for the quickstart: ≈ 1174 rpm, and the sampling
  EXPECT_GT(sampled.worst_margin(f, 0.99 * w), 0.0);
  EXPECT_LT(sampled.worst_margin(f, 1.01 * w), 0.0);
}

}  // namespace
}  // namespace camdyn::optim
