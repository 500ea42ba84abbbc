// The any-law lift-area bound (optim/optimize/lobe_bound.h) against a closed
// form. On a dwell at s = 0, the undamped rigid follower at one speed ω
// keeps P ≥ P_min iff u'' ≥ −λ² u with u = s + u₀, u₀ = (F₀ − P_min) / k and
// λ² = k / (M ω²). Among the lifts with s = 0 at both ends of an event of
// β < π / λ, w = u − U with U = u₀ cos(λ(θ − β/2)) / cos(λβ/2) has
// w'' + λ² w ≥ 0 and w = 0 at the ends, so w ≤ 0 (maximum principle with
// the positive cos(λ(θ − β/2))): U is the most lift anywhere, and its area
// A = 2 u₀ tan(λβ/2) / λ − u₀ β is the bound. The lift jumps in slope at the
// ends, which the programme allows (it bounds s'' from below only).
#include "optim/optimize/lobe_bound.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace camdyn::optim {
namespace {

MotionLaw dwell_law() { return MotionLaw({MotionLaw::Piece{0.0, 2.0 * std::numbers::pi, 0.0, 0.0, nullptr}}); }

RigidFollower follower() {
  RigidFollower f;
  f.mass = 0.09;
  f.stiffness = 35000.0;
  f.preload = 250.0;
  f.min_force = 50.0;
  return f;
}

TEST(LiftAreaBound, MatchesTheClosedFormOfTheUndampedSpringLimit) {
  // Above the study's red line: at 3500 rpm λβ > π and the spring alone
  // would hold any lift.
  const RigidFollower f = follower();
  const double omega = 6000.0 * std::numbers::pi / 30.0;
  const double lambda = std::sqrt(f.stiffness / (f.mass * omega * omega));
  const double u0 = (f.preload - f.min_force) / f.stiffness;
  const double from = 10.0 * std::numbers::pi / 180.0, to = 140.0 * std::numbers::pi / 180.0;
  const double beta = to - from;
  ASSERT_LT(lambda * beta, std::numbers::pi);
  const double exact = 2.0 * u0 * std::tan(0.5 * lambda * beta) / lambda - u0 * beta;
  LobeLimits limits;
  limits.omegas = {0.0, omega};
  double previous = 0.0;
  for (const int grid : {200, 400, 800}) {
    const LobeBound b = lift_area_bound(dwell_law(), from, to, f, limits, grid);
    ASSERT_TRUE(b.solved) << b.status;
    // Second-order differences: the error falls as 1/N²; at N = 200 the
    // stencil's error in s'' is h² u'''' / 12 ≈ 1e-6 of u'' (h ≈ 0.011 rad).
    EXPECT_NEAR(b.area, exact, 2e-4 * exact) << "grid " << grid;
    if (grid > 200) {
      EXPECT_LT(std::abs(b.area - exact), std::abs(previous - exact) + 1e-12 * exact);
    }
    previous = b.area;
    // The optimum is the extremal: U at the middle.
    const double middle = b.lift[static_cast<std::size_t>(grid / 2)];
    EXPECT_NEAR(middle, u0 / std::cos(0.5 * lambda * beta) - u0, 1e-3 * middle);
  }
}

// A lift cap that binds: the bound is the capped extremal's area, less than
// both the cap times the span and the uncapped bound, and the lift never
// passes the cap.
TEST(LiftAreaBound, HoldsTheLiftCapAndOtherLimits) {
  const RigidFollower f = follower();
  const double omega = 6000.0 * std::numbers::pi / 30.0;
  const double from = 10.0 * std::numbers::pi / 180.0, to = 140.0 * std::numbers::pi / 180.0;
  LobeLimits limits;
  limits.omegas = {0.0, omega};
  const LobeBound free = lift_area_bound(dwell_law(), from, to, f, limits, 400);
  limits.max_lift = 0.009;
  limits.face_limit = 0.019;
  limits.pitch_height = 0.018;
  limits.min_radius = 0.005;
  limits.max_jerk = 1.0;
  const LobeBound capped = lift_area_bound(dwell_law(), from, to, f, limits, 400);
  ASSERT_TRUE(capped.solved);
  EXPECT_LT(capped.area, free.area);
  EXPECT_LT(capped.area, 0.009 * (to - from));
  const double h = (to - from) / 400;
  for (std::size_t i = 1; i + 1 < capped.lift.size(); ++i) {
    const double s = capped.lift[i];
    const double ds = (capped.lift[i + 1] - capped.lift[i - 1]) / (2 * h);
    const double d2s = (capped.lift[i + 1] - 2 * s + capped.lift[i - 1]) / (h * h);
    EXPECT_LE(s, 0.009 * (1 + 1e-9));
    EXPECT_LE(std::abs(ds), 0.019 * (1 + 1e-7));
    EXPECT_GE(0.018 + s + d2s, 0.005 * (1 - 1e-7));
    EXPECT_GE(f.margin(omega, {s, ds, d2s, 0.0, 0.0}), -1e-6);
  }
}

TEST(LiftAreaBound, SaysWhenNoLiftMeetsTheConstraints) {
  // At rest the spring holds the follower with P_min only above
  // s = (P_min − F₀) / k = 1.43 mm, and the cap is 1 mm.
  RigidFollower f = follower();
  f.min_force = 300.0;
  LobeLimits limits;
  limits.omegas = {0.0};
  limits.max_lift = 0.001;
  const LobeBound b = lift_area_bound(dwell_law(), 0.2, 2.0, f, limits, 100);
  EXPECT_FALSE(b.solved);
  EXPECT_EQ(b.status, "infeasible");
}

}  // namespace
}  // namespace camdyn::optim
