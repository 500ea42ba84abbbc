// Contour cams: the periodic spline fit of a closed point list (residuals,
// derivatives, noise), the curvature analysis (concave portions against the
// analytic zero crossings of a polar curve), the follower checks, input
// validation, and the rigid follower lift against closed forms and against
// the motion law the contour was synthesised from.
#include "geometry/contour_cam.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <random>
#include <vector>

#include "allocation_counter.h"
#include "common/constants.h"
#include "common/errors.h"
#include "finite_difference.h"
#include "geometry/cam_roller.h"
#include "io/config.h"
#include "law_checks.h"
#include "test_curves.h"
#include "tolerance.h"

namespace camdyn {
namespace {

const std::string kFile = "scene.json";
const std::string kPath = "mechanism.cam.motion_law.contour";
const std::string kPoints = "mechanism.cam.motion_law.contour.points";

using test::Ellipse;

/// Polar curve r(φ) = R (1 + ε cos kφ), concave near the minima of r when ε k² > 1 − ε.
struct Lobed {
  double radius = 0.04, eps = 0.15;
  int k = 3;
  Eigen::Vector2d point(double phi) const {
    return radius * (1 + eps * std::cos(k * phi)) * Eigen::Vector2d(std::cos(phi), std::sin(phi));
  }
  /// Signed curvature (> 0 convex): (r² + 2r'² − r r'') / (r² + r'²)^{3/2}.
  double curvature(double phi) const {
    const double r0 = radius * (1 + eps * std::cos(k * phi)), r1 = -radius * eps * k * std::sin(k * phi),
                 r2 = -radius * eps * k * k * std::cos(k * phi);
    return (r0 * r0 + 2 * r1 * r1 - r0 * r2) / std::pow(r0 * r0 + r1 * r1, 1.5);
  }
};

std::vector<Eigen::Vector2d> sample(const auto& point_of, int n) {
  std::vector<Eigen::Vector2d> pts;
  for (int i = 0; i < n; ++i) pts.push_back(point_of(kTwoPi * i / n));
  return pts;
}

/// Largest distance from the exact curve (dense samples) to the fitted one:
/// the fit's true accuracy, between the data points as well as at them.
double max_deviation(const ContourCam& cam, const auto& exact_point, int samples = 4000) {
  const int grid = 4096;
  std::vector<Eigen::Vector2d> fitted;
  for (int k = 0; k < grid; ++k) fitted.push_back(cam.at(kTwoPi * k / grid).r);
  double worst = 0;
  int best = 0;
  for (int i = 0; i < samples; ++i) {
    const Eigen::Vector2d q = exact_point(kTwoPi * (i + 0.5) / samples);
    // The samples run along the curve: search all of the grid first, then near the last foot point.
    const int window = i == 0 ? grid / 2 : 64;
    const int centre = best;
    for (int j = -window; j <= window; ++j) {
      const int k = ((centre + j) % grid + grid) % grid;
      if ((fitted[k] - q).squaredNorm() < (fitted[best] - q).squaredNorm()) best = k;
    }
    double t = kTwoPi * best / grid;
    for (int it = 0; it < 20; ++it) {  // Newton on (C − q)·C' = 0
      const CurvePoint c = cam.at(t);
      t -= (c.r - q).dot(c.dr) / (c.dr.squaredNorm() + (c.r - q).dot(c.d2r));
    }
    worst = std::max(worst, (cam.at(t).r - q).norm());
  }
  return worst;
}

/// The 20 mm cycloidal rise-return on a 40 mm base circle, 10 mm roller, 5 mm offset.
struct RollerCamScene {
  MotionLaw law = test::build(test::segments({test::segment("rise", "cycloidal", 120, 0.02), test::dwell(180),
                                              test::segment("return", "cycloidal", 300, 0.02), test::dwell(360)}));
  TranslatingRollerCam cam;
  RollerCamScene() {
    cam.law = &law;
    cam.base_radius = 0.04;
    cam.roller_radius = 0.01;
    cam.offset = 0.005;
    cam.direction = 1;
  }
};

void expect_input_error(const std::vector<Eigen::Vector2d>& pts, const ContourFitOptions& options,
                        const std::string& path, const std::string& reason_part) {
  try {
    ContourCam::fit(pts, options, kFile, kPath);
    ADD_FAILURE() << "no InputError, expected one at " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_EQ(e.file(), kFile);
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
  }
}

// ------------------------------------------------ fit

TEST(ContourFit, DerivativesMatchFiniteDifferences) {
  const Ellipse ellipse(0.05, 0.03);
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return ellipse.at(u).r; }, 90), {}, kFile);
  for (int i = 0; i < 37; ++i) {
    const double u = kTwoPi * (i + 0.37) / 37;
    const CurvePoint c = cam.at(u);
    for (int axis = 0; axis < 2; ++axis) {
      const auto d1 = test::central_difference([&](double x) { return cam.at(x).r(axis); }, u, 1e-4, 0.05);
      const auto d2 = test::central_difference([&](double x) { return cam.at(x).dr(axis); }, u, 1e-4, 0.05);
      const auto d3 = test::central_difference([&](double x) { return cam.at(x).d2r(axis); }, u, 1e-4, 0.05);
      EXPECT_NEAR(c.dr(axis), d1.value, d1.tolerance) << "u = " << u;
      EXPECT_NEAR(c.d2r(axis), d2.value, d2.tolerance) << "u = " << u;
      EXPECT_NEAR(c.d3r(axis), d3.value, d3.tolerance) << "u = " << u;
    }
    // Periodic: the parameter may be any real.
    EXPECT_LT((cam.at(u + 3 * kTwoPi).r - c.r).norm(), test::kRoundoff * test::kLengthScale);
  }
}

