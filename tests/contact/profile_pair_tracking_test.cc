// The general two-parameter common-normal tracker (docs/model.md §2) against
// analytic distances (ellipse–circle by Eberly's robust root, symmetric
// ellipse pairs, a flat face on a turned ellipse, a concave flank), against
// finite differences (Jacobian, time derivatives), through first contact,
// under differential tracking, and against the one-parameter circle
// reduction on a roller cam.
#include "contact/profile_pair_tracking.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>
#include <vector>

#include "allocation_counter.h"
#include "common/constants.h"
#include "contact/point_curve_tracking.h"
#include "geometry/cam_roller.h"
#include "geometry/motion_law.h"
#include "test_curves.h"
#include "tests/geometry/finite_difference.h"
#include "tests/geometry/law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// Tolerance levels.
// Closed-form gaps: both sides are computed to a few ulps of the body size (0.1 m).
constexpr double kAnalyticGap = 1e-12;  // [m]
// The acceptance level of the issue for the ellipse–circle distance.
constexpr double kAcceptanceGap = 1e-10;  // [m]

using test::Ellipse;

/// Polar curve r(φ) = R (1 + ε cos kφ) (counterclockwise): concave near the
/// minima of r when ε k² > 1 − ε.
class Lobed final : public PeriodicCurve {
 public:
  Lobed(double radius, double eps, int k) : radius_(radius), eps_(eps), k_(k) {}
  double rho(double phi, int order) const {
    const double kk = k_, c = std::cos(kk * phi), s = std::sin(kk * phi);
    switch (order) {
      case 0:
        return radius_ * (1 + eps_ * c);
      case 1:
        return -radius_ * eps_ * kk * s;
      case 2:
        return -radius_ * eps_ * kk * kk * c;
      default:
        return radius_ * eps_ * kk * kk * kk * s;
    }
  }
  CurvePoint at(double phi) const override {
    // r = ρ e(φ) with e' = J e: r^(n) = Σ C(n,k) ρ^(n−k) e^(k), e'' = −e, e''' = −J e.
    const Eigen::Vector2d e(std::cos(phi), std::sin(phi)), je(-e.y(), e.x());
    const double r0 = rho(phi, 0), r1 = rho(phi, 1), r2 = rho(phi, 2), r3 = rho(phi, 3);
    return {r0 * e, r1 * e + r0 * je, r2 * e + 2 * r1 * je - r0 * e, r3 * e + 3 * r2 * je - 3 * r1 * e - r0 * je};
  }
  /// Signed curvature of a polar curve (> 0 convex), the textbook formula.
  double curvature(double phi) const {
    const double r0 = rho(phi, 0), r1 = rho(phi, 1), r2 = rho(phi, 2);
    return (r0 * r0 + 2 * r1 * r1 - r0 * r2) / std::pow(r0 * r0 + r1 * r1, 1.5);
  }

 private:
  double radius_, eps_;
  int k_;
};

// ------------------------------------------------ independent reference: Eberly

/// Root of F(s) = (r0 z0 / (s + r0))² + (z1 / (s + 1))² − 1 by bisection
/// (D. Eberly, "Distance from a point to an ellipse, an ellipsoid, or a
/// hyperellipsoid", Geometric Tools, 2013, GetRoot).
double eberly_root(double r0, double z0, double z1, double g) {
  const double n0 = r0 * z0;
  double s0 = z1 - 1, s1 = g < 0 ? 0 : std::hypot(n0, z1) - 1, s = 0;
  for (int i = 0; i < 2000; ++i) {
    s = 0.5 * (s0 + s1);
    if (s == s0 || s == s1) break;
    const double ratio0 = n0 / (s + r0), ratio1 = z1 / (s + 1);
    const double gs = ratio0 * ratio0 + ratio1 * ratio1 - 1;
    if (gs > 0)
      s0 = s;
    else if (gs < 0)
      s1 = s;
    else
      break;
  }
  return s;
}

/// Signed distance (> 0 outside) from y to the ellipse x²/e0² + y²/e1² = 1,
/// e0 ≥ e1, and the closest point. Eberly's DistancePointEllipse, any quadrant.
double eberly_signed_distance(double e0, double e1, Eigen::Vector2d y, Eigen::Vector2d* closest = nullptr) {
  const double sx = y.x() < 0 ? -1 : 1, sy = y.y() < 0 ? -1 : 1;
  const double y0 = std::abs(y.x()), y1 = std::abs(y.y());
  double x0 = 0, x1 = 0, distance = 0;
  if (y1 > 0) {
    if (y0 > 0) {
      const double z0 = y0 / e0, z1 = y1 / e1, g = z0 * z0 + z1 * z1 - 1;
      if (g != 0) {
        const double r0 = (e0 / e1) * (e0 / e1);
        const double sbar = eberly_root(r0, z0, z1, g);
        x0 = r0 * y0 / (sbar + r0);
        x1 = y1 / (sbar + 1);
        distance = std::hypot(x0 - y0, x1 - y1);
      } else {
        x0 = y0;
        x1 = y1;
      }
    } else {
      x0 = 0;
      x1 = e1;
      distance = std::abs(y1 - e1);
    }
  } else {
    const double numer0 = e0 * y0, denom0 = e0 * e0 - e1 * e1;
    if (numer0 < denom0) {
      const double xde0 = numer0 / denom0;
      x0 = e0 * xde0;
      x1 = e1 * std::sqrt(1 - xde0 * xde0);
      distance = std::hypot(x0 - y0, x1);
    } else {
      x0 = e0;
      x1 = 0;
      distance = std::abs(y0 - e0);
    }
  }
  if (closest != nullptr) *closest = Eigen::Vector2d(sx * x0, sy * x1);
  const bool inside = (y0 / e0) * (y0 / e0) + (y1 / e1) * (y1 / e1) < 1;
  return inside ? -distance : distance;
}

