// Spline motion laws: spline segments (boundary control points matching the
// neighbours to second order) and whole-cycle periodic splines, inline or
// from a lift table.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "common/constants.h"
#include "io/config.h"  // load_table_rows
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::build;
using test::dwell;
using test::kLawPath;
using test::segment;
using test::segments;

SegmentConfig spline(const std::string& type, double end_deg, double lift, std::vector<double> control_points,
                     int degree = 5) {
  SegmentConfig s = segment(type, "spline", end_deg, lift);
  s.degree = degree;
  s.control_points = std::move(control_points);
  return s;
}

// ---------------------------------------------------------------- segments

TEST(SplineSegment, IsC2BetweenDwells) {
  const MotionLaw law = build(segments(
      {dwell(30), spline("rise", 150, 0.02, {0.1, 0.5, 0.9}), dwell(200), segment("return", "cycloidal", 360, 0.02)}));
  for (double deg : {30.0, 150.0}) test::expect_c2_at(law, deg * kDegToRad, std::to_string(deg) + "°");
  EXPECT_NEAR(law.eval(30 * kDegToRad).s, 0.0, test::kEps * 0.02);
  EXPECT_NEAR(law.eval(150 * kDegToRad).s, 0.02, test::kExact * 0.02);
}

TEST(SplineSegment, IsC2WithHarmonicAndCycloidalNeighbours) {
  // Harmonic ends with f'' = −π²/2 ≠ 0, which the spline has to pick up.
  const MotionLaw law =
      build(segments({segment("rise", "harmonic", 60, 0.01), spline("rise", 150, 0.01, {0.3, 0.6}), dwell(200),
                      spline("return", 300, 0.01, {0.2, 0.5, 0.8}, 7), segment("return", "cycloidal", 360, 0.01)}));
  const double a60 = law.eval(60 * kDegToRad).d2s;
  EXPECT_LT(a60, -0.01);  // the boundary acceleration is really nonzero
  for (double deg : {60.0, 150.0, 200.0, 300.0}) test::expect_c2_at(law, deg * kDegToRad, std::to_string(deg) + "°");
  test::expect_derivatives_match_fd(law,
                                    {0.0, 60 * kDegToRad, 150 * kDegToRad, 200 * kDegToRad, 300 * kDegToRad, kTwoPi});
}

TEST(SplineSegment, AdjacentSplinesMeetAtRest) {
  // A spline next to a spline uses zero velocity and acceleration at their boundary.
  const MotionLaw law = build(segments({spline("rise", 120, 0.01, {0.5}, 3), spline("return", 360, 0.01, {0.4, 0.6})}));
  for (double deg : {0.0, 120.0}) {
    const LawSample l = law.eval(deg * kDegToRad);
    EXPECT_NEAR(l.ds, 0.0, test::kRoundoff * 0.01) << deg;
    EXPECT_NEAR(l.d2s, 0.0, test::kRoundoff * 0.01) << deg;
    test::expect_c2_at(law, deg * kDegToRad, std::to_string(deg) + "°");
  }
}

class SplineSegmentDegree : public ::testing::TestWithParam<int> {};

TEST_P(SplineSegmentDegree, LinearRampControlPointsGiveAMonotoneRise) {
  // With dwell neighbours the control polygon is 0,0,0, ramp, 1,1,1: monotone,
  // so the spline is monotone (variation diminishing property).
  std::vector<double> ramp(6);
  for (int j = 0; j < 6; ++j) ramp[j] = (j + 1) / 7.0;
  const MotionLaw law = build(segments({dwell(20), spline("rise", 110, 0.015, ramp, GetParam()), dwell(200),
                                        segment("return", "polynomial_345", 360, 0.015)}));
  double max_ds = 0.0, min_ds = 0.0;
  for (int i = 0; i <= 9000; ++i) {
    const double ds = law.eval((20 + 90.0 * i / 9000) * kDegToRad).ds;
    max_ds = std::max(max_ds, ds);
    min_ds = std::min(min_ds, ds);
  }
  EXPECT_GT(max_ds, 0.0);
  EXPECT_GE(min_ds, -test::kExact * max_ds);  // rounding only
  EXPECT_NEAR(law.eval(110 * kDegToRad).s, 0.015, test::kExact * 0.015);
  test::expect_c2_at(law, 20 * kDegToRad, "20°");
  test::expect_c2_at(law, 110 * kDegToRad, "110°");
  test::expect_derivatives_match_fd(law, {0.0, 20 * kDegToRad, 110 * kDegToRad, 200 * kDegToRad, kTwoPi});
}

INSTANTIATE_TEST_SUITE_P(Degrees, SplineSegmentDegree, ::testing::Values(3, 5, 7));