TEST(ContourFit, InterpolatesWhenThereAreAsManyControlPointsAsPoints) {
  const Ellipse ellipse(0.05, 0.03);
  const auto pts = sample([&](double u) { return ellipse.at(u).r; }, 12);
  ContourFitOptions options;
  options.control_points = 12;
  const ContourCam cam = ContourCam::fit(pts, options, kFile);
  EXPECT_EQ(cam.report().control_points, 12);
  EXPECT_LT(cam.report().max_residual, test::kRoundoff * test::kLengthScale);
  EXPECT_EQ(cam.orientation(), +1);
}

TEST(ContourFit, ExactPointsOfARollerCamGiveAFitFarBelowManufacturingTolerance) {
  const RollerCamScene s;
  const auto exact = [&](double u) { return s.cam.contour(u); };
  const ContourCam cam = ContourCam::fit(sample(exact, 720), {}, kFile);
  const ContourFitReport& rep = cam.report();
  EXPECT_EQ(rep.points, 720);
  EXPECT_EQ(rep.control_points, 360);
  EXPECT_EQ(cam.orientation(), -1) << "the synthesised contour runs clockwise for a ccw cam";
  const double deviation = max_deviation(cam, exact);
  // Degree 5 on a 1° grid: errors ~ h⁶ |r⁽⁶⁾|, far below a micrometre. (The
  // cycloidal law's jerk jumps at its segment ends, so r is only C² there.)
  EXPECT_LT(deviation, 1e-7);
  EXPECT_LE(rep.max_residual, deviation + test::kRoundoff * test::kLengthScale)
      << "residuals at the points bound by the deviation";
  EXPECT_LE(rep.rms_residual, rep.max_residual);
  EXPECT_TRUE(rep.concave.empty());
  // The contour's smallest radius of curvature, from the synthesis: ρ_pitch − r_r.
  double min_rho = INFINITY;
  for (int i = 0; i < 36000; ++i)
    min_rho = std::min(min_rho, std::abs(s.cam.pitch_radius_of_curvature(kTwoPi * i / 36000) - 0.01));
  EXPECT_NEAR(rep.min_radius_of_curvature, min_rho, 1e-3 * min_rho);
}

TEST(ContourFit, DropsARepeatedClosingPoint) {
  const Ellipse ellipse(0.05, 0.03);
  auto pts = sample([&](double u) { return ellipse.at(u).r; }, 40);
  pts.push_back(pts.front());
  const ContourCam cam = ContourCam::fit(pts, {}, kFile);
  EXPECT_EQ(cam.report().points, 40);
  EXPECT_EQ(cam.points().size(), 40u);
}

