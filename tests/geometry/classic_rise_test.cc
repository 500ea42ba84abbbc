// The classic normalised rise laws f(x), x ∈ [0, 1]: boundary values, closed-form
// derivatives against finite differences, and the textbook peak coefficients.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/constants.h"
#include "finite_difference.h"
#include "geometry/motion_law.h"
#include "law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

struct ClassicCase {
  std::string name;
  double peak_velocity;           ///< max f' (textbook C_v)
  double peak_acceleration;       ///< max |f''| (textbook C_a)
  double accel_at_0, accel_at_1;  ///< f''(0), f''(1)
};

void PrintTo(const ClassicCase& c, std::ostream* os) { *os << c.name; }

class ClassicRise : public ::testing::TestWithParam<ClassicCase> {};

TEST_P(ClassicRise, StartsAtZeroEndsAtOneWithZeroVelocity) {
  const auto f = classic_rise(parse_enum<SegmentLaw>(GetParam().name));
  ASSERT_NE(f, nullptr);
  const LawSample a = f->eval(0.0), b = f->eval(1.0);
  EXPECT_NEAR(a.s, 0.0, test::kRoundoff);
  EXPECT_NEAR(b.s, 1.0, test::kRoundoff);
  EXPECT_NEAR(a.ds, 0.0, test::kRoundoff);
  EXPECT_NEAR(b.ds, 0.0, test::kRoundoff);
  // f'' at the ends is scaled by up to (4π)² inside the law: allow that many ulps more.
  EXPECT_NEAR(a.d2s, GetParam().accel_at_0, test::kAmplifiedRoundoff);
  EXPECT_NEAR(b.d2s, GetParam().accel_at_1, test::kAmplifiedRoundoff);
}

TEST_P(ClassicRise, IsPointSymmetricAboutTheMidpoint) {
  // All six laws satisfy f(1 − x) = 1 − f(x), a check independent of the formulas.
  const auto f = classic_rise(parse_enum<SegmentLaw>(GetParam().name));
  for (int i = 0; i <= 100; ++i) {
    const double x = i / 100.0;
    EXPECT_NEAR(f->eval(1.0 - x).s, 1.0 - f->eval(x).s, test::kRoundoff) << "x = " << x;
    EXPECT_NEAR(f->eval(1.0 - x).ds, f->eval(x).ds, 2 * kPi * test::kRoundoff) << "x = " << x;
  }
}

TEST_P(ClassicRise, DerivativesMatchFiniteDifferences) {
  const auto f = classic_rise(parse_enum<SegmentLaw>(GetParam().name));
  // h small against the shortest feature (an eighth of the rise); the grid
  // (i + 0.5)/40 stays ≥ 0.0125 ≫ 2h away from the breakpoints k/8 of the
  // piecewise laws.
  constexpr double h = 1e-4;
  for (int i = 0; i < 40; ++i) {
    const double x = (i + 0.5) / 40.0;
    const LawSample exact = f->eval(x);
    const auto d1 = test::central_difference([&](double t) { return f->eval(t).s; }, x, h);
    const auto d2 = test::central_difference([&](double t) { return f->eval(t).ds; }, x, h);
    const auto d3 = test::central_difference([&](double t) { return f->eval(t).d2s; }, x, h);
    EXPECT_NEAR(exact.ds, d1.value, d1.tolerance) << "f' at x = " << x;
    EXPECT_NEAR(exact.d2s, d2.value, d2.tolerance) << "f'' at x = " << x;
    EXPECT_NEAR(exact.d3s, d3.value, d3.tolerance) << "f''' at x = " << x;
  }
}

TEST_P(ClassicRise, PeakCoefficientsMatchTextbookValues) {
  const auto f = classic_rise(parse_enum<SegmentLaw>(GetParam().name));
  double peak_v = 0.0, peak_a = 0.0;
  // 1e5 samples locate a smooth maximum to ≈ |f''''|·(1e-5)²/8 < 1e-6.
  for (int i = 0; i <= 100000; ++i) {
    const LawSample l = f->eval(i / 100000.0);
    peak_v = std::max(peak_v, l.ds);
    peak_a = std::max(peak_a, std::abs(l.d2s));
  }
  // Textbook coefficients are quoted to 2–3 decimals.
  EXPECT_NEAR(peak_v, GetParam().peak_velocity, test::kQuoted);
  EXPECT_NEAR(peak_a, GetParam().peak_acceleration, test::kQuoted);
}

INSTANTIATE_TEST_SUITE_P(AllLaws, ClassicRise,
                         ::testing::Values(ClassicCase{"cycloidal", 2.0, 2 * kPi, 0.0, 0.0},
                                           ClassicCase{"polynomial_345", 1.875, 5.77, 0.0, 0.0},
                                           ClassicCase{"polynomial_4567", 2.1875, 7.52, 0.0, 0.0},
                                           ClassicCase{"harmonic", kPi / 2, kPi* kPi / 2, kPi* kPi / 2, -kPi* kPi / 2},
                                           ClassicCase{"modified_trapezoid", 2.0, 4.89, 0.0, 0.0},
                                           ClassicCase{"modified_sine", 1.76, 5.53, 0.0, 0.0}),
                         [](const ::testing::TestParamInfo<ClassicCase>& tp) { return tp.param.name; });

TEST(ClassicRiseNames, OnlyTheClassicLawsHaveAShape) {
  EXPECT_FALSE(enum_from_name<SegmentLaw>("cubic").has_value());
  EXPECT_EQ(classic_rise(SegmentLaw::spline), nullptr);
  EXPECT_EQ(classic_rise(SegmentLaw::none), nullptr);
  for (const SegmentLaw law : classic_rise_laws()) EXPECT_NE(classic_rise(law), nullptr) << to_string(law);
}

TEST(ClassicRiseModified, AccelerationFollowsThePrescribedShape) {
  // The piecewise laws are built from their acceleration shapes: check the
  // shape itself at the span centres (as multiples of the peak, f''(1/8)).
  const auto ms = classic_rise(SegmentLaw::modified_sine);
  const double ca = ms->eval(0.125).d2s;
  EXPECT_NEAR(ms->eval(0.5).d2s, 0.0, test::kAmplifiedRoundoff);
  EXPECT_NEAR(ms->eval(0.875).d2s, -ca, test::kAmplifiedRoundoff);
  EXPECT_NEAR(ms->eval(0.0625).d2s, ca * std::sin(kPi / 4), test::kAmplifiedRoundoff);
  const auto mt = classic_rise(SegmentLaw::modified_trapezoid);
  const double ct = mt->eval(0.25).d2s;
  EXPECT_NEAR(mt->eval(0.125).d2s, ct, test::kAmplifiedRoundoff);
  EXPECT_NEAR(mt->eval(0.375).d2s, ct, test::kAmplifiedRoundoff);
  EXPECT_NEAR(mt->eval(0.5).d2s, 0.0, test::kAmplifiedRoundoff);
  EXPECT_NEAR(mt->eval(0.75).d2s, -ct, test::kAmplifiedRoundoff);
  EXPECT_NEAR(mt->eval(0.0625).d2s, ct * std::sin(kPi / 4), test::kAmplifiedRoundoff);
}

}  // namespace
}  // namespace camdyn
