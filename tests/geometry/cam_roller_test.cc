// Translating roller cam: pitch curve and its derivatives, contour, curvature,
// pressure angle, and the manufacturability checks of check_cam.
#include "geometry/cam_roller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/constants.h"
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::dwell;
using test::segment;
using test::segments;

MotionLaw standard_law() {
  return test::build(segments({segment("rise", "cycloidal", 120, 0.02), dwell(180),
                               segment("return", "polynomial_345", 300, 0.02), dwell(360)}));
}

MotionLaw dwell_law() { return test::build(segments({dwell(360)})); }

TranslatingRollerCam make_cam(const MotionLaw& law, double e, int sigma) {
  TranslatingRollerCam cam;
  cam.law = &law;
  cam.base_radius = 0.04;    // [m]
  cam.roller_radius = 0.01;  // [m]
  cam.offset = e;
  cam.direction = sigma;
  return cam;
}

struct Variant {
  double offset;  ///< [m]
  int sigma;
};
void PrintTo(const Variant& v, std::ostream* os) { *os << "e=" << v.offset << " sigma=" << v.sigma; }

class CamVariant : public ::testing::TestWithParam<Variant> {};

// Geometry is a handful of flops on lengths ~0.05 m: ulp-level errors ~1e-17 m.
constexpr double kLengthTol = test::kRoundoff * test::kLengthScale;  // [m]

TEST_P(CamVariant, DwellPitchCurveIsACircleOfRadiusBasePlusRoller) {
  const MotionLaw law = dwell_law();
  const TranslatingRollerCam cam = make_cam(law, GetParam().offset, GetParam().sigma);
  for (int i = 0; i < 36; ++i) {
    const double u = i * 10 * kDegToRad;
    EXPECT_NEAR(cam.pitch(u).r.norm(), 0.05, kLengthTol);
    EXPECT_NEAR(cam.contour(u).norm(), 0.04, kLengthTol);
    EXPECT_NEAR(cam.pitch_radius_of_curvature(u), 0.05, test::kAmplifiedRoundoff * test::kLengthScale);
    EXPECT_NEAR(cam.pitch_radius_of_curvature(u) - cam.roller_radius, 0.04,
                test::kAmplifiedRoundoff * test::kLengthScale);  // contour
  }
  // Cam angle 0 puts the follower's base position (e, y₀) over the centre.
  EXPECT_NEAR(cam.pitch(0.0).r.x(), GetParam().offset, kLengthTol);
  EXPECT_NEAR(cam.pitch(0.0).r.y(), cam.y0(), kLengthTol);
}

TEST_P(CamVariant, PitchDerivativesMatchFiniteDifferences) {
  const MotionLaw law = standard_law();
  const TranslatingRollerCam cam = make_cam(law, GetParam().offset, GetParam().sigma);
  constexpr double h = 1e-4;  // [rad]
  for (int i = 0; i < 50; ++i) {
    const double u = kTwoPi * (i + 0.3) / 50;  // ≥ 0.5° from the law's breakpoints
    const CurvePoint p = cam.pitch(u);
    for (int axis = 0; axis < 2; ++axis) {
      const auto d1 = test::central_difference([&](double t) { return cam.pitch(t).r[axis]; }, u, h);
      const auto d2 = test::central_difference([&](double t) { return cam.pitch(t).dr[axis]; }, u, h);
      const auto d3 = test::central_difference([&](double t) { return cam.pitch(t).d2r[axis]; }, u, h);
      EXPECT_NEAR(p.dr[axis], d1.value, d1.tolerance) << "P' at u = " << u;
      EXPECT_NEAR(p.d2r[axis], d2.value, d2.tolerance) << "P'' at u = " << u;
      EXPECT_NEAR(p.d3r[axis], d3.value, d3.tolerance) << "P''' at u = " << u;
    }
  }
}