TEST(ContourFit, NoisyPointsLeaveResidualsOfTheNoiseAndAFitCloserThanIt) {
  const RollerCamScene s;
  const auto exact = [&](double u) { return s.cam.contour(u); };
  constexpr double sigma = 2e-6;  // [m] per coordinate, a good CMM
  std::mt19937 rng(12345);
  std::normal_distribution<double> noise(0.0, sigma);
  auto pts = sample(exact, 720);
  for (auto& p : pts) p += Eigen::Vector2d(noise(rng), noise(rng));
  const ContourCam cam = ContourCam::fit(pts, {}, kFile);
  const ContourFitReport& rep = cam.report();
  // The residual is the normal component of the noise (σ per direction),
  // less what the m = N/2 coefficients per coordinate absorb: about σ √(1 − m/N).
  EXPECT_GT(rep.rms_residual, 0.5 * sigma);
  EXPECT_LT(rep.rms_residual, 1.0 * sigma);
  EXPECT_LT(rep.max_residual, 5 * sigma);
  // Averaging: the fit is closer to the true contour than the noise (√(m/N) σ ≈ 0.7σ rms).
  EXPECT_LT(max_deviation(cam, exact), 3 * sigma);
  // The recovered law is within the fit's deviation.
  const RigidFollowerLift lift(cam, FollowerContact::circle, 0.01, 0.005, +1);
  double worst = 0;
  for (int i = 0; i < 360; ++i) {
    const double th = kTwoPi * i / 360;
    worst = std::max(worst, std::abs(lift.displacement(th) - s.law.eval(th).s));
  }
  // Moving the contour by δ along its normal moves the roller by δ / cos φ
  // (pressure angle φ ≤ 35° here): within twice the fit's deviation.
  EXPECT_LT(worst, 2 * max_deviation(cam, exact));
}

TEST(ContourFit, SmoothingRemovesTheCurvatureWigglesOfNoise) {
  // A convex cam (curvature 16–31 1/m) measured roughly: σ = 10 µm on 0.35 mm
  // spacing. Noise of σ/h² ~ 80 1/m in the second derivative swamps the plain
  // least-squares fit's curvature and fakes concave flanks; the third-difference
  // penalty damps wavelengths below ~2π λ^{1/6} control-point spacings
  // (20 at λ = 1e3, against the cam's ~180 per half turn).
  const double a = 0.05, b = 0.04;
  const Ellipse ellipse(a, b);
  constexpr double sigma = 1e-5;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, sigma);
  auto pts = sample([&](double u) { return ellipse.at(u).r; }, 720);
  for (auto& p : pts) p += Eigen::Vector2d(noise(rng), noise(rng));
  const auto curvature_error = [&](const ContourCam& cam) {
    double worst = 0;  // at each point's foot point, against the ellipse at the point's own parameter
    for (int i = 0; i < 720; ++i) {
      const double u = kTwoPi * i / 720;
      const double exact = a * b / std::pow(std::hypot(a * std::sin(u), b * std::cos(u)), 3);
      worst = std::max(worst, std::abs(cam.curvature(cam.point_parameter(i)) - exact));
    }
    return worst;
  };
  ContourFitOptions smooth;
  smooth.smoothing = 1e3;
  const ContourCam plain = ContourCam::fit(pts, {}, kFile), smoothed = ContourCam::fit(pts, smooth, kFile);
  EXPECT_FALSE(plain.report().concave.empty()) << "noise fakes concave flanks without smoothing";
  EXPECT_GT(curvature_error(plain), b / (a * a));
  EXPECT_TRUE(smoothed.report().concave.empty());
  EXPECT_LT(curvature_error(smoothed), 0.1 * b / (a * a)) << "within 10% of the smallest curvature";
  // Smoothing gives back the degrees of freedom that absorbed noise: residual → σ.
  EXPECT_GT(smoothed.report().rms_residual, 0.8 * sigma);
  EXPECT_LT(smoothed.report().rms_residual, 1.2 * sigma);
  EXPECT_LT(max_deviation(smoothed, [&](double u) { return ellipse.at(u).r; }), sigma);
}

