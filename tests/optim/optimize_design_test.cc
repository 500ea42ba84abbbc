// The design space and kinematics of the optimize study: classic-law
// coefficients against their closed forms, the least-squares fit that starts
// the search, monotone bounds, continuity with a moving classic neighbour, and
// the config fields with their errors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/motion_law.h"
#include "io/json_archive.h"
#include "optim/optimize/design.h"
#include "optim/optimize/kinematics.h"
#include "optim/optimize/optimize_config.h"
#include "study/study.h"
#include "tolerance.h"

namespace camdyn::optim {
namespace {

// Sampling 4000 points per piece puts the sample next to any extremum within
// 1/8000 of the segment: the coefficient is low by at most ~f⁗·h²/8 ≈ 1e-7 relative.
constexpr double kSampledPeak = 1e-6;

const ConfigSource kDesignSource{"test.json", CAMDYN_SOURCE_DIR};

SceneConfig scene_with_law(const std::string& segments_json) {
  Json doc = Json::parse(R"({
    "mechanism": {
      "cam": { "base_radius": 0.04, "rpm": 1000, "motion_law": { "segments": )" +
                         segments_json + R"( } },
      "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": 1e10 } } })");
  return scene_from_json(doc, kDesignSource);
}

const char* kCycloidal = R"([
  { "type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.02 },
  { "type": "dwell", "end_deg": 180 },
  { "type": "return", "law": "cycloidal", "end_deg": 300, "lift": 0.02 },
  { "type": "dwell", "end_deg": 360 } ])";

LawKinematics kinematics_of(const SceneConfig& scene) {
  const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test.json");
  return law_kinematics(law, scene.mechanism.cam.motion_law.segments);
}

TEST(Kinematics, ClassicLawCoefficientsMatchTheirClosedForms) {
  const LawKinematics cyc = kinematics_of(scene_with_law(kCycloidal));
  ASSERT_EQ(cyc.segments.size(), 2u);
  for (const SegmentKinematics& s : cyc.segments) {
    EXPECT_NEAR(s.velocity_coefficient, 2.0, 2.0 * kSampledPeak);
    EXPECT_NEAR(s.acceleration_coefficient, 2.0 * kPi, 2.0 * kPi * kSampledPeak);
    EXPECT_NEAR(s.jerk_coefficient, 4.0 * kPi * kPi, 4.0 * kPi * kPi * kSampledPeak);
  }
  const double beta = 120.0 * kPi / 180.0;
  // The cycloidal peak (x = 1/4) falls on a sample: only rounding remains.
  constexpr double kOnASample = 1e-9;
  EXPECT_NEAR(cyc.peak_acceleration, 2.0 * kPi * 0.02 / (beta * beta), kOnASample);
  EXPECT_EQ(cyc.segments[1].type, "return");
  EXPECT_DOUBLE_EQ(cyc.segments[1].start_deg, 180.0);

  const LawKinematics p345 = kinematics_of(scene_with_law(R"([
    { "type": "rise", "law": "polynomial_345", "end_deg": 120, "lift": 0.02 },
    { "type": "return", "law": "polynomial_345", "end_deg": 360, "lift": 0.02 } ])"));
  const double ca = 10.0 / std::sqrt(3.0);  // 5.7735 at x = 1/2 ± √3/6
  EXPECT_NEAR(p345.segments[0].velocity_coefficient, 1.875, 1.875 * kSampledPeak);
  EXPECT_NEAR(p345.segments[0].acceleration_coefficient, ca, ca * kSampledPeak);
  EXPECT_NEAR(p345.segments[0].jerk_coefficient, 60.0, 60.0 * kSampledPeak);
}