Eigen::Matrix2d rot(double angle) {
  Eigen::Matrix2d r;
  r << std::cos(angle), -std::sin(angle), std::sin(angle), std::cos(angle);
  return r;
}

// ------------------------------------------------ ellipse against circle

struct CircleCase {
  double angle_a;             // ellipse orientation [rad]
  double centre_x, centre_y;  // circle centre in the ellipse frame [m]
  double radius;              // [m]
};

class ProfilePairEllipseCircle : public ::testing::TestWithParam<CircleCase> {};

TEST_P(ProfilePairEllipseCircle, GapMatchesEberlyDistanceMinusRadius) {
  const CircleCase c = GetParam();
  const Ellipse ellipse(0.05, 0.03);
  const ClosedCurveProfile a(ellipse);
  const CircleProfile b(c.radius);
  const Eigen::Vector2d p_a(0.01, -0.02);
  const BodyMotion ma = BodyMotion::make(c.angle_a, p_a);
  const Eigen::Vector2d centre_A(c.centre_x, c.centre_y);
  const BodyMotion mb = BodyMotion::make(0.3, rot(c.angle_a) * centre_A + p_a);
  Eigen::Vector2d foot_A;
  const double expected = eberly_signed_distance(0.05, 0.03, centre_A, &foot_A) - c.radius;

  PairTrackerWorkspace ws(a, b);
  double u = 0, v = 0;
  PairEvaluation pair;
  ASSERT_TRUE(global_profile_pair(a, b, ma, mb, 0.0, 0.0, ws, u, v, pair));
  EXPECT_NEAR(pair.gap, expected, kAcceptanceGap);
  EXPECT_NEAR(pair.gap, expected, kAnalyticGap) << "tighter than the acceptance level";
  EXPECT_LT((pair.point_A_W - (rot(c.angle_a) * foot_A + p_a)).norm(), 1e-9) << "the foot point";
  EXPECT_TRUE(pair.valid());
  EXPECT_NEAR(pair.normal_W.dot(pair.normal_B_W), -1.0, test::kRoundoff);
  EXPECT_LT(std::abs(pair.f(0)), 1e-15);
  EXPECT_LT(std::abs(pair.f(1)), 1e-13);
  EXPECT_EQ(ws.global_searches, 1);
}

INSTANTIATE_TEST_SUITE_P(ApartTouchingAndInterfering, ProfilePairEllipseCircle,
                         ::testing::Values(CircleCase{0.0, 0.09, 0.0, 0.01},       // on the major axis, apart
                                           CircleCase{0.4, 0.04, 0.045, 0.01},     // general point, apart
                                           CircleCase{-1.2, -0.03, -0.04, 0.015},  // third quadrant
                                           CircleCase{2.0, 0.051, 0.012, 0.008},   // interfering (depth < radius)
                                           CircleCase{0.7, 0.0, 0.035, 0.01},      // on the minor axis, interfering
                                           CircleCase{0.0, 0.046, 0.0, 0.01}));    // centre inside the ellipse

// ------------------------------------------------ ellipse against ellipse

struct EllipsePairCase {
  double turn;       // both bodies turned by this about the origin [rad]
  double b_angle;    // B's own orientation relative to A [rad]: 0 or π/2
  double direction;  // B's centre on A's x axis (0) or y axis (π/2) [rad]
  double distance;   // centre distance [m]
};

class ProfilePairEllipseEllipse : public ::testing::TestWithParam<EllipsePairCase> {};

TEST_P(ProfilePairEllipseEllipse, SymmetricPairGapIsCentreDistanceMinusSemiAxes) {
  const EllipsePairCase c = GetParam();
  const Ellipse ea(0.05, 0.03), eb(0.025, 0.015);
  const ClosedCurveProfile a(ea), b(eb);
  const BodyMotion ma = BodyMotion::make(c.turn);
  const Eigen::Vector2d dir(std::cos(c.direction), std::sin(c.direction));
  const BodyMotion mb = BodyMotion::make(c.turn + c.b_angle, rot(c.turn) * (c.distance * dir));
  // Extent of each body along the centre line.
  const bool a_major = std::abs(dir.x()) > 0.5;
  const bool b_major = a_major == (std::abs(std::cos(c.b_angle)) > 0.5);
  const double expected = c.distance - (a_major ? 0.05 : 0.03) - (b_major ? 0.025 : 0.015);
  PairTrackerWorkspace ws(a, b);
  double u = 0, v = 0;
  PairEvaluation pair;
  ASSERT_TRUE(global_profile_pair(a, b, ma, mb, 0.0, 0.0, ws, u, v, pair));
  EXPECT_NEAR(pair.gap, expected, kAnalyticGap);
  EXPECT_TRUE(pair.valid());
  // The pair lies on the centre line: A's vertex.
  EXPECT_LT((pair.point_A_W - rot(c.turn) * ((a_major ? 0.05 : 0.03) * dir)).norm(), 1e-9);
  if (expected < 0) {
    EXPECT_GT(-pair.gap, 0.0) << "interference depth";
  }
}