// ------------------------------------------------ concave portions and follower checks

/// Parameter φ where the lobed curve's curvature crosses zero, by bisection.
double lobed_zero(const Lobed& c, double a, double b) {
  const bool neg_a = c.curvature(a) < 0;
  for (int i = 0; i < 100; ++i) {
    const double m = 0.5 * (a + b);
    if ((c.curvature(m) < 0) == neg_a)
      a = m;
    else
      b = m;
  }
  return 0.5 * (a + b);
}

TEST(ContourConcave, PortionsMatchTheAnalyticCurvatureZeros) {
  const Lobed lobed;
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return lobed.point(u); }, 360), {}, kFile);
  const ContourFitReport& rep = cam.report();
  ASSERT_EQ(rep.concave.size(), 3u);
  // Hollows centred on 60°, 180°, 300°; each begins where κ turns negative.
  const double begin = lobed_zero(lobed, 0.1, kPi / 3) * 180 / kPi, end = 120 - begin;
  const double rho = -1 / lobed.curvature(kPi / 3);  // 0.0578 m
  for (const ConcavePortion& c : rep.concave) {
    const double centre = std::round((c.angle_begin_deg + 60) / 120) * 120 - 60;  // 60, 180 or 300
    const double offset = centre - 60;
    // 360 exact points, degree 5 (2° per control point): the curvature is
    // accurate to ~1e-4 relative, the zeros to far below 0.01°; the first
    // point of a portion is the sample nearest its zero, one per degree.
    constexpr double kZeroDeg = 0.01, kOnePoint = 1.0;
    EXPECT_NEAR(c.angle_begin_deg, begin + offset, kZeroDeg);
    EXPECT_NEAR(c.angle_end_deg, end + offset, kZeroDeg);
    EXPECT_NEAR(c.min_abs_radius, rho, 1e-4 * rho) << "curvature: two derivatives of the fit, ~h⁴";
    EXPECT_NEAR(c.min_abs_radius_angle_deg, centre, kZeroDeg);
    EXPECT_NEAR(c.point_begin, std::round(begin + offset), kOnePoint) << "one point per degree";
    EXPECT_GE(c.u_begin, 0.0);
    EXPECT_LT(c.u_begin, kTwoPi);
    EXPECT_GT(c.u_end, c.u_begin);
  }
  EXPECT_NEAR(rep.min_radius_of_curvature, std::min(rho, 1 / lobed.curvature(0)), 1e-4 * rho);
}

TEST(ContourConcave, FlatFaceCannotFollowAConcaveFlank) {
  const Lobed lobed;
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return lobed.point(u); }, 360), {}, kFile);
  try {
    check_contour_for_follower(cam, FollowerContact::line, 0.0, kFile, kPath);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), kPoints);
    EXPECT_NE(e.reason().find("concave from polar angle"), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("near point"), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("flat-faced"), std::string::npos) << e.what();
  }
}

TEST(ContourConcave, RollerFollowsHollowsWiderThanItself) {
  const Lobed lobed;  // hollows of radius 0.0578 m
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return lobed.point(u); }, 360), {}, kFile);
  EXPECT_NO_THROW(check_contour_for_follower(cam, FollowerContact::circle, 0.02, kFile, kPath));
  EXPECT_NO_THROW(check_contour_for_follower(cam, FollowerContact::circle, 0.05, kFile, kPath));
  try {
    check_contour_for_follower(cam, FollowerContact::circle, 0.07, kFile, kPath);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), kPoints);
    EXPECT_NE(e.reason().find("less than the follower radius 0.07 m"), std::string::npos) << e.what();
  }
}

