// Motion laws built from rise / dwell / return segments with the classic laws:
// continuity, periodicity, derivatives, and the InputError of each bad input.
#include "geometry/motion_law.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "common/constants.h"
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::build;
using test::dwell;
using test::kLawPath;
using test::segment;
using test::segments;

const std::string kSegs = kLawPath + ".segments";

/// Rise 0–120°, dwell to 180°, return 180–300°, dwell to 360° with one law.
MotionLawConfig rise_dwell_return(const std::string& law, double lift = 0.02) {
  return segments({segment("rise", law, 120, lift), dwell(180), segment("return", law, 300, lift), dwell(360)});
}

class SegmentLaw : public ::testing::TestWithParam<std::string> {};

TEST_P(SegmentLaw, IsC2AcrossSegmentBoundaries) {
  const MotionLaw law = build(rise_dwell_return(GetParam()));
  for (double deg : {0.0, 120.0, 180.0, 300.0}) test::expect_c2_at(law, deg * kDegToRad, std::to_string(deg) + "°");
}

TEST_P(SegmentLaw, ReachesTheLiftAndStartsAtZero) {
  const MotionLaw law = build(rise_dwell_return(GetParam()));
  EXPECT_EQ(law.eval(0.0).s, 0.0);
  EXPECT_NEAR(law.eval(150 * kDegToRad).s, 0.02, test::kExact * 0.02);  // dwell level, exact up to rounding
  EXPECT_NEAR(law.lift(), 0.02, test::kExact * 0.02);
  EXPECT_NEAR(law.min_s(), 0.0, test::kExact * 0.02);
  EXPECT_EQ(law.eval(330 * kDegToRad).s, 0.0);
}

TEST_P(SegmentLaw, IsPeriodicForNegativeAndLargeAngles) {
  const MotionLaw law = build(rise_dwell_return(GetParam()));
  const test::RateBounds b = test::sampled_bounds(law);
  for (double th : {0.1, 1.0, 2.5, 4.0, 6.0}) {
    for (int k : {-3, -1, 1, 7, 1500}) {
      const double shifted = th + kTwoPi * k;  // up to ≈ 9.4e3 rad
      // Forming θ + 2πk rounds by ≤ ulp(|θ + 2πk|) and the reduction adds as much again.
      const double dth = 4 * std::numeric_limits<double>::epsilon() * std::abs(shifted);
      const LawSample a = law.eval(th), p = law.eval(shifted);
      EXPECT_NEAR(p.s, a.s, 2 * b.ds * dth + test::kExact * law.max_s()) << th << " + 2π·" << k;
      EXPECT_NEAR(p.ds, a.ds, 2 * b.d2s * dth + test::kExact * b.ds) << th << " + 2π·" << k;
      EXPECT_NEAR(p.d2s, a.d2s, 2 * b.d3s * dth + test::kExact * b.d2s) << th << " + 2π·" << k;
    }
  }
  // The ends of the period map onto θ = 0.
  EXPECT_EQ(law.eval(kTwoPi).s, law.eval(0.0).s);
  EXPECT_EQ(law.eval(-1e-300).s, law.eval(0.0).s);
}

TEST_P(SegmentLaw, DerivativesMatchFiniteDifferences) {
  const MotionLaw law = build(rise_dwell_return(GetParam()));
  test::expect_derivatives_match_fd(law, {0.0, 120 * kDegToRad, 180 * kDegToRad, 300 * kDegToRad, kTwoPi});
}

INSTANTIATE_TEST_SUITE_P(C2Laws, SegmentLaw,
                         ::testing::Values("cycloidal", "polynomial_345", "polynomial_4567", "modified_trapezoid",
                                           "modified_sine"));

TEST(SegmentLawHarmonic, AccelerationJumpsAtADwell) {
  // Harmonic is only C¹ next to a dwell; this also shows the C² check can fail.
  const MotionLaw law = build(rise_dwell_return("harmonic"));
  constexpr double delta = 1e-9;  // [rad]
  const double jump = law.eval(delta).d2s - law.eval(-delta).d2s;
  const double expected = 0.02 * std::numbers::pi * std::numbers::pi / 2 / std::pow(120 * kDegToRad, 2);
  // s'' moves by O(δ·|s'''|) = O(δ²) relative on either side (s''' = 0 at the dwell end).
  EXPECT_NEAR(jump, expected, delta * expected);
}

TEST(SegmentLawBuild, StartingWithAReturnShiftsTheBaseToZero) {
  const MotionLaw law = build(segments({dwell(30), segment("return", "cycloidal", 150, 0.01), dwell(200),
                                        segment("rise", "polynomial_345", 360, 0.01)}));
  EXPECT_NEAR(law.eval(10 * kDegToRad).s, 0.01, test::kExact * 0.01);
  EXPECT_NEAR(law.eval(170 * kDegToRad).s, 0.0, test::kExact * 0.01);
  EXPECT_NEAR(law.min_s(), 0.0, test::kExact * 0.01);
  EXPECT_NEAR(law.max_s(), 0.01, test::kExact * 0.01);
}

