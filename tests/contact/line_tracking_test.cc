// The flat-face (line) reduction of the common-normal tracker against the
// analytic support point of an ellipse.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "contact/line_curve_tracking.h"
#include "test_curves.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// The shared test ellipse, semi-axes 50 and 30 mm (counter-clockwise), star-shaped about the origin.
using test::Ellipse;
constexpr double kLineSemiA = 0.05, kLineSemiB = 0.03;

/// A face whose normal m (towards the ellipse) makes angle `angle` with −y, at distance `h` above the ellipse.
struct Face {
  Eigen::Vector2d p, m;
};
Face face(const Ellipse& e, double angle, double h) {
  const Eigen::Vector2d m(std::sin(angle), -std::cos(angle));
  // The ellipse's support value in direction −m is sqrt(a² m_x² + b² m_y²).
  const double support = std::sqrt(e.a() * e.a() * m.x() * m.x() + e.b() * e.b() * m.y() * m.y());
  return {-(support + h) * m, m};
}

TEST(LineTracking, ResidualDerivativeMatchesFiniteDifference) {
  const Ellipse e(kLineSemiA, kLineSemiB);
  const Face f = face(e, 0.3, 0.01);
  for (double u : {0.1, 0.7, 2.0, 4.0}) {
    const double h = 1e-6;
    const double fd = (evaluate_line_pair(e, f.p, f.m, u + h).f - evaluate_line_pair(e, f.p, f.m, u - h).f) / (2 * h);
    EXPECT_NEAR(evaluate_line_pair(e, f.p, f.m, u).f_u, fd, test::kFiniteDifference * std::abs(fd) + test::kRoundoff);
  }
}

TEST(LineTracking, NewtonAndGlobalFindTheSupportPointAndTheExactGap) {
  const Ellipse e(kLineSemiA, kLineSemiB);
  for (double angle : {0.0, 0.4, -1.0, 2.5}) {
    for (double h : {0.01, 1e-6, -2e-5}) {  // apart, nearly touching, interfering
      const Face f = face(e, angle, h);
      // Support point in direction −m: u* = atan2(−b m_y, −a m_x).
      const double u_star = std::atan2(-e.b() * f.m.y(), -e.a() * f.m.x());
      double u = 0.0;
      TrackedPair pair;
      ASSERT_TRUE(global_line_pair(e, f.p, f.m, u_star + 0.5, u, pair)) << angle;
      EXPECT_NEAR(std::remainder(u - u_star, 2 * std::numbers::pi), 0.0, test::kAmplifiedRoundoff) << angle;
      EXPECT_NEAR(pair.gap, h, test::kRoundoff * test::kLengthScale) << angle;
      EXPECT_NEAR(pair.normal.dot(f.m), -1.0, test::kAmplifiedRoundoff);  // normals opposed
      double v = u_star + 0.2;
      ASSERT_TRUE(newton_track_line(e, f.p, f.m, v, pair));
      EXPECT_NEAR(std::remainder(v - u_star, 2 * std::numbers::pi), 0.0, test::kAmplifiedRoundoff);
    }
  }
}

TEST(LineTracking, NewtonRejectsTheFarSideOfTheProfile) {
  const Ellipse e(kLineSemiA, kLineSemiB);
  const Face f = face(e, 0.0, 0.01);  // face above the ellipse: the support point is at u = π/2
  double u = -std::numbers::pi / 2;   // the bottom: a maximum of m·r, not a support point
  TrackedPair pair;
  EXPECT_FALSE(newton_track_line(e, f.p, f.m, u, pair));
}

}  // namespace
}  // namespace camdyn
