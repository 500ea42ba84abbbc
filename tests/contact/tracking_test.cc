// The one-parameter common-normal tracker against analytic distances.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/point_curve_tracking.h"
#include "test_curves.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// The shared test ellipse, semi-axes 50 and 30 mm (counter-clockwise), star-shaped about the origin.
using test::Ellipse;
constexpr double kSemiA = 0.05, kSemiB = 0.03;

TEST(Tracking, ResidualDerivativeMatchesFiniteDifference) {
  const Ellipse e(kSemiA, kSemiB);
  const Eigen::Vector2d c(0.06, 0.02);
  for (double u : {0.1, 0.7, 2.0, 4.0}) {
    const double h = 1e-6;
    const double fd = (evaluate_pair(e, c, u + h).f - evaluate_pair(e, c, u - h).f) / (2 * h);
    EXPECT_NEAR(evaluate_pair(e, c, u).f_u, fd, test::kFiniteDifference * std::abs(fd) + test::kRoundoff);
  }
}

TEST(Tracking, GapOnEllipseAxesIsExact) {
  const Ellipse e(kSemiA, kSemiB);
  TrackedPair pair;
  double u = 0.0;
  // A point outside the ellipse on its major axis: gap = x − a; inside: negative.
  for (double x : {0.07, 0.051, 0.0499}) {
    ASSERT_TRUE(global_pair(e, Eigen::Vector2d(x, 0.0), 0.0, u, pair));
    EXPECT_NEAR(pair.gap, x - e.a(), test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR(std::remainder(u, 2 * std::numbers::pi), 0.0, test::kAmplifiedRoundoff);
  }
}

TEST(Tracking, NewtonFindsTheFootPointOfAGeneralPoint) {
  const Ellipse e(kSemiA, kSemiB);
  const Eigen::Vector2d c(0.04, 0.035);
  double u = 1.0;
  TrackedPair pair;
  ASSERT_TRUE(newton_track(e, c, u, pair));
  // The foot point: c − P(u) is parallel to the normal, and |gap| = distance.
  EXPECT_NEAR(std::abs(pair.f), 0.0, test::kRoundoff * test::kLengthScale * test::kLengthScale);
  EXPECT_NEAR(std::abs(pair.gap), (c - pair.point).norm(), test::kRoundoff * test::kLengthScale);
  // Brute force minimum distance over a fine sampling agrees, to what samples
  // 1.6 µm apart can miss of a smooth minimum.
  constexpr double kSampling = 1e-10;  // [m]
  double best = INFINITY;
  for (int i = 0; i < 200000; ++i) best = std::min(best, (c - e.at(2 * std::numbers::pi * i / 200000).r).norm());
  EXPECT_NEAR(pair.gap, best, kSampling);
}

TEST(Tracking, GlobalPairStaysOnTheBranchNearTheReference) {
  const Ellipse e(kSemiA, kSemiB);
  double u = 0.0;
  TrackedPair pair;
  const double ref = 10 * std::numbers::pi + 0.3;  // five turns on
  ASSERT_TRUE(global_pair(e, Eigen::Vector2d(0.05, 0.01), ref, u, pair));
  EXPECT_LT(std::abs(u - ref), std::numbers::pi);
}

}  // namespace
}  // namespace camdyn