TEST_P(CamVariant, ContourIsTheInnerOffsetByTheRollerRadius) {
  const MotionLaw law = standard_law();
  const TranslatingRollerCam cam = make_cam(law, GetParam().offset, GetParam().sigma);
  for (int i = 0; i < 72; ++i) {
    const double u = i * 5 * kDegToRad;
    const CurvePoint p = cam.pitch(u);
    const Eigen::Vector2d c = cam.contour(u);
    EXPECT_NEAR((p.r - c).norm(), cam.roller_radius, kLengthTol);
    EXPECT_NEAR((p.r - c).dot(p.dr), 0.0, kLengthTol);  // along the normal: ⟂ the tangent
    EXPECT_LT(c.norm(), p.r.norm());                    // on the cam centre side
  }
}

TEST_P(CamVariant, PressureAngleMatchesTheClosedForm) {
  // σ·atan((s' − σe)/(y₀ + s)); for σ = +1 the textbook atan((s' − e)/(y₀ + s)).
  const MotionLaw law = standard_law();
  const double e = GetParam().offset;
  const int sg = GetParam().sigma;
  const TranslatingRollerCam cam = make_cam(law, e, sg);
  for (int i = 0; i < 72; ++i) {
    const double th = i * 5 * kDegToRad;
    const LawSample l = law.eval(th);
    EXPECT_NEAR(cam.pressure_angle(th), sg * std::atan((l.ds - sg * e) / (cam.y0() + l.s)), test::kRoundoff)
        << "θ = " << th;
  }
}

