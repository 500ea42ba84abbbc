// Cam synthesis for every follower (envelope theory) and its checks: the
// profile and its derivatives, analytic contours, the cusp / undercut /
// face-width checks naming the cam angle.
#include "geometry/cam_synthesis.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "allocation_counter.h"
#include "common/constants.h"
#include "common/errors.h"
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::dwell;
using test::segment;
using test::segments;

std::shared_ptr<const MotionLaw> law_of(double lift, double rise_end = 120, double dwell_end = 180,
                                        double return_end = 300) {
  return std::make_shared<const MotionLaw>(
      test::build(segments({segment("rise", "cycloidal", rise_end, lift), dwell(dwell_end),
                            segment("return", "polynomial_345", return_end, lift), dwell(360)})));
}

FollowerConfig follower(const std::string& motion, const std::string& shape) {
  FollowerConfig f;
  f.motion = parse_enum<FollowerMotion>(motion);
  f.shape.type = parse_enum<FollowerShape>(shape);
  f.shape.radius = shape == "flat" ? 0.0 : (shape == "roller" ? 0.01 : 0.025);
  f.shape.face_width = shape == "flat" ? 0.2 : 0.0;
  if (motion == "oscillating") {
    f.pivot = {0.1, 0.06};
    f.arm_length = shape == "flat" ? 0.11 : 0.08;
  } else {
    f.offset = shape == "flat" ? 0.0 : 0.004;
  }
  return f;
}

SynthesisedCam make(const std::string& motion, const std::string& shape, int sigma = 1) {
  const double lift = motion == "oscillating" ? 12 * kDegToRad : 0.02;
  return SynthesisedCam(law_of(lift), make_follower_geometry(follower(motion, shape), 0.04, "scene.json"), sigma);
}

struct Kind {
  std::string motion, shape;
  int sigma;
};
void PrintTo(const Kind& k, std::ostream* os) { *os << k.motion << "_" << k.shape << (k.sigma > 0 ? "_ccw" : "_cw"); }

class EveryFollower : public ::testing::TestWithParam<Kind> {};

TEST_P(EveryFollower, ProfileDerivativesMatchFiniteDifferences) {
  const SynthesisedCam cam = make(GetParam().motion, GetParam().shape, GetParam().sigma);
  for (double deg : {10.0, 47.0, 100.0, 150.0, 200.0, 245.0, 290.0, 330.0}) {
    const double u = deg * kDegToRad;
    const CurvePoint p = cam.at(u);
    const Eigen::Vector2d d[3] = {p.dr, p.d2r, p.d3r};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 2; ++c) {
        auto g = [&](double x) {
          const CurvePoint q = cam.at(x);
          const Eigen::Vector2d v[3] = {q.r, q.dr, q.d2r};
          return v[k](c);
        };
        const test::FdEstimate fd = test::central_difference(g, u, 1e-4, 0.1);
        EXPECT_NEAR(d[k](c), fd.value, fd.tolerance + test::kAmplifiedRoundoff)
            << "derivative " << k + 1 << " at " << deg;
      }
  }
}