TEST(SplineSegment, WorksWithOnlyTheBoundaryControlPoints) {
  const MotionLaw law =
      build(segments({spline("rise", 90, 0.01, {}), dwell(180), segment("return", "modified_sine", 360, 0.01)}));
  EXPECT_NEAR(law.eval(90 * kDegToRad).s, 0.01, test::kExact * 0.01);
  EXPECT_NEAR(law.eval(45 * kDegToRad).s, 0.005, test::kExact * 0.01);  // degree 5 Bézier 0,0,0,1,1,1 is symmetric
  test::expect_c2_at(law, 90 * kDegToRad, "90°");
}

TEST(SplineSegment, TooFewControlPointsForTheDegree) {
  test::expect_input_error(
      segments({spline("rise", 90, 0.01, {0.5}, 7), dwell(180), segment("return", "cycloidal", 360, 0.01)}),
      kLawPath + ".segments[0].control_points", "at least 8");
}

TEST(SplineSegment, DegreeBelowThree) {
  test::expect_input_error(
      segments({spline("rise", 90, 0.01, {0.5}, 2), dwell(180), segment("return", "cycloidal", 360, 0.01)}),
      kLawPath + ".segments[0].degree", "[3,");
}

// ---------------------------------------------------------------- periodic

const std::vector<double> kKnotsDeg = {0, 30, 60, 90, 120, 150, 180, 210, 240, 270, 300, 330};
const std::vector<double> kLifts = {0.0,   0.001, 0.004, 0.008, 0.0115, 0.0125,
                                    0.012, 0.009, 0.005, 0.002, 0.0005, 0.0};  // [m]
const std::vector<double> kUnevenKnotsDeg = {0, 20, 45, 90, 100, 150, 200, 260, 300, 340};
const std::vector<double> kUnevenLifts = {0.0, 0.002, 0.006, 0.010, 0.011, 0.012, 0.007, 0.003, 0.001, 0.0};

MotionLawConfig periodic(int degree, std::vector<double> knots, std::vector<double> lift) {
  MotionLawConfig c;
  c.spline = PeriodicSplineConfig{degree, std::move(knots), std::move(lift)};
  return c;
}

struct PeriodicCase {
  int degree;
  bool uneven;
};
void PrintTo(const PeriodicCase& c, std::ostream* os) {
  *os << "degree " << c.degree << (c.uneven ? ", uneven knots" : ", uniform knots");
}

class PeriodicSpline : public ::testing::TestWithParam<PeriodicCase> {
 protected:
  const std::vector<double>& knots() const { return GetParam().uneven ? kUnevenKnotsDeg : kKnotsDeg; }
  const std::vector<double>& lifts() const { return GetParam().uneven ? kUnevenLifts : kLifts; }
  MotionLaw law() const { return build(periodic(GetParam().degree, knots(), lifts())); }
  /// Breakpoints [deg]: the knots for odd degree, the midpoints between them for even.
  std::vector<double> breakpoints_deg() const {
    if (GetParam().degree % 2 == 1) return knots();
    std::vector<double> b;
    for (std::size_t j = 0; j < knots().size(); ++j)
      b.push_back(0.5 * (knots()[j] + (j + 1 < knots().size() ? knots()[j + 1] : 360.0)));
    return b;
  }
};

TEST_P(PeriodicSpline, InterpolatesTheKnotsExactly) {
  const MotionLaw l = law();
  // The 12×12 collocation system is well conditioned: residuals are a few ulps of 0.01 m.
  for (std::size_t j = 0; j < knots().size(); ++j)
    EXPECT_NEAR(l.eval(knots()[j] * kDegToRad).s, lifts()[j], test::kAmplifiedRoundoff * 0.01) << knots()[j] << "°";
}

TEST_P(PeriodicSpline, IsPeriodicAndSmoothAtItsBreakpoints) {
  const MotionLaw l = law();
  for (double th : {0.3, 2.0, 5.5}) {
    EXPECT_NEAR(l.eval(th + kTwoPi).s, l.eval(th).s, test::kRoundoff * 0.01);
    EXPECT_NEAR(l.eval(th - 2 * kTwoPi).ds, l.eval(th).ds, test::kRoundoff * test::kLengthScale);
  }
  // s, s', s'' continuous (degree − 1 ≥ 2) ...
  for (double b : breakpoints_deg()) test::expect_c2_at(l, b * kDegToRad, std::to_string(b) + "°");
  if (GetParam().degree < 5) return;
  // ... and s''' too for degree ≥ 5 (degree − 1 ≥ 4 > 3): a continuous s''' changes by
  // at most 2δ·max|s''''| across a breakpoint; max|s''''| is bounded by the
  // largest sampled difference quotient of s''' (step 1e-4 rad), times 2.
  double lip = 0.0;
  for (int i = 0; i < 62832; ++i) {
    const double th = i * 1e-4;
    lip = std::max(lip, std::abs(l.eval(th + 1e-4).d3s - l.eval(th).d3s) / 1e-4);
  }
  constexpr double delta = 1e-8;
  for (double b : breakpoints_deg())
    EXPECT_NEAR(l.eval(b * kDegToRad - delta).d3s, l.eval(b * kDegToRad + delta).d3s, 2 * delta * 2 * lip)
        << "s''' at " << b << "°";
}