TEST(SegmentLawBuild, RoundingLevelLiftMismatchIsClosedExactly) {
  // 0.1 + 0.2 ≠ 0.3 in binary, a relative 2e-16 apart: accepted, and the law
  // still closes (s just below 2π equals s(0) to rounding).
  const MotionLaw law = build(segments({segment("rise", "cycloidal", 60, 0.1), segment("rise", "cycloidal", 120, 0.2),
                                        segment("return", "cycloidal", 360, 0.3)}));
  EXPECT_NEAR(law.eval(kTwoPi - 1e-12).s, 0.0, test::kExact * 0.1);  // ulps of the 0.1 m step
}

TEST(SegmentLawBuild, OscillatingLiftDegIsInRadians) {
  SegmentConfig rise = segment("rise", "cycloidal", 90);
  rise.lift_deg = 20.0;
  SegmentConfig ret = segment("return", "cycloidal", 270);
  ret.lift_deg = 20.0;
  const MotionLaw law = build(segments({rise, dwell(180), ret, dwell(360)}));
  EXPECT_NEAR(law.eval(135 * kDegToRad).s, 20 * kDegToRad, test::kEps * 20 * kDegToRad);  // one rounding
}

TEST(SegmentLawBuild, SingleDwellIsAConstantLaw) {
  const MotionLaw law = build(segments({dwell(360)}));
  EXPECT_EQ(law.eval(1.0).s, 0.0);
  EXPECT_EQ(law.lift(), 0.0);
}

// ---------------------------------------------------------------- errors

TEST(SegmentLawErrors, SegmentsNotCovering360) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[3].end_deg = 350;
  test::expect_input_error(c, kSegs + "[3].end_deg", "360");
}

TEST(SegmentLawErrors, DecreasingEndDeg) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[2].end_deg = 100;  // before segment 1 ends (180°)
  test::expect_input_error(c, kSegs + "[2].end_deg", "greater");
}

TEST(SegmentLawErrors, EndBeyond360) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[2].end_deg = 400;
  test::expect_input_error(c, kSegs + "[2].end_deg", "360");
}

// A denormal end angle (found by the scene fuzzer) vanished in radians and
// made a segment of zero span; any span under 1e-6° is refused.
TEST(SegmentLawErrors, ASpanTooShortToTurnThroughNamesTheEndAngle) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[0].end_deg = 5e-324;
  test::expect_input_error(c, kSegs + "[0].end_deg", "at least 1e-06");
  c.segments[0].end_deg = 1e-7;
  test::expect_input_error(c, kSegs + "[0].end_deg", "at least 1e-06");
}

TEST(SegmentLawErrors, LiftMismatch) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[2].lift = 0.019;
  test::expect_input_error(c, kSegs, "lift mismatch");
}

TEST(SegmentLawErrors, RiseWithoutALaw) {
  // An unknown word never gets here (the loader rejects it); a rise built in
  // code without a law is named by the geometry.
  auto c = rise_dwell_return("cycloidal");
  c.segments[0].law = camdyn::SegmentLaw::none;
  test::expect_input_error(c, kSegs + "[0].law", "unknown law");
}

TEST(SegmentLawErrors, NegativeOrZeroLift) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[0].lift = -0.02;
  test::expect_input_error(c, kSegs + "[0].lift", "> 0");
  c.segments[0].lift = 0.0;
  test::expect_input_error(c, kSegs + "[0].lift", "> 0");
}

TEST(SegmentLawErrors, BothOrNeitherOfLiftAndLiftDeg) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[2].lift_deg = 3.0;
  test::expect_input_error(c, kSegs + "[2]", "exactly one");
  c.segments[2].lift_deg.reset();
  c.segments[2].lift.reset();  // a return without a lift goes back down by the rise (docs/config.md `motion_law`)
  EXPECT_NO_THROW(test::build(c));
  c.segments[0].lift.reset();  // a rise needs one
  test::expect_input_error(c, kSegs + "[0]", "exactly one");
}

TEST(SegmentLawErrors, MixedLiftUnits) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[2].lift.reset();
  c.segments[2].lift_deg = 1.0;
  test::expect_input_error(c, kSegs + "[2].lift_deg", "mixes");
}

TEST(SegmentLawErrors, UnknownTypeAndDwellWithLift) {
  auto c = rise_dwell_return("cycloidal");
  c.segments[1].type = SegmentType::unset;
  test::expect_input_error(c, kSegs + "[1].type", "unknown segment type");
  c.segments[1].type = SegmentType::dwell;
  c.segments[1].lift = 0.01;
  test::expect_input_error(c, kSegs + "[1]", "dwell");
}

TEST(SegmentLawErrors, NoLawOrTwoKinds) {
  test::expect_input_error(MotionLawConfig{}, kLawPath, "one of");
  auto c = rise_dwell_return("cycloidal");
  c.spline = PeriodicSplineConfig{};
  test::expect_input_error(c, kLawPath, "only one");
}

}  // namespace
}  // namespace camdyn