INSTANTIATE_TEST_SUITE_P(AxesAlignedAndCrossed, ProfilePairEllipseEllipse,
                         ::testing::Values(EllipsePairCase{0.0, 0.0, 0.0, 0.09}, EllipsePairCase{0.8, 0.0, 0.0, 0.0745},
                                           EllipsePairCase{-0.3, kPi / 2, 0.0, 0.07},
                                           EllipsePairCase{1.1, kPi / 2, 0.0, 0.0640},
                                           EllipsePairCase{0.0, 0.0, kPi / 2, 0.05},
                                           EllipsePairCase{2.5, 0.0, kPi / 2, 0.0447}));

// ------------------------------------------------ flat face and mushroom arc

TEST(ProfilePairFlatFace, GapIsFaceHeightMinusSupportOfTurnedEllipse) {
  const double a = 0.05, b = 0.03;
  const Ellipse ellipse(a, b);
  const ClosedCurveProfile cam(ellipse);
  const SegmentProfile face(Eigen::Vector2d::Zero(), Eigen::Vector2d(0, -1), 0.04);
  PairTrackerWorkspace ws(cam, face);
  for (double beta : {0.0, 0.3, 1.0, 2.2}) {
    for (double height : {0.06, 0.045, 0.04}) {
      // Support height of the turned ellipse in +y: sqrt(a² sin²β + b² cos²β).
      const double support = std::hypot(a * std::sin(beta), b * std::cos(beta));
      const BodyMotion mc = BodyMotion::make(beta), mf = BodyMotion::make(0.0, Eigen::Vector2d(0.0, height));
      double u = 0, v = 0;
      PairEvaluation pair;
      ASSERT_TRUE(global_profile_pair(cam, face, mc, mf, 0.0, 0.0, ws, u, v, pair));
      EXPECT_NEAR(pair.gap, height - support, kAnalyticGap) << "β = " << beta << ", height " << height;
      EXPECT_NEAR(pair.normal_W.y(), 1.0, test::kRoundoff);
      EXPECT_EQ(pair.curvature_B, 0.0);
    }
  }
}

TEST(ProfilePairFlatFace, ContactBeyondTheFaceIsOutOfDomain) {
  const Ellipse ellipse(0.05, 0.03);
  const ClosedCurveProfile cam(ellipse);
  // A narrow face shifted to the side: the common normal meets its line outside it.
  const SegmentProfile face(Eigen::Vector2d(0.02, 0.0), Eigen::Vector2d(0, -1), 0.005);
  const BodyMotion mc = BodyMotion::make(0.0), mf = BodyMotion::make(0.0, Eigen::Vector2d(0.0, 0.031));
  double u = kPi / 2, v = -0.02;  // the true pair: the ellipse's top, face parameter −0.02
  PairEvaluation pair;
  EXPECT_EQ(newton_profile_pair(cam, face, mc, mf, u, v, pair), PairStatus::out_of_domain);
  EXPECT_NEAR(v, -0.02, test::kAmplifiedRoundoff);
}

TEST(ProfilePairMushroom, ArcAgainstEllipseMatchesEberly) {
  const Ellipse ellipse(0.05, 0.03);
  const ClosedCurveProfile cam(ellipse);
  const double big_r = 0.1;  // mushroom face radius [m], its lower arc
  const ArcProfile mushroom(big_r, Eigen::Vector2d::Zero(), -kPi / 2 - 0.4, -kPi / 2 + 0.4);
  PairTrackerWorkspace ws(cam, mushroom);
  for (double beta : {0.2, 1.3}) {
    const Eigen::Vector2d centre(0.004, 0.03 + big_r + 0.002);
    const BodyMotion mc = BodyMotion::make(beta), mm = BodyMotion::make(0.0, centre);
    const double expected = eberly_signed_distance(0.05, 0.03, rot(-beta) * centre) - big_r;
    double u = 0, v = -kPi / 2;
    PairEvaluation pair;
    ASSERT_TRUE(global_profile_pair(cam, mushroom, mc, mm, 0.0, -kPi / 2, ws, u, v, pair));
    EXPECT_NEAR(pair.gap, expected, kAcceptanceGap);
    EXPECT_GT(v, -kPi / 2 - 0.4);
    EXPECT_LT(v, -kPi / 2 + 0.4);
  }
}

// ------------------------------------------------ concave flank

// r(φ) = 0.04 (1 + 0.15 cos 3φ): concave around φ = 60°, 180°, 300°, where
// r = 0.034 m and the radius of curvature is −0.0578 m (symmetric about the ray).
const Lobed kLobed(0.04, 0.15, 3);

TEST(ProfilePairConcave, SmallRollerInTheHollowTouchesItsBottom) {
  const ClosedCurveProfile cam(kLobed);
  const double rho = 0.02, r_min = 0.04 * 0.85;
  ASSERT_LT(kLobed.curvature(kPi / 3), 0.0);
  ASSERT_GT(-1.0 / kLobed.curvature(kPi / 3), rho) << "the roller fits the hollow";
  const CircleProfile roller(rho);
  PairTrackerWorkspace ws(cam, roller);
  for (double turn : {0.0, 0.9}) {
    for (double gap : {1e-3, 0.0, -5e-4}) {
      // Roller centre on the symmetry ray φ = 60° (turned with the cam).
      const Eigen::Vector2d centre = rot(turn) * ((r_min + rho + gap) * Eigen::Vector2d(0.5, std::sqrt(3.0) / 2));
      const BodyMotion mc = BodyMotion::make(turn), mr = BodyMotion::make(0.0, centre);
      double u = 0, v = 0;
      PairEvaluation pair;
      ASSERT_TRUE(global_profile_pair(cam, roller, mc, mr, 0.0, 0.0, ws, u, v, pair));
      EXPECT_NEAR(pair.gap, gap, kAnalyticGap);
      EXPECT_NEAR(std::remainder(u - kPi / 3, kTwoPi), 0.0, test::kConverged) << "the bottom of the hollow";
      EXPECT_LT(pair.curvature_A, 0.0);
      EXPECT_TRUE(pair.valid());
    }
  }
}