TEST_P(EveryFollower, ChecksPassForTheStandardDesignAndReportTheGeometry) {
  const SynthesisedCam cam = make(GetParam().motion, GetParam().shape, GetParam().sigma);
  const CamGeometryReport r = check_cam(cam, "scene.json");
  EXPECT_GT(r.min_radius_of_curvature, 0.0);
  // A flat face is pushed normal to itself, and its points move normal to it
  // (translating along its axis; oscillating about a pivot on the face line):
  // pressure angle 0.
  const bool flat_face = GetParam().shape == "flat";
  EXPECT_GE(r.max_pressure_angle_deg, 0.0);
  EXPECT_LT(r.max_pressure_angle_deg, flat_face ? test::kAmplifiedRoundoff : 60.0);
  if (!flat_face) {
    EXPECT_GT(r.max_pressure_angle_deg, 1.0);
  }
  // On the law, the pair parameter is the cam angle: the follower element
  // touches the profile at u = θ (circle: the centre on the centre curve;
  // flat: the face line through the contour point, its normal along the contour's).
  for (double deg : {30.0, 150.0, 250.0}) {
    const double theta = deg * kDegToRad;
    const SynthesisedCam::Kinematics k = cam.kinematics(theta);
    const double sg = GetParam().sigma;
    const Eigen::Vector2d r_world = Eigen::Rotation2Dd(sg * theta) * cam.at(theta).r;
    const Eigen::Vector2d t_world = Eigen::Rotation2Dd(sg * theta) * cam.at(theta).dr;
    EXPECT_NEAR(k.normal.dot(t_world), 0.0, test::kAmplifiedRoundoff)
        << deg;  // the contact normal is normal to the profile
    if (GetParam().shape == "flat") {
      EXPECT_NEAR((k.contact - r_world).norm(), 0.0, test::kRoundoff * test::kLengthScale) << deg;
    }
    EXPECT_GT(k.g_q, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Followers, EveryFollower,
                         ::testing::Values(Kind{"translating", "roller", 1}, Kind{"translating", "roller", -1},
                                           Kind{"translating", "flat", 1}, Kind{"translating", "flat", -1},
                                           Kind{"translating", "mushroom", 1}, Kind{"oscillating", "roller", 1},
                                           Kind{"oscillating", "roller", -1}, Kind{"oscillating", "flat", 1},
                                           Kind{"oscillating", "flat", -1}, Kind{"oscillating", "mushroom", 1}));

TEST(CamSynthesis, TranslatingRollerCentreCurveIsThePitchCurve) {
  const auto law = law_of(0.02);
  TranslatingRollerCam roller;
  roller.law = law.get();
  roller.base_radius = 0.04;
  roller.roller_radius = 0.01;
  roller.offset = 0.004;
  const SynthesisedCam cam = make("translating", "roller");
  for (int i = 0; i < 72; ++i) {
    const double u = i * 5 * kDegToRad;
    EXPECT_NEAR((cam.at(u).r - roller.pitch(u).r).norm(), 0.0, test::kExact * test::kLengthScale);
    EXPECT_NEAR((cam.at(u).d3r - roller.pitch(u).d3r).norm(), 0.0, test::kRoundoff);
    EXPECT_NEAR(cam.kinematics(u).pressure_angle, roller.pressure_angle(u), test::kRoundoff);
  }
}

TEST(CamSynthesis, TranslatingFlatContourIsSPrimeAcrossAndBasePlusSUp) {
  // Envelope of the lines y = r_b + s(θ) turned by −θ: the contact point is
  // (σ s', r_b + s) in the world and the contour's radius of curvature is r_b + s + s''.
  for (int sigma : {1, -1}) {
    const SynthesisedCam cam = make("translating", "flat", sigma);
    for (int i = 0; i < 36; ++i) {
      const double theta = i * 10 * kDegToRad + 0.1;
      const LawSample s = cam.law().eval(theta);
      const SynthesisedCam::Kinematics k = cam.kinematics(theta);
      EXPECT_NEAR(k.contact.x(), sigma * s.ds, test::kRoundoff * test::kLengthScale);
      EXPECT_NEAR(k.contact.y(), 0.04 + s.s, test::kRoundoff * test::kLengthScale);
      EXPECT_NEAR(k.face_offset, sigma * s.ds, test::kRoundoff * test::kLengthScale);
      EXPECT_NEAR(k.radius_of_curvature, 0.04 + s.s + s.d2s, test::kRoundoff);
      EXPECT_NEAR(k.g_q, 1.0, test::kExact);
      EXPECT_NEAR(k.pressure_angle, 0.0, test::kExact);
    }
  }
}

TEST(CamSynthesis, OscillatingRollerCentreIsOnTheArmCircle) {
  const SynthesisedCam cam = make("oscillating", "roller");
  const FollowerGeometry& f = cam.follower();
  const Eigen::Vector2d pivot(0.1, 0.06);
  for (int i = 0; i < 36; ++i) {
    const double theta = i * 10 * kDegToRad;
    const Eigen::Vector2d c = Eigen::Rotation2Dd(theta) * cam.at(theta).r;  // centre, world
    EXPECT_NEAR((c - pivot).norm(), 0.08, test::kRoundoff * test::kLengthScale);
    const double psi = std::atan2(c.y() - pivot.y(), c.x() - pivot.x());
    EXPECT_NEAR(std::remainder(psi - f.psi0 - f.kappa * cam.law().eval(theta).s, kTwoPi), 0.0,
                test::kRoundoff * kTwoPi);
  }
  EXPECT_NEAR(cam.at(330 * kDegToRad).r.norm(), 0.05,
              test::kRoundoff * test::kLengthScale);  // on the base-circle dwell
}

TEST(CamSynthesis, FlatFaceCuspNamesTheMinimumBaseRadius) {
  // A short, high rise: r_b + s + s'' > 0 fails for small base radii.
  const auto law = law_of(0.02, 60, 180, 240);
  double rb_min = 0.0;
  for (int i = 0; i < 360000; ++i) {
    const LawSample s = law->eval(kTwoPi * i / 360000);
    rb_min = std::max(rb_min, -(s.s + s.d2s));
  }
  ASSERT_GT(rb_min, 0.03);
  auto check = [&](double rb) {
    FollowerConfig f = follower("translating", "flat");
    return check_cam(SynthesisedCam(law, make_follower_geometry(f, rb, "scene.json"), 1), "scene.json");
  };
  EXPECT_NO_THROW(check(rb_min * 1.001));
  try {
    check(rb_min * 0.999);
    FAIL() << "a cusp was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam");
    EXPECT_NE(std::string(e.what()).find("cusp"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at cam angle"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("base radius above"), std::string::npos) << e.what();
  }
}

TEST(CamSynthesis, FaceTooNarrowIsADesignError) {
  FollowerConfig f = follower("translating", "flat");
  const auto law = law_of(0.02);
  double max_ds = 0.0;
  for (int i = 0; i < 36000; ++i) max_ds = std::max(max_ds, std::abs(law->eval(kTwoPi * i / 36000).ds));
  f.shape.face_width = 2.0 * max_ds * 1.001;
  EXPECT_NO_THROW(check_cam(SynthesisedCam(law, make_follower_geometry(f, 0.04, "s.json"), 1), "s.json"));
  f.shape.face_width = 2.0 * max_ds * 0.999;
  try {
    check_cam(SynthesisedCam(law, make_follower_geometry(f, 0.04, "s.json"), 1), "s.json");
    FAIL() << "a face too narrow was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.shape.face_width");
    EXPECT_NE(std::string(e.what()).find("at cam angle"), std::string::npos) << e.what();
  }
}

TEST(CamSynthesis, MushroomUndercutIsReported) {
  FollowerConfig f = follower("translating", "mushroom");
  f.shape.radius = 0.2;  // far larger than the pitch curve's convex radius at the rise
  try {
    check_cam(SynthesisedCam(law_of(0.02, 60, 180, 240), make_follower_geometry(f, 0.02, "s.json"), 1), "s.json");
    FAIL() << "an undercut was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam");
    EXPECT_NE(std::string(e.what()).find("mushroom radius"), std::string::npos) << e.what();
  }
}

TEST(CamSynthesis, EvaluatingTheProfileAllocatesNothing) {
  for (const Kind& k : {Kind{"translating", "roller", 1}, Kind{"translating", "flat", 1},
                        Kind{"oscillating", "flat", -1}, Kind{"oscillating", "mushroom", 1}}) {
    const SynthesisedCam cam = make(k.motion, k.shape, k.sigma);
    double sink = 0.0;
    const long before = test::allocation_count();
    for (int i = 0; i < 360; ++i) {
      const CurvePoint p = cam.at(i * kDegToRad);
      sink += p.d3r.x() + cam.kinematics(i * kDegToRad).g_q;
    }
    EXPECT_EQ(test::allocation_count() - before, 0) << k.motion << " " << k.shape;
    EXPECT_TRUE(std::isfinite(sink));
  }
}

TEST(FollowerGeometry, ImpossibleArmsAreInputErrors) {
  FollowerConfig f = follower("oscillating", "roller");
  f.arm_length = 0.01;  // cannot reach the base circle from the pivot
  try {
    make_follower_geometry(f, 0.04, "s.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.arm_length");
  }
  FollowerConfig g = follower("oscillating", "flat");
  g.pivot = {0.01, 0.02};  // inside the base circle
  try {
    make_follower_geometry(g, 0.04, "s.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.pivot");
  }
}

}  // namespace
}  // namespace camdyn