TEST(ContourConcave, ConvexCamPassesEveryFollower) {
  const Ellipse ellipse(0.05, 0.03);
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return ellipse.at(u).r; }, 180), {}, kFile);
  EXPECT_TRUE(cam.report().concave.empty());
  EXPECT_NO_THROW(check_contour_for_follower(cam, FollowerContact::line, 0.0, kFile, kPath));
  EXPECT_NO_THROW(check_contour_for_follower(cam, FollowerContact::circle, 0.2, kFile, kPath));
  // The ellipse's smallest radius b²/a = 0.018 m flags a corner check set above it.
  constexpr double kFitRadius = 1e-6;  // [m], a fit through 180 exact points: ≈ 5e-5 relative
  EXPECT_NEAR(cam.report().min_convex_radius, 0.03 * 0.03 / 0.05, kFitRadius);
  const double at = cam.report().min_convex_radius_angle_deg;  // the ends of the major axis
  EXPECT_LT(std::min({at, std::abs(at - 180), 360 - at}), 0.01);
  EXPECT_THROW(check_contour_for_follower(cam, FollowerContact::line, 0.0, kFile, kPath, 0.02), InputError);
}

// ------------------------------------------------ validation

TEST(ContourValidation, RejectsBadPointLists) {
  const Ellipse ellipse(0.05, 0.03);
  const auto good = sample([&](double u) { return ellipse.at(u).r; }, 24);
  expect_input_error({good.begin(), good.begin() + 7}, {}, kPoints, "at least 8");
  auto nan = good;
  nan[5].x() = NAN;
  expect_input_error(nan, {}, kPoints, "point 5 is not finite");
  auto repeated = good;
  repeated[9] = repeated[8];
  expect_input_error(repeated, {}, kPoints, "point 9");
  auto swapped = good;
  std::swap(swapped[10], swapped[11]);
  expect_input_error(swapped, {}, kPoints, "does not continue the polar angle");
  auto twice = sample([&](double u) { return ellipse.at(2 * u).r; }, 48);  // goes around twice
  expect_input_error(twice, {}, kPoints, "wind 2 times");
  auto off_centre = good;  // the cam centre outside the contour
  for (auto& p : off_centre) p.x() += 0.2;
  expect_input_error(off_centre, {}, kPoints, "does not continue the polar angle");
  auto centre = good;
  centre[3] = Eigen::Vector2d::Zero();
  expect_input_error(centre, {}, kPoints, "point 3 is at the cam centre");
}

TEST(ContourValidation, RejectsBadOptions) {
  const Ellipse ellipse(0.05, 0.03);
  const auto pts = sample([&](double u) { return ellipse.at(u).r; }, 24);
  ContourFitOptions o;
  o.degree = 2;
  expect_input_error(pts, o, kPath + ".degree", "must be in [3, 9]");
  o = {};
  o.control_points = 25;
  expect_input_error(pts, o, kPath + ".control_points", "[6, 24]");
  o = {};
  o.smoothing = -1;
  expect_input_error(pts, o, kPath + ".smoothing", ">= 0");
}

// ------------------------------------------------ rigid follower lift

TEST(RigidLift, FlatFaceOnAnEllipseIsItsSupportFunction) {
  const double a = 0.05, b = 0.03;
  const Ellipse ellipse(a, b);
  const RigidFollowerLift lift(ellipse, FollowerContact::line, 0.0, 0.0, +1);
  for (int i = 0; i < 50; ++i) {
    const double th = kTwoPi * (i + 0.1) / 50;
    // Turned by θ, the height of the ellipse is y = sqrt(a² sin²θ + b² cos²θ).
    const double s = std::sin(th), c = std::cos(th);
    const double y = std::hypot(a * s, b * c);
    const double dy = (a * a - b * b) * s * c / y;
    const double d2y = ((a * a - b * b) * std::cos(2 * th) - dy * dy) / y;
    const RigidLift l = lift.at(th);
    EXPECT_NEAR(l.y, y, test::kRoundoff * test::kLengthScale);
    EXPECT_NEAR(l.dy, dy, test::kRoundoff);
    EXPECT_NEAR(l.d2y, d2y, test::kAmplifiedRoundoff);
  }
  EXPECT_NEAR(lift.lowest(), b, test::kRoundoff * test::kLengthScale);
}