/// Distance from c to the lobed curve: dense sampling, then golden section (independent of the tracker).
double brute_force_distance(const Lobed& curve, const Eigen::Vector2d& c) {
  const int n = 20000;
  int best = 0;
  double best_d = INFINITY;
  for (int i = 0; i < n; ++i) {
    const double d = (curve.at(kTwoPi * i / n).r - c).norm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  double lo = kTwoPi * (best - 1) / n, hi = kTwoPi * (best + 1) / n;
  const auto dist = [&](double x) { return (curve.at(x).r - c).norm(); };
  for (int it = 0; it < 200; ++it) {
    const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    if (dist(m1) < dist(m2))
      hi = m2;
    else
      lo = m1;
  }
  return dist(0.5 * (lo + hi));
}

TEST(ProfilePairConcave, LargeRollerCannotFollowTheHollowAndBridgesIt) {
  const ClosedCurveProfile cam(kLobed);
  const double rho = 0.08, r_min = 0.04 * 0.85;  // larger than the hollow's 0.0578 m radius
  const CircleProfile roller(rho);
  const Eigen::Vector2d ray(0.5, std::sqrt(3.0) / 2);
  const Eigen::Vector2d centre = (r_min + rho) * ray;  // touching the bottom of the hollow
  const BodyMotion mc = BodyMotion::make(0.0), mr = BodyMotion::make(0.0, centre);
  // The pair at the bottom solves f = 0 but is not a distance minimum.
  double u = kPi / 3, v = kPi / 3 + kPi;
  PairEvaluation pair;
  EXPECT_EQ(newton_profile_pair(cam, roller, mc, mr, u, v, pair), PairStatus::invalid);
  EXPECT_NEAR(pair.gap, 0.0, kAnalyticGap);
  EXPECT_LT(pair.relative_curvature, 0.0);
  // The valid pairs are on the flanks, where the roller interferes.
  PairTrackerWorkspace ws(cam, roller);
  ASSERT_TRUE(global_profile_pair(cam, roller, mc, mr, 0.0, 0.0, ws, u, v, pair));
  EXPECT_GT(std::abs(std::remainder(u - kPi / 3, kTwoPi)), 0.05);
  EXPECT_NEAR(pair.gap, brute_force_distance(kLobed, centre) - rho, kAcceptanceGap);
  EXPECT_LT(pair.gap, 0.0);
}

// ------------------------------------------------ derivatives

/// A scene with both bodies moving: A turns about a moving origin, B turns and slides.
struct MovingScene {
  double t0 = 0.2;
  BodyMotion a(double t) const {
    return BodyMotion::make(0.3 + 7.0 * t, Eigen::Vector2d(0.01 + 0.02 * t, -0.005 * t), 7.0,
                            Eigen::Vector2d(0.02, -0.005));
  }
  BodyMotion b(double t) const {
    return BodyMotion::make(-0.4 - 3.0 * t, Eigen::Vector2d(0.06 - 0.01 * t, 0.05 + 0.03 * t), -3.0,
                            Eigen::Vector2d(-0.01, 0.03));
  }
};

TEST(ProfilePairDerivatives, JacobianAndTimeDerivativesMatchFiniteDifferences) {
  const Ellipse ea(0.05, 0.03), eb(0.025, 0.015);
  const ClosedCurveProfile a(ea), b(eb);
  const MovingScene scene;
  const BodyMotion ma = scene.a(scene.t0), mb = scene.b(scene.t0);
  for (const std::pair<double, double>& uv : {std::pair{0.4, 3.3}, std::pair{1.7, 5.0}, std::pair{-2.0, 0.2}}) {
    const double u = uv.first, v = uv.second;  // (clang 14 cannot capture structured bindings)
    const PairEvaluation p = evaluate_profile_pair(a, b, ma, mb, u, v);
    for (int row = 0; row < 2; ++row) {
      const double scale = row == 0 ? 0.1 : 1.0;  // |f1| ≲ 0.1 m, |f2| ≤ 1
      const auto fu = test::central_difference(
          [&](double x) { return evaluate_profile_pair(a, b, ma, mb, x, v).f(row); }, u, 1e-4, scale);
      const auto fv = test::central_difference(
          [&](double x) { return evaluate_profile_pair(a, b, ma, mb, u, x).f(row); }, v, 1e-4, scale);
      const auto ft = test::central_difference(
          [&](double t) { return evaluate_profile_pair(a, b, scene.a(t), scene.b(t), u, v).f(row); }, scene.t0, 1e-5,
          scale);
      EXPECT_NEAR(p.jacobian(row, 0), fu.value, fu.tolerance) << "∂f" << row + 1 << "/∂u at " << u << ", " << v;
      EXPECT_NEAR(p.jacobian(row, 1), fv.value, fv.tolerance) << "∂f" << row + 1 << "/∂v";
      EXPECT_NEAR(p.f_t(row), ft.value, ft.tolerance) << "∂f" << row + 1 << "/∂t";
    }
    const auto gt = test::central_difference(
        [&](double t) { return evaluate_profile_pair(a, b, scene.a(t), scene.b(t), u, v).gap; }, scene.t0, 1e-5, 0.1);
    EXPECT_NEAR(p.gap_rate, gt.value, gt.tolerance) << "∂g/∂t";
  }
}

// ------------------------------------------------ tracking in time

/// An ellipse cam turning at ω against a circle follower that descends
/// through first contact and on into interference.
struct DescendingScene {
  Ellipse ellipse{0.05, 0.03};
  double omega = 2.0;  // [rad/s]
  double rho = 0.01;   // [m]
  BodyMotion cam(double t) const { return BodyMotion::make(omega * t, Eigen::Vector2d::Zero(), omega); }
  // Centre height 0.09 → 0.05 over 1 s, while the cam's extent along +y
  // grows from 0.03 to 0.047: from a 50 mm gap into interference.
  BodyMotion roller(double t) const {
    return BodyMotion::make(0.0, Eigen::Vector2d(0.004, 0.09 - 0.04 * t), 0.0, Eigen::Vector2d(0.0, -0.04));
  }
  double exact_gap(double t) const {
    const Eigen::Vector2d c = rot(-omega * t) * roller(t).position;
    return eberly_signed_distance(0.05, 0.03, c) - rho;
  }
};

/// The descending scene's profiles, with the pair found by the global search at t = 0.
class ProfilePairTracking : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(global_profile_pair(a, b, s.cam(0), s.roller(0), kPi / 2, -kPi / 2, ws, u, v, pair));
  }
  const DescendingScene s{};
  const ClosedCurveProfile a{s.ellipse};
  const CircleProfile b{s.rho};
  PairTrackerWorkspace ws{a, b};
  double u = 0, v = 0;
  PairEvaluation pair;
};