TEST_P(PeriodicSpline, DerivativesMatchFiniteDifferences) {
  std::vector<double> breaks;
  for (double b : breakpoints_deg()) breaks.push_back(b * kDegToRad);
  breaks.push_back(kTwoPi);
  test::expect_derivatives_match_fd(law(), breaks);
}

INSTANTIATE_TEST_SUITE_P(Degrees, PeriodicSpline,
                         ::testing::Values(PeriodicCase{3, false}, PeriodicCase{4, false}, PeriodicCase{5, false},
                                           PeriodicCase{5, true}, PeriodicCase{6, true}, PeriodicCase{7, false}),
                         [](const ::testing::TestParamInfo<PeriodicCase>& tp) {
                           return "degree" + std::to_string(tp.param.degree) + (tp.param.uneven ? "Uneven" : "Uniform");
                         });

TEST(PeriodicTable, GivesTheSameLawAsTheInlineSpline) {
  MotionLawConfig c;
  c.table = TableConfig{CAMDYN_TEST_DATA_DIR "/geometry/periodic_lift.csv", "angle_deg", "lift", 5, {}, {}, {}};
  load_table_rows(*c.table);
  const MotionLaw from_table = build(c);
  const MotionLaw inline_law = build(periodic(5, kKnotsDeg, kLifts));
  // Same numbers in, same arithmetic: equal to rounding.
  for (int i = 0; i < 720; ++i) {
    const double th = i * 0.5 * kDegToRad;
    EXPECT_NEAR(from_table.eval(th).s, inline_law.eval(th).s, test::kExact * 0.01);
    EXPECT_NEAR(from_table.eval(th).d2s, inline_law.eval(th).d2s, test::kRoundoff * test::kLengthScale);
  }
}

class PeriodicTableErrors : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + "camdyn_geometry_" + name;
    std::ofstream(path) << text;
    return path;
  }
  MotionLawConfig table(const std::string& file) {
    MotionLawConfig c;
    c.table = TableConfig{file, "angle_deg", "lift", 3, {}, {}, {}};
    return c;
  }
  void expect(const MotionLawConfig& c, const std::string& file, const std::string& path,
              const std::string& reason_part) {
    try {
      MotionLawConfig loaded = c;  // the loader reads the rows, the geometry checks them
      load_table_rows(*loaded.table);
      build(loaded);
      ADD_FAILURE() << "no InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << e.what();
      EXPECT_EQ(e.path(), path) << e.what();
      EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
    }
  }
};

TEST_F(PeriodicTableErrors, AnglesNotIncreasingNameTheLine) {
  const std::string f = write("decreasing.csv", "angle_deg,lift\n0,0\n90,1\n# note\n80,2\n200,1\n");
  expect(table(f), f, "line 5", "greater");
}

TEST_F(PeriodicTableErrors, ClosingRowDifferentFromTheFirst) {
  const std::string f = write("closing.csv", "angle_deg,lift\n0,0\n90,1\n180,2\n270,1\n360,0.5\n");
  expect(table(f), f, "line 6", "repeat");
}

TEST_F(PeriodicTableErrors, MissingFileAndTooFewRows) {
  const std::string missing = ::testing::TempDir() + "camdyn_no_such_table.csv";
  expect(table(missing), missing, "mechanism.cam.motion_law.table.file", "cannot open");  // the field that named it
  const std::string f = write("short.csv", "angle_deg,lift\n0,0\n90,1\n180,0\n");
  expect(table(f), f, "column angle_deg", "at least 4");
}

TEST(PeriodicSplineErrors, NameTheFieldAndIndex) {
  const std::string at = kLawPath + ".spline";
  auto knots = kKnotsDeg;
  knots[3] = 60;  // repeats knot 2
  test::expect_input_error(periodic(5, knots, kLifts), at + ".knots_deg[3]", "greater");
  knots = kKnotsDeg;
  knots.back() = 360;
  test::expect_input_error(periodic(5, knots, kLifts), at + ".knots_deg[11]", "[0, 360)");
  test::expect_input_error(periodic(5, {0, 60, 120, 180, 240}, {0, 1, 2, 1, 0}), at + ".knots_deg", "at least 6");
  test::expect_input_error(periodic(5, kKnotsDeg, {0.0, 0.001}), at + ".lift", "2 lift values");
  auto lifts = kLifts;
  lifts[2] = std::nan("");
  test::expect_input_error(periodic(5, kKnotsDeg, lifts), at + ".lift[2]", "finite");
  test::expect_input_error(periodic(2, kKnotsDeg, kLifts), at + ".degree", "[3,");
}

}  // namespace
}  // namespace camdyn