TEST(RigidLift, RollerOnAnEccentricCircleMatchesTheClosedForm) {
  // Cam: circle of radius R about (ε, 0); roller ρ on the axis x = e:
  // y(θ) = ε_y + sqrt((R + ρ)² − (e − ε_x)²) with (ε_x, ε_y) = ε (cos σθ, sin σθ).
  const double big_r = 0.04, eps = 0.008, rho = 0.012, e = 0.006;
  struct Eccentric final : PeriodicCurve {
    double big_r, eps;
    Eccentric(double r, double ecc) : big_r(r), eps(ecc) {}
    CurvePoint at(double u) const override {
      const double c = std::cos(u), s = std::sin(u);
      return {{eps + big_r * c, big_r * s}, {-big_r * s, big_r * c}, {-big_r * c, -big_r * s}, {big_r * s, -big_r * c}};
    }
  } cam(big_r, eps);
  for (int sigma : {+1, -1}) {
    const RigidFollowerLift lift(cam, FollowerContact::circle, rho, e, sigma);
    const auto y_of = [&](double th) {
      const double ex = eps * std::cos(sigma * th), ey = eps * std::sin(sigma * th);
      return ey + std::sqrt((big_r + rho) * (big_r + rho) - (e - ex) * (e - ex));
    };
    for (int i = 0; i < 40; ++i) {
      const double th = kTwoPi * (i + 0.3) / 40;
      const RigidLift l = lift.at(th);
      const auto dy = test::central_difference(y_of, th, 1e-4, 0.05);
      const auto d2y = test::central_difference([&](double x) { return lift.at(x).dy; }, th, 1e-4, 0.01);
      EXPECT_NEAR(l.y, y_of(th), test::kRoundoff * test::kLengthScale);
      EXPECT_NEAR(l.dy, dy.value, dy.tolerance);
      EXPECT_NEAR(l.d2y, d2y.value, d2y.tolerance);
      // The contact point is on the cam, ρ from the roller centre.
      EXPECT_NEAR((l.contact_W - Eigen::Vector2d(e, l.y)).norm(), rho, test::kRoundoff * test::kLengthScale);
    }
  }
}

TEST(RigidLift, RecoversTheMotionLawOfASynthesisedRollerCam) {
  const RollerCamScene s;
  const auto exact = [&](double u) { return s.cam.contour(u); };
  const ContourCam cam = ContourCam::fit(sample(exact, 720), {}, kFile);
  const double deviation = max_deviation(cam, exact);
  const RigidFollowerLift lift(cam, FollowerContact::circle, 0.01, 0.005, +1);
  // The lowest centre height is the synthesis' y₀ (base circle + roller).
  EXPECT_NEAR(lift.lowest(), s.cam.y0(), 2 * deviation);
  double worst_s = 0, worst_ds = 0;
  for (int i = 0; i < 1440; ++i) {
    const double th = kTwoPi * i / 1440;
    const RigidLift l = lift.at(th);
    const LawSample law = s.law.eval(th);
    worst_s = std::max(worst_s, std::abs(l.y - s.cam.y0() - law.s));
    worst_ds = std::max(worst_ds, std::abs(l.dy - law.ds));
  }
  // Moving the contour by δ along its normal moves the roller by δ / cos φ
  // (pressure angle φ ≤ 35° here): within twice the fit deviation.
  EXPECT_LT(worst_s, 2 * deviation);
  EXPECT_LT(worst_ds, 1e-5) << "ds/dθ [m/rad], against a lift rate of up to 0.03 m/rad";
}