TEST_F(ProfilePairTracking, WarmNewtonIsContinuousThroughFirstContact) {
  const int steps = 2000;
  double prev_u = u, prev_v = v, prev_gap = pair.gap, max_du = 0, max_dv = 0;
  double du_at_contact = -1, dv_at_contact = -1;
  int crossings = 0;
  for (int i = 1; i <= steps; ++i) {
    const double t = static_cast<double>(i) / steps;
    PairNewtonOptions opts;
    opts.max_iterations = 4;
    ASSERT_EQ(newton_profile_pair(a, b, s.cam(t), s.roller(t), u, v, pair, opts), PairStatus::converged) << "t = " << t;
    ASSERT_NEAR(pair.gap, s.exact_gap(t), kAcceptanceGap) << "t = " << t;
    const double du = std::abs(u - prev_u), dv = std::abs(v - prev_v);
    max_du = std::max(max_du, du);
    max_dv = std::max(max_dv, dv);
    if ((prev_gap > 0) != (pair.gap > 0)) {
      ++crossings;
      du_at_contact = du;
      dv_at_contact = dv;
    }
    prev_u = u;
    prev_v = v;
    prev_gap = pair.gap;
  }
  EXPECT_EQ(ws.global_searches, 1);
  ASSERT_GE(crossings, 1) << "the follower must pass through first contact; final gap " << prev_gap;
  EXPECT_LT(prev_gap, 0.0);
  // Smooth motion: per step (u, v) move by about ω Δt = 1e-3 rad; no jump at g = 0.
  EXPECT_LT(max_du, 5e-3);
  EXPECT_LT(max_dv, 5e-3);
  EXPECT_LT(du_at_contact, 5e-3);
  EXPECT_LT(dv_at_contact, 5e-3);
}

/// Result of integrating (u, v) with the tracker's rates by classic RK4.
struct Rk4Run {
  double max_f1 = 0;         ///< largest |f1| after each step [m]
  double max_gap_error = 0;  ///< largest |g − exact| [m]
  Eigen::Vector2d f_end = Eigen::Vector2d::Zero();
};

Rk4Run integrate_pair(const DescendingScene& s, const PairProfile& a, const PairProfile& b, double u, double v,
                      double alpha, int steps, double t_end) {
  Rk4Run run;
  double x[2] = {u, v};
  const auto rate = [&](double t, const double* y, double* dy) {
    const PairEvaluation p = evaluate_profile_pair(a, b, s.cam(t), s.roller(t), y[0], y[1]);
    EXPECT_EQ(profile_pair_rates(p, alpha, dy[0], dy[1]), PairStatus::converged);
  };
  const double h = t_end / steps;
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    double k1[2], k2[2], k3[2], k4[2], y[2];
    rate(t, x, k1);
    for (int j = 0; j < 2; ++j) y[j] = x[j] + 0.5 * h * k1[j];
    rate(t + 0.5 * h, y, k2);
    for (int j = 0; j < 2; ++j) y[j] = x[j] + 0.5 * h * k2[j];
    rate(t + 0.5 * h, y, k3);
    for (int j = 0; j < 2; ++j) y[j] = x[j] + h * k3[j];
    rate(t + h, y, k4);
    for (int j = 0; j < 2; ++j) x[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
    const PairEvaluation p = evaluate_profile_pair(a, b, s.cam(t + h), s.roller(t + h), x[0], x[1]);
    run.max_f1 = std::max(run.max_f1, std::abs(p.f(0)));
    run.max_gap_error = std::max(run.max_gap_error, std::abs(p.gap - s.exact_gap(t + h)));
    run.f_end = p.f;
  }
  return run;
}

