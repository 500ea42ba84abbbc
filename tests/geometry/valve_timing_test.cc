// Valvetrain conventions (geometry/valve_timing.h) against laws whose
// checking-height crossings, peak and ramp ends are known in closed form.
#include "geometry/valve_timing.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "law_checks.h"

namespace camdyn {
namespace {

using test::build;
using test::dwell;
using test::segment;
using test::segments;

// Crossings are bisected on the law to adjacent doubles; the law's own
// rounding (|s| ≈ 1e-2 m, slope ≥ 1e-5 m/rad near the crossings tested) moves them by < 1e-12 rad.
constexpr double kCrossing = 1e-10;  // [rad]
constexpr double kLift = 1e-15;      // [m], rounding of s ≈ 1e-2 m
// A peak where ds/dθ vanishes quadratically (a cycloid's end): ds's rounding
// (1e-16 relative) hides its root over δ ≈ β sqrt(1e-16 / 2π²) ≈ 5e-9 rad.
constexpr double kPeak = 1e-7;  // [rad]

/// The distance between two cam angles on the circle [rad].
double circular_distance(double a, double b) {
  const double d = std::remainder(a - b, 2.0 * std::numbers::pi);
  return std::abs(d);
}

/// The closed-form cycloidal rise of `lift` over [start, start + beta] [m].
double cycloid(double theta, double start, double beta, double lift) {
  const double x = (theta - start) / beta;
  return lift * (x - std::sin(2.0 * kPi * x) / (2.0 * kPi));
}

/// Where the closed-form rise reaches `height`, by the test's own bisection (the cycloid is monotonic) [rad].
double cycloid_crossing(double start, double beta, double lift, double height) {
  double lo = start, hi = start + beta;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (cycloid(mid, start, beta, lift) < height ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Rise 30–130° and return 130–250° (cycloidal, 10 mm), base circle elsewhere:
// the opening at h is where the rise reaches h, the closing where the return
// (the mirrored rise) comes down to it.
TEST(ValveTiming, DurationAtCheckingHeightsMatchesTheClosedFormCycloid) {
  constexpr double lift = 0.01;
  const MotionLaw law = build(segments(
      {dwell(30), segment("rise", "cycloidal", 130, lift), segment("return", "cycloidal", 250, lift), dwell(360)}));
  const std::vector<double> heights = {0.0002, 0.001, 0.005, 0.0099};
  const ValveTiming timing = valve_timing(law, heights);
  ASSERT_EQ(timing.heights.size(), heights.size());
  const double rise_start = 30 * kDegToRad, rise = 100 * kDegToRad, ret_end = 250 * kDegToRad, ret = 120 * kDegToRad;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    const double h = heights[i];
    const double opening = cycloid_crossing(rise_start, rise, lift, h);
    // On the return s(θ) = L − cycloid(θ − 130°): s = h where the mirrored rise reaches L − h.
    const double closing = ret_end - cycloid_crossing(0.0, ret, lift, h);
    const CheckingHeightTiming& t = timing.heights[i];
    EXPECT_EQ(t.height, h);
    ASSERT_EQ(t.intervals.size(), 1u) << h;
    ASSERT_TRUE(t.event.has_value());
    EXPECT_NEAR(t.event->opening, opening, kCrossing) << h;
    EXPECT_NEAR(t.event->closing, closing, kCrossing) << h;
    EXPECT_NEAR(t.duration, closing - opening, 2 * kCrossing) << h;
    EXPECT_NEAR(t.midpoint, 0.5 * (opening + closing), kCrossing) << h;
  }
  EXPECT_NEAR(timing.max_lift, lift, kLift);
  EXPECT_NEAR(timing.lobe_centre, 130 * kDegToRad, kPeak);
  EXPECT_FALSE(timing.opening_ramp.has_value());  // one rise piece: no ramp
  EXPECT_FALSE(timing.closing_ramp.has_value());
}

// An event across cam angle 0 (rise 300–360°, return 0–60°): one interval that wraps past 2π.
TEST(ValveTiming, EventAcrossCamAngleZeroIsOneIntervalPastTwoPi) {
  constexpr double lift = 0.008, h = 0.001;
  const MotionLaw law =
      build(segments({segment("return", "cycloidal", 60, lift), dwell(300), segment("rise", "cycloidal", 360, lift)}));
  const ValveTiming timing = valve_timing(law, std::vector<double>{h});
  const CheckingHeightTiming& t = timing.heights.front();
  ASSERT_EQ(t.intervals.size(), 1u);
  const double opening = cycloid_crossing(300 * kDegToRad, 60 * kDegToRad, lift, h);
  const double closing = 2 * kPi + 60 * kDegToRad - cycloid_crossing(0.0, 60 * kDegToRad, lift, h);
  EXPECT_NEAR(t.event->opening, opening, kCrossing);
  EXPECT_NEAR(t.event->closing, closing, kCrossing);
  EXPECT_GT(t.event->closing, 2 * kPi);
  EXPECT_NEAR(t.duration, closing - opening, 2 * kCrossing);
  EXPECT_LT(circular_distance(timing.lobe_centre, 0.0), kPeak);  // the peak at 360° = 0°
}

TEST(ValveTiming, HeightAboveTheLiftIsNeverReached) {
  const MotionLaw law = build(segments(
      {segment("rise", "cycloidal", 90, 0.005), dwell(180), segment("return", "cycloidal", 270, 0.005), dwell(360)}));
  const ValveTiming timing = valve_timing(law, std::vector<double>{0.006});
  EXPECT_TRUE(timing.heights.front().intervals.empty());
  EXPECT_EQ(timing.heights.front().duration, 0.0);
  EXPECT_FALSE(timing.heights.front().event.has_value());
}

// A dwell at full lift (90–180°): the lobe centre is its middle.
TEST(ValveTiming, LobeCentreOfADwellAtFullLiftIsItsMiddle) {
  const MotionLaw law = build(segments(
      {segment("rise", "cycloidal", 90, 0.005), dwell(180), segment("return", "cycloidal", 270, 0.005), dwell(360)}));
  const ValveTiming timing = valve_timing(law, std::vector<double>{0.001});
  EXPECT_NEAR(timing.lobe_centre, 135 * kDegToRad, kPeak);
  EXPECT_NEAR(timing.max_lift, 0.005, kLift);
}

// Ramps as pieces: a small rise before the main rise and a small return after
// the main return. The opening ramp ends at 20° with its lift, the closing
// ramp starts at 200° with its lift; a cycloid ends with zero velocity.
TEST(ValveTiming, RampsMarkedAsPiecesGiveTheirEndsHeightAndVelocity) {
  constexpr double ramp = 0.0003, main = 0.0087;
  const MotionLaw law = build(
      segments({segment("rise", "cycloidal", 20, ramp), segment("rise", "cycloidal", 100, main),
                segment("return", "cycloidal", 180, main), segment("return", "cycloidal", 200, ramp), dwell(360)}));
  const ValveTiming timing = valve_timing(law, std::vector<double>{0.001});
  ASSERT_TRUE(timing.opening_ramp.has_value());
  ASSERT_TRUE(timing.closing_ramp.has_value());
  EXPECT_NEAR(timing.opening_ramp->angle, 20 * kDegToRad, kCrossing);
  EXPECT_NEAR(timing.opening_ramp->height, ramp, kLift);
  EXPECT_NEAR(timing.opening_ramp->velocity, 0.0, kLift);
  EXPECT_NEAR(timing.closing_ramp->angle, 180 * kDegToRad, kCrossing);
  EXPECT_NEAR(timing.closing_ramp->height, ramp, kLift);
  EXPECT_NEAR(timing.closing_ramp->velocity, 0.0, kLift);
  // Half the ramp height is reached on the ramps.
  const ValveTiming half = valve_timing(law, std::vector<double>{0.5 * ramp});
  EXPECT_NEAR(half.heights.front().event->opening, 10 * kDegToRad, kCrossing);
  EXPECT_NEAR(half.heights.front().event->closing, 190 * kDegToRad, kCrossing);
}

// Ramp ends named by angle: the lift and ds/dθ of the closed-form cycloid there.
TEST(ValveTiming, RampEndsGivenByAngleReadTheLawThere) {
  constexpr double lift = 0.01;
  const MotionLaw law = build(segments(
      {dwell(30), segment("rise", "cycloidal", 130, lift), segment("return", "cycloidal", 250, lift), dwell(360)}));
  const ValveTiming timing = valve_timing(law, std::vector<double>{0.001}, std::pair(40 * kDegToRad, 240 * kDegToRad));
  const double beta = 100 * kDegToRad, x = 0.1;
  ASSERT_TRUE(timing.opening_ramp.has_value());
  EXPECT_NEAR(timing.opening_ramp->height, cycloid(40 * kDegToRad, 30 * kDegToRad, beta, lift), kLift);
  EXPECT_NEAR(timing.opening_ramp->velocity, lift / beta * (1.0 - std::cos(2.0 * kPi * x)), 1e-12);
  ASSERT_TRUE(timing.closing_ramp.has_value());
  EXPECT_LT(timing.closing_ramp->velocity, 0.0);
  EXPECT_NEAR(timing.closing_ramp->height, cycloid(10 * kDegToRad, 0.0, 120 * kDegToRad, lift), kLift);
}

}  // namespace
}  // namespace camdyn