TEST(CamCurvature, IsTheCurveFormulaInPolarFormWithoutOffset) {
  // Independent check of the sign convention: for e = 0 the pitch curve is the
  // polar curve r(u) = y₀ + s(u), whose curvature is
  // κ = (r² + 2r'² − r r'') / (r² + r'²)^(3/2) (positive where convex), any σ.
  const MotionLaw law = standard_law();
  for (const int sigma : {+1, -1}) {
    const TranslatingRollerCam cam = make_cam(law, 0.0, sigma);
    for (int i = 0; i < 72; ++i) {
      const double u = (i + 0.5) * 5 * kDegToRad;
      const LawSample l = law.eval(u);
      const double r = cam.y0() + l.s;
      const double kappa = (r * r + 2 * l.ds * l.ds - r * l.d2s) / std::pow(r * r + l.ds * l.ds, 1.5);
      EXPECT_NEAR(cam.pitch_curvature(u), kappa, test::kAmplifiedRoundoff * (std::abs(kappa) + 1))
          << "u = " << u << ", σ = " << sigma;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(OffsetsAndDirections, CamVariant,
                         ::testing::Values(Variant{0.0, 1}, Variant{0.0, -1}, Variant{0.012, 1}, Variant{0.012, -1},
                                           Variant{-0.008, 1}));

// ---------------------------------------------------------------- check_cam

TEST(CheckCam, ReportMatchesADenseScan) {
  const MotionLaw law = standard_law();
  const TranslatingRollerCam cam = make_cam(law, 0.01, 1);
  const CamGeometryReport r = check_cam(cam, "scene.json");
  double max_phi = 0.0, min_rho = 1e9, at_phi = 0.0;
  const int n = 200000;  // spacing 3e-5 rad (0.002°)
  // A smooth extremum between samples is off by < 1e-7 relative in value; its
  // location is far less sharp: allow about five samples.
  constexpr double kGridMiss = 1e-7, kGridMissDeg = 0.01;
  for (int i = 0; i < n; ++i) {
    const double u = kTwoPi * i / n;
    const double phi = std::abs(cam.pressure_angle(u)) / kDegToRad;
    if (phi > max_phi) {
      max_phi = phi;
      at_phi = u / kDegToRad;
    }
    min_rho = std::min(min_rho, std::abs(cam.pitch_radius_of_curvature(u) - cam.roller_radius));
  }
  // The refined extremum is at least as extreme as any sample, and not by more
  // than the dense grid can miss.
  EXPECT_GE(r.max_pressure_angle_deg, max_phi - test::kAmplifiedRoundoff);
  EXPECT_NEAR(r.max_pressure_angle_deg, max_phi, kGridMiss * max_phi);
  EXPECT_NEAR(r.max_pressure_angle_at_deg, at_phi, kGridMissDeg);
  EXPECT_LE(r.min_radius_of_curvature, min_rho + kLengthTol);
  EXPECT_NEAR(r.min_radius_of_curvature, min_rho, kGridMiss * min_rho);
}

TEST(CheckCam, BaseCircleDwellHasContourRadiusEqualToBaseRadius) {
  const MotionLaw law = dwell_law();
  const CamGeometryReport r = check_cam(make_cam(law, 0.005, -1), "scene.json");
  EXPECT_NEAR(r.min_radius_of_curvature, 0.04, test::kAmplifiedRoundoff * test::kLengthScale);
  EXPECT_NEAR(r.max_pressure_angle_deg, std::atan(0.005 / std::sqrt(0.05 * 0.05 - 0.005 * 0.005)) / kDegToRad,
              test::kAmplifiedRoundoff * 10);
}

/// The cam angle [deg] that an InputError message names ("at cam angle 22.5°").
double named_angle(const InputError& e) {
  // Plain parsing: std::regex trips a false -Wmaybe-uninitialized in GCC 12 sanitizer builds.
  const std::string reason = e.reason();
  const std::string marker = "at cam angle ";
  const size_t at = reason.find(marker);
  if (at == std::string::npos) return -1.0;
  return std::stod(reason.substr(at + marker.size()));
}

TEST(CheckCam, RollerTooBigForASharpRiseIsAnUndercut) {
  // r_b = 20 mm, a 20 mm cycloidal rise in 30°: the nose after the rise has a
  // pitch radius ≈ r²/(r + |s''|) ≈ 5 mm < r_r = 10 mm, near 3/4 of the rise
  // where s'' is most negative.
  const MotionLaw law = test::build(segments(
      {segment("rise", "cycloidal", 30, 0.02), dwell(180), segment("return", "cycloidal", 300, 0.02), dwell(360)}));
  TranslatingRollerCam cam = make_cam(law, 0.0, 1);
  cam.base_radius = 0.02;
  try {
    check_cam(cam, "scene.json");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam");
    EXPECT_NE(e.reason().find("undercut"), std::string::npos) << e.what();
    const double deg = named_angle(e);
    EXPECT_GT(deg, 15.0) << e.what();
    EXPECT_LT(deg, 30.0) << e.what();
  }
  cam.roller_radius = 0.002;  // a small roller fits
  EXPECT_NO_THROW(check_cam(cam, "scene.json"));
}

TEST(CheckCam, OffsetNotLessThanBasePlusRollerRadius) {
  const MotionLaw law = standard_law();
  TranslatingRollerCam cam = make_cam(law, 0.05, 1);  // r_b + r_r = 0.05
  try {
    check_cam(cam, "scene.json");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.offset");
    EXPECT_EQ(e.file(), "scene.json");
  }
  cam.offset = -0.06;
  EXPECT_THROW(check_cam(cam, "scene.json"), InputError);
}

TEST(CheckCam, NonPositiveRadii) {
  const MotionLaw law = standard_law();
  TranslatingRollerCam cam = make_cam(law, 0.0, 1);
  cam.base_radius = 0.0;
  try {
    check_cam(cam, "scene.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam.base_radius");
  }
  cam.base_radius = 0.04;
  cam.roller_radius = -0.01;
  try {
    check_cam(cam, "scene.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.shape.radius");
  }
}

TEST(CheckCam, PitchCurveTurningBackIsNotMakeable) {
  // Large offset with a steep rise: |q|² < σ·e·s' (q = (e, y₀ + s)) in mid-rise,
  // so the pitch curve folds back about the cam centre.
  const MotionLaw law = test::build(segments(
      {segment("rise", "cycloidal", 30, 0.02), dwell(180), segment("return", "cycloidal", 300, 0.02), dwell(360)}));
  TranslatingRollerCam cam = make_cam(law, 0.02, 1);
  cam.base_radius = 0.02;
  cam.roller_radius = 0.005;
  try {
    check_cam(cam, "scene.json");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(e.reason().find("turns back"), std::string::npos) << e.what();
    const double deg = named_angle(e);
    EXPECT_GT(deg, 0.0) << e.what();
    EXPECT_LT(deg, 30.0) << e.what();
  }
}

}  // namespace
}  // namespace camdyn