TEST_F(ProfilePairTracking, DifferentialTrackingWithRk4StaysOnTheManifold) {
  for (double alpha : {0.0, 50.0}) {
    // The drift of f is RK4's truncation error: it falls as h⁴ (16× per halving;
    // measured 4.7e-12 → 2.9e-13 m for α = 0, 1.8e-9 → 1.1e-10 m for α = 50,
    // whose stabilising term adds (α h)⁴ terms).
    const Rk4Run coarse = integrate_pair(s, a, b, u, v, alpha, 250, 1.0);
    const Rk4Run fine = integrate_pair(s, a, b, u, v, alpha, 500, 1.0);
    EXPECT_GT(coarse.max_f1 / fine.max_f1, 12.0) << "fourth order, α = " << alpha;
    EXPECT_LT(fine.max_f1, 2e-10) << "α = " << alpha;
    // The gap is stationary on the manifold, so it is insensitive to that drift.
    EXPECT_LT(fine.max_gap_error, kAnalyticGap) << "α = " << alpha;
  }
}

TEST_F(ProfilePairTracking, StabilisationRemovesDriftAtRateAlpha) {
  // Start off the manifold: ḟ = −α f makes f(t) = f(0) e^{−α t} exactly.
  const double alpha = 20.0, t_end = 0.25;
  const double u0 = u + 1e-3, v0 = v - 2e-3;
  const Eigen::Vector2d f0 = evaluate_profile_pair(a, b, s.cam(0), s.roller(0), u0, v0).f;
  const Rk4Run run = integrate_pair(s, a, b, u0, v0, alpha, 1000, t_end);
  const Eigen::Vector2d expected = f0 * std::exp(-alpha * t_end);
  // RK4 with α h = 0.005: relative error of the decay ~ (α h)⁴ / 120 per step, far below 1e-6.
  EXPECT_NEAR(run.f_end(0), expected(0), 1e-6 * std::abs(f0(0)));
  EXPECT_NEAR(run.f_end(1), expected(1), 1e-6 * std::abs(f0(1)));
}

// ------------------------------------------------ against the circle reduction

/// The pitch curve of a roller cam, seen by the one-parameter tracker (which
/// reads `pitch` in older and `at` in newer versions of point_curve_tracking.h).
struct PitchCurve {
  const TranslatingRollerCam* cam;
  CurvePoint pitch(double u) const { return cam->pitch(u); }
  CurvePoint at(double u) const { return cam->pitch(u); }
};

/// The roller cam's contour, the inner offset of the pitch curve P by r_r,
/// with two derivatives (all the tracker reads): C = P − r_r N, and with the
/// pitch's speed λ, unit tangent T, outward normal N and curvature κ
/// (N' = κλT): C' = (1 − r_r κ) P', C'' = (1 − r_r κ) P'' − r_r κ' P'.
class RollerCamContour final : public PeriodicCurve {
 public:
  explicit RollerCamContour(const TranslatingRollerCam& cam) : cam_(&cam) {}
  CurvePoint at(double u) const override {
    const CurvePoint p = cam_->pitch(u);
    const double sg = cam_->direction;
    const double lam = p.dr.norm();
    const double cr = p.dr.x() * p.d2r.y() - p.dr.y() * p.d2r.x();
    const double cr1 = p.dr.x() * p.d3r.y() - p.dr.y() * p.d3r.x();
    const double lam1 = p.dr.dot(p.d2r) / lam;
    const double kappa = -sg * cr / (lam * lam * lam);
    const double kappa1 = -sg * (cr1 / (lam * lam * lam) - 3 * cr * lam1 / (lam * lam * lam * lam));
    const Eigen::Vector2d n = sg * Eigen::Vector2d(-p.dr.y(), p.dr.x()) / lam;
    const double rr = cam_->roller_radius;
    // d3r is not needed by the pair tracker and left zero.
    return {p.r - rr * n, (1 - rr * kappa) * p.dr, (1 - rr * kappa) * p.d2r - rr * kappa1 * p.dr,
            Eigen::Vector2d::Zero()};
  }

 private:
  const TranslatingRollerCam* cam_;
};

MotionLaw cycloidal_law() {
  MotionLawConfig config;
  config.segments = {test::segment("rise", "cycloidal", 120, 0.02), test::dwell(180),
                     test::segment("return", "cycloidal", 300, 0.02), test::dwell(360)};
  return build_motion_law(config, "test", "mechanism.cam.motion_law");
}

/// The roller cam both comparisons with the circle reduction use: base radius
/// 40 mm, roller 10 mm, follower axis 5 mm off the cam centre, ccw.
TranslatingRollerCam offset_roller_cam(const MotionLaw& law) {
  TranslatingRollerCam cam;
  cam.law = &law;
  cam.base_radius = 0.04;
  cam.roller_radius = 0.01;
  cam.offset = 0.005;
  cam.direction = 1;
  return cam;
}