TEST(DesignSpace, InitialFitReproducesTheBaselineLaw) {
  const SceneConfig base = scene_with_law(kCycloidal);
  const DesignSpace space(base, DesignConfig{}, "test.json");
  EXPECT_EQ(space.dimension(), 12);
  EXPECT_EQ(space.designed_segments(), (std::vector<std::size_t>{0, 2}));
  // A degree-5 spline with 12 control points against a cycloid: within 1e-4 of
  // the lift and 1 % of the peak acceleration.
  EXPECT_LT(space.fit_quality().max_lift_error, 1e-4);
  EXPECT_LT(space.fit_quality().max_acceleration_error, 1e-2);
  const SceneConfig fitted = space.scene(space.initial());
  const SegmentConfig& rise = fitted.mechanism.cam.motion_law.segments[0];
  EXPECT_EQ(rise.law, SegmentLaw::spline);
  EXPECT_EQ(rise.degree, 5);
  EXPECT_EQ(rise.control_points.size(), 6u);
  EXPECT_EQ(fitted.mechanism.cam.motion_law.segments[1].law, SegmentLaw::none);  // the dwell is untouched
  const LawKinematics k = kinematics_of(fitted);
  EXPECT_NEAR(k.segments[0].acceleration_coefficient, 2.0 * kPi, 0.02 * 2.0 * kPi);
}

// Any point of the box gives an ordered control polygon, hence a monotone rise.
TEST(DesignSpace, MonotoneBoundsKeepEveryDesignMonotone) {
  const SceneConfig base = scene_with_law(kCycloidal);
  const DesignSpace space(base, DesignConfig{}, "test.json");
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<double> x(space.dimension());
    for (int j = 0; j < space.dimension(); ++j)
      x[j] = std::uniform_real_distribution<double>(space.lower()[j], space.upper()[j])(rng);
    const SceneConfig scene = space.scene(x);
    for (std::size_t seg : space.designed_segments()) {
      const std::vector<double>& c = scene.mechanism.cam.motion_law.segments[seg].control_points;
      for (std::size_t j = 0; j < c.size(); ++j) {
        EXPECT_GE(c[j], j == 0 ? 0.0 : c[j - 1]);
        EXPECT_LE(c[j], 1.0);
      }
    }
    const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test.json");
    for (int i = 0; i <= 1000; ++i) {
      const double theta = (120.0 * i / 1000.0) * kPi / 180.0;
      EXPECT_GE(law.eval(theta).ds, -test::kAmplifiedRoundoff) << "trial " << trial << " at " << theta;
    }
  }
}

// A designed rise that ends where a harmonic return starts (no dwell): the
// boundary control points follow the harmonic's acceleration, which changes
// with the rise's end angle; s, s' and s'' stay continuous there for any design.
TEST(DesignSpace, MovingEndAngleKeepsContinuityWithAClassicNeighbour) {
  const SceneConfig base = scene_with_law(R"([
    { "type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.02 },
    { "type": "return", "law": "harmonic", "end_deg": 240, "lift": 0.02 },
    { "type": "dwell", "end_deg": 360 } ])");
  DesignConfig config;
  config.segments = {SegmentType::rise};
  config.end_deg_range.rise = std::vector<double>{100.0, 140.0};
  const DesignSpace space(base, config, "test.json");
  ASSERT_EQ(space.dimension(), 7);
  EXPECT_EQ(space.variables().back().name, "segments[0].end_deg");
  EXPECT_DOUBLE_EQ(space.initial().back(), 0.5);  // 120 within [100, 140]
  std::mt19937_64 rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    std::vector<double> x(space.dimension());
    for (double& v : x) v = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    const SceneConfig scene = space.scene(x);
    const double end_deg = scene.mechanism.cam.motion_law.segments[0].end_deg;
    EXPECT_NEAR(end_deg, 100.0 + 40.0 * x.back(), test::kAmplifiedRoundoff);
    const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test.json");
    const double te = end_deg * kPi / 180.0, eps = 1e-7;
    const LawSample left = law.eval(te - eps), right = law.eval(te + eps);
    // Continuous across te: s moves by O(ε²) (s' = 0 there), s' by ≈ 2ε·|s''|.
    constexpr double kJoin = 1e-9, kJoinSlope = 1e-6;  // [m], [m/rad]
    EXPECT_NEAR(left.s, right.s, kJoin);
    EXPECT_NEAR(left.ds, right.ds, kJoinSlope);
    EXPECT_NEAR(left.d2s, right.d2s, 1e-4 * std::abs(right.d2s) + 1e-6) << "trial " << trial;
    for (int i = 0; i < 1000; ++i)
      EXPECT_GE(law.eval(te * i / 1000.0).ds, -test::kAmplifiedRoundoff) << "trial " << trial;
  }
}