TEST(RigidLift, RollerThatMissesTheCamIsAnInputError) {
  const Ellipse ellipse(0.05, 0.03);
  try {
    const RigidFollowerLift lift(ellipse, FollowerContact::circle, 0.01, 0.045, +1, 2048, kFile);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.offset");
    EXPECT_NE(e.reason().find("reduce the offset"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------ golden point files

/// Points of a `{ "contour": { "points": [...] } }` file written by tests/data/contour/generate_contours.py.
std::vector<Eigen::Vector2d> read_points(const std::string& name) {
  std::ifstream in(std::string(CAMDYN_TEST_DATA_DIR) + "/contour/" + name);
  const Json doc = Json::parse(in);
  std::vector<Eigen::Vector2d> pts;
  for (const Json& p : doc.at("contour").at("points")) pts.emplace_back(p.at(0).get<double>(), p.at(1).get<double>());
  return pts;
}

TEST(ContourGoldenFiles, PythonSynthesisedRollerCamGivesBackTheLaw) {
  // The script synthesises the contour independently of cam_roller.cc; the
  // fitted contour must carry the same law within its deviation from the C++ one.
  const RollerCamScene s;
  const auto pts = read_points("roller_cam_cycloidal.json");
  ASSERT_EQ(pts.size(), 360u);
  EXPECT_LT((pts[0] - s.cam.contour(0.0)).norm(), test::kAmplifiedRoundoff) << "the same cam";
  const ContourCam cam = ContourCam::fit(pts, {}, kFile);
  const double deviation = max_deviation(cam, [&](double u) { return s.cam.contour(u); });
  EXPECT_LT(deviation, 1e-6);
  const RigidFollowerLift lift(cam, FollowerContact::circle, 0.01, 0.005, +1);
  double worst = 0;
  for (int i = 0; i < 720; ++i) {
    const double th = kTwoPi * i / 720;
    worst = std::max(worst, std::abs(lift.displacement(th) - s.law.eval(th).s));
  }
  EXPECT_LT(worst, 2 * deviation);
}

TEST(ContourGoldenFiles, NoisyMeasurementNeedsSmoothingForTheAcceleration) {
  constexpr double sigma = 2e-6;  // the script's noise per coordinate [m]
  const RollerCamScene s;
  const auto pts = read_points("roller_cam_cycloidal_noisy.json");
  const ContourCam plain = ContourCam::fit(pts, {}, kFile);
  EXPECT_GT(plain.report().rms_residual, 0.5 * sigma);
  EXPECT_LT(plain.report().rms_residual, 1.0 * sigma);
  ContourFitOptions options;
  options.smoothing = 10;
  const ContourCam smoothed = ContourCam::fit(pts, options, kFile);
  EXPECT_LT(smoothed.report().rms_residual, 1.2 * sigma);
  // s'' of the law is 2π h/β² = 0.0286 m/rad² at most. The rigid lift's s''
  // takes two derivatives of the contour: noise σ/h² on 1° spacing swamps it
  // without smoothing; with λ = 10 it is a few per cent.
  const auto worst_d2s = [&](const ContourCam& cam) {
    const RigidFollowerLift lift(cam, FollowerContact::circle, 0.01, 0.005, +1);
    double worst = 0;
    for (int i = 0; i < 720; ++i) {
      const double th = kTwoPi * i / 720;
      worst = std::max(worst, std::abs(lift.at(th).d2y - s.law.eval(th).d2s));
    }
    return worst;
  };
  const double peak = 2 * kPi * 0.02 / std::pow(2 * kPi / 3, 2);
  EXPECT_GT(worst_d2s(plain), 0.2 * peak);
  EXPECT_LT(worst_d2s(smoothed), 0.1 * peak);
  EXPECT_TRUE(smoothed.report().concave.empty());
}

TEST(ContourGoldenFiles, LobedContourIsRejectedForAFlatFace) {
  const ContourCam cam = ContourCam::fit(read_points("lobed_concave.json"), {}, kFile);
  EXPECT_EQ(cam.report().concave.size(), 3u);
  EXPECT_THROW(check_contour_for_follower(cam, FollowerContact::line, 0.0, kFile, kPath), InputError);
}

// ------------------------------------------------ allocation

TEST(ContourAllocation, EvaluationAndRigidLiftDoNotAllocate) {
  const Lobed lobed;
  const ContourCam cam = ContourCam::fit(sample([&](double u) { return lobed.point(u); }, 120), {}, kFile);
  const RigidFollowerLift lift(cam, FollowerContact::circle, 0.01, 0.0, +1);
  const long before = test::allocation_count();
  double sink = 0;
  for (int i = -300; i < 300; ++i) {
    const double u = 0.0123 * i;
    sink += cam.at(u).d3r.x() + cam.curvature(u) + lift.at(u).d2y;
  }
  EXPECT_EQ(test::allocation_count(), before);
  EXPECT_TRUE(std::isfinite(sink));
}

}  // namespace
}  // namespace camdyn