TEST(ProfilePairVsCircleReduction, SamePairAndGapOnARollerCamOverATurn) {
  const MotionLaw law = cycloidal_law();
  const TranslatingRollerCam cam = offset_roller_cam(law);
  const RollerCamContour contour(cam);
  const ClosedCurveProfile a(contour);
  const CircleProfile b(cam.roller_radius);
  const PitchCurve pitch{&cam};
  PairTrackerWorkspace ws(a, b);
  double u = 0, v = 0;
  bool started = false;
  int compared = 0;
  double max_gap_diff = 0, max_point_diff = 0, max_normal_diff = 0;
  for (int i = 0; i <= 720; ++i) {
    const double theta = kTwoPi * i / 720.0;
    // The roller a little above, exactly on, and a little into the cam.
    const double delta = std::array{1e-4, 0.0, -2e-5}[i % 3];
    const Eigen::Vector2d centre_W(cam.offset, cam.y0() + law.eval(theta).s + delta);
    const BodyMotion mc = BodyMotion::make(theta, Eigen::Vector2d::Zero(), 100.0);
    const BodyMotion mr = BodyMotion::make(0.0, centre_W);
    PairEvaluation pair;
    if (!started) {
      ASSERT_TRUE(global_profile_pair(a, b, mc, mr, 0.0, 0.0, ws, u, v, pair));
      started = true;
    } else {
      ASSERT_TRUE(track_profile_pair(a, b, mc, mr, ws, u, v, pair)) << "θ = " << theta;
    }
    // The reduction: the roller centre against the pitch curve, in the cam frame.
    const Eigen::Vector2d centre_C = rot(-theta) * centre_W;
    double ur = 0;
    TrackedPair reduced;
    ASSERT_TRUE(global_pair(pitch, centre_C, theta, ur, reduced));
    const Eigen::Vector2d contour_point_W = rot(theta) * (reduced.point - cam.roller_radius * reduced.normal);
    max_gap_diff = std::max(max_gap_diff, std::abs(pair.gap - reduced.gap));
    max_point_diff = std::max(max_point_diff, (pair.point_A_W - contour_point_W).norm());
    max_normal_diff = std::max(max_normal_diff, (pair.normal_W - rot(theta) * reduced.normal).norm());
    ++compared;
  }
  EXPECT_EQ(compared, 721);
  EXPECT_LT(max_gap_diff, kAnalyticGap);
  EXPECT_LT(max_point_diff, 1e-9);
  EXPECT_LT(max_normal_diff, 1e-9);
  EXPECT_EQ(ws.global_searches, 1) << "warm-started Newton kept the pair over the whole turn";
}

/// A translating roller follower (mass, return spring, Hertz contact) on the
/// roller cam, integrated with RK4; the contact gap and normal come either from
/// the general tracker (cam contour against the roller circle, warm-started
/// Newton at every right-hand side) or from the circle reduction (roller centre
/// against the pitch curve). Returns the metrics of docs/model.md §8 it can.
struct FollowerRun {
  double peak_force = 0, min_force = INFINITY, max_kinematic_error = 0, max_penetration = 0;
  long global_searches = 0;
};

FollowerRun run_follower(bool general) {
  const MotionLaw law = cycloidal_law();
  const TranslatingRollerCam cam = offset_roller_cam(law);
  const RollerCamContour contour(cam);
  const ClosedCurveProfile a(contour);
  const CircleProfile b(cam.roller_radius);
  const PitchCurve pitch{&cam};
  PairTrackerWorkspace ws(a, b);
  constexpr double omega = 100.0, mass = 0.3, k = 5000.0, preload = 40.0, stiffness = 1e9;  // SI
  double u = 0, v = 0, ur = 0;
  bool started = false;
  const auto contact = [&](double t, double y, double& force_y, double& normal_force) {
    const double theta = omega * t;
    const Eigen::Vector2d centre(cam.offset, y);
    double gap = 0;
    Eigen::Vector2d n_W;
    if (general) {
      const BodyMotion mc = BodyMotion::make(theta, Eigen::Vector2d::Zero(), omega), mr = BodyMotion::make(0.0, centre);
      PairEvaluation pair;
      if (!started) {
        EXPECT_TRUE(global_profile_pair(a, b, mc, mr, 0.0, 0.0, ws, u, v, pair));
        started = true;
      } else {
        EXPECT_TRUE(track_profile_pair(a, b, mc, mr, ws, u, v, pair));
      }
      gap = pair.gap;
      n_W = pair.normal_W;
    } else {
      TrackedPair reduced;
      const Eigen::Vector2d c = rot(-theta) * centre;
      if (!started || !newton_track(pitch, c, ur, reduced)) {
        EXPECT_TRUE(global_pair(pitch, c, theta, ur, reduced));
        started = true;
      }
      gap = reduced.gap;
      n_W = rot(theta) * reduced.normal;
    }
    normal_force = gap < 0 ? stiffness * std::pow(-gap, 1.5) : 0.0;  // Hertz, no damping
    force_y = normal_force * n_W.y();
    return gap;
  };
  const double y0 = cam.y0();
  double y = y0 - std::pow(preload / stiffness, 2.0 / 3.0), ydot = 0;  // statically pressed on the base circle
  const auto accel = [&](double t, double yy, double& fn) {
    double fy = 0;
    contact(t, yy, fy, fn);
    return (fy - k * (yy - y0) - preload) / mass;
  };
  FollowerRun run;
  const double h = 1e-5, t_end = kTwoPi / omega;  // one turn
  const int steps = static_cast<int>(std::round(t_end / h));
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    double fn = 0;
    const double a1 = accel(t, y, fn), v1 = ydot;
    const double a2 = accel(t + h / 2, y + h / 2 * v1, fn), v2 = ydot + h / 2 * a1;
    const double a3 = accel(t + h / 2, y + h / 2 * v2, fn), v3 = ydot + h / 2 * a2;
    const double a4 = accel(t + h, y + h * v3, fn), v4 = ydot + h * a3;
    y += h / 6 * (v1 + 2 * v2 + 2 * v3 + v4);
    ydot += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
    double fy = 0;
    const double gap = contact(t + h, y, fy, fn);
    run.peak_force = std::max(run.peak_force, fn);
    run.min_force = std::min(run.min_force, fn);
    run.max_penetration = std::max(run.max_penetration, -gap);
    run.max_kinematic_error = std::max(run.max_kinematic_error, std::abs(y - y0 - law.eval(omega * (t + h)).s));
  }
  run.global_searches = ws.global_searches;
  return run;
}