TEST(DesignSpace, InconsistentDesignsAreInputErrors) {
  const SceneConfig base = scene_with_law(kCycloidal);
  auto error_path = [&](const DesignConfig& c) -> std::string {
    try {
      DesignSpace space(base, c, "test.json");
    } catch (const InputError& e) {
      return e.path();
    }
    return "(no error)";
  };
  DesignConfig overlap;
  overlap.end_deg_range.rise = std::vector<double>{100.0, 190.0};  // beyond the dwell's end at 180
  EXPECT_EQ(error_path(overlap), "design.end_deg_range.rise");
  DesignConfig outside;
  outside.end_deg_range.ret = std::vector<double>{310.0, 340.0};  // baseline 300 not inside
  EXPECT_EQ(error_path(outside), "design.end_deg_range.return");
  DesignConfig not_designed;
  not_designed.segments = {SegmentType::rise};
  not_designed.end_deg_range.ret = std::vector<double>{280.0, 320.0};
  EXPECT_EQ(error_path(not_designed), "design.end_deg_range.return");

  const SceneConfig rise_only = scene_with_law(R"([
    { "type": "rise", "law": "cycloidal", "end_deg": 180, "lift": 0.02 },
    { "type": "return", "law": "cycloidal", "end_deg": 360, "lift": 0.02 } ])");
  DesignConfig last;
  last.end_deg_range.ret = std::vector<double>{300.0, 359.0};
  try {
    DesignSpace space(rise_only, last, "test.json");
    ADD_FAILURE() << "the last segment's end cannot move";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "design.end_deg_range.return");
  }

  Json doc = Json::parse(R"({ "mechanism": {
    "cam": { "base_radius": 0.04, "rpm": 1000,
             "motion_law": { "spline": { "degree": 5, "knots_deg": [0, 60, 120, 180, 240, 300],
                                         "lift": [0, 0.01, 0.02, 0.02, 0.01, 0] } } },
    "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3, "spring": { "stiffness": 5000 } },
    "contact": { "stiffness": 1e10 } } })");
  try {
    DesignSpace space(scene_from_json(doc, kDesignSource), DesignConfig{}, "test.json");
    ADD_FAILURE() << "a periodic spline law has no segments to design";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam.motion_law");
  }
}

TEST(OptimizeConfig, DefaultsRoundTripAndUnknownKeysAreNamed) {
  const OptimizeStudyConfig defaults =
      optimize_config_from_json(Json::parse(R"({ "operating_rpm": [1000] })"), kDesignSource);
  EXPECT_EQ(defaults.design.control_points, 6);
  EXPECT_EQ(defaults.optimizer.algorithm, "LN_COBYLA");
  EXPECT_EQ(*defaults.constraints.max_pressure_angle_deg, 30.0);
  EXPECT_EQ(optimize_config_from_json(to_json(defaults), kDesignSource), defaults);

  auto error_of = [&](const char* text) -> InputError {
    try {
      optimize_config_from_json(Json::parse(text), kDesignSource);
    } catch (const InputError& e) {
      return e;
    }
    return InputError("", "(no error)", "");
  };
  const InputError typo = error_of(R"({ "operating_rpm": [1000], "optimizer": { "algoritm": "LN_SBPLX" } })");
  EXPECT_EQ(typo.path(), "optimizer.algoritm");
  EXPECT_NE(typo.reason().find("algorithm"), std::string::npos) << typo.what();
  EXPECT_EQ(typo.file(), "test.json");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [] })").path(), "operating_rpm");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [1000], "optimizer": { "algorithm": "GN_ISRES", "starts": 3 } })").path(),
            "optimizer.starts");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [1000], "objective": { "separation": 0 } })").path(), "objective");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [1000], "design": { "segments": ["rise", "dwell"] } })").path(),
            "design.segments[1]");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [1000], "design": { "end_deg_range": { "rise": [140, 100] } } })").path(),
            "design.end_deg_range.rise");
  EXPECT_EQ(error_of(R"({ "operating_rpm": [1000], "constraints": { "min_contact_force": 0 } })").path(),
            "constraints.min_contact_force");
}

}  // namespace
}  // namespace camdyn::optim