TEST(ProfilePairVsCircleReduction, SameFollowerMetricsInAFixedStepSimulation) {
  const FollowerRun general = run_follower(true), reduced = run_follower(false);
  // Same ODE, same steps: the trackers' gaps agree to ~1e-12 m, which moves a
  // Hertz force of ~100 N (dF/dδ = 1.5 K δ^½ ≈ 1e7 N/m) by ~1e-5 N; the
  // trajectory carries that difference on to the kinematic error.
  EXPECT_NEAR(general.peak_force, reduced.peak_force, 1e-6 * reduced.peak_force);
  EXPECT_NEAR(general.min_force, reduced.min_force, 1e-6 * reduced.peak_force);
  EXPECT_NEAR(general.max_kinematic_error, reduced.max_kinematic_error, 1000 * kAnalyticGap);
  EXPECT_NEAR(general.max_penetration, reduced.max_penetration, 10 * kAnalyticGap);
  EXPECT_GT(reduced.min_force, 0.0) << "955 rpm is below this cam's jump speed: no separation";
  EXPECT_LT(reduced.max_kinematic_error, 1e-4) << "the follower follows the law";
  EXPECT_EQ(general.global_searches, 1) << "one initialisation, no resets over the turn";
}

// ------------------------------------------------ allocation

TEST(ProfilePairAllocation, EvaluateNewtonRatesAndGlobalSearchDoNotAllocate) {
  const Ellipse ea(0.05, 0.03);
  const ClosedCurveProfile a(ea);
  const CircleProfile b(0.01);
  PairTrackerWorkspace ws(a, b);  // allocates, once
  const BodyMotion ma = BodyMotion::make(0.3), mb = BodyMotion::make(0.0, Eigen::Vector2d(0.02, 0.045));
  const long before = test::allocation_count();
  double u = 0, v = 0, du = 0, dv = 0;
  PairEvaluation pair;
  const bool found = global_profile_pair(a, b, ma, mb, 0.0, 0.0, ws, u, v, pair);
  const PairStatus status = newton_profile_pair(a, b, ma, mb, u, v, pair);
  const PairStatus rates = profile_pair_rates(pair, 10.0, du, dv);
  const bool tracked = track_profile_pair(a, b, ma, mb, ws, u, v, pair);
  EXPECT_EQ(test::allocation_count(), before);
  EXPECT_TRUE(found && tracked);
  EXPECT_EQ(status, PairStatus::converged);
  EXPECT_EQ(rates, PairStatus::converged);
}

}  // namespace
}  // namespace camdyn

namespace camdyn {
namespace {

TEST(InwardOffsetProfile, OfAnEllipseHasTheOffsetPointsAndExactDerivatives) {
  // The offset lies at distance d inside the ellipse along its normal, and its
  // r', r'' match central differences of r and r'.
  const Ellipse ellipse(0.05, 0.03);
  const ClosedCurveProfile base(ellipse);
  constexpr double d = 0.008;
  const InwardOffsetProfile offset(base, d);
  EXPECT_EQ(offset.outward_side(), base.outward_side());
  for (int i = 0; i < 24; ++i) {
    const double u = 2 * std::numbers::pi * (i + 0.37) / 24;
    const CurvePoint b = base.at(u), o = offset.at(u);
    const Eigen::Vector2d n = outward_normal(b.r, b.dr);  // star-shaped about the origin
    EXPECT_NEAR((o.r - (b.r - d * n)).norm(), 0.0, test::kRoundoff * test::kLengthScale);
    for (int k = 0; k < 2; ++k) {
      const auto rx = [&](double x) { return offset.at(x).r[k]; };
      const auto dx = [&](double x) { return offset.at(x).dr[k]; };
      const test::FdEstimate r1 = test::central_difference(rx, u, 1e-4, 0.05);
      const test::FdEstimate r2 = test::central_difference(dx, u, 1e-4, 0.05);
      EXPECT_NEAR(o.dr[k], r1.value, r1.tolerance) << "u " << u;
      EXPECT_NEAR(o.d2r[k], r2.value, r2.tolerance) << "u " << u;
    }
  }
}

TEST(InwardOffsetProfile, OfACircleIsTheSmallerConcentricCircle) {
  const CircleProfile circle(0.04, Eigen::Vector2d(0.01, -0.02));
  const InwardOffsetProfile offset(circle, 0.015);
  for (int i = 0; i < 12; ++i) {
    const double v = 0.5 * i;
    const CurvePoint expected = CircleProfile(0.025, Eigen::Vector2d(0.01, -0.02)).at(v), got = offset.at(v);
    EXPECT_NEAR((got.r - expected.r).norm(), 0.0, test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR((got.dr - expected.dr).norm(), 0.0, test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR((got.d2r - expected.d2r).norm(), 0.0, test::kRoundoff * test::kLengthScale);
  }
}

}  // namespace
}  // namespace camdyn
