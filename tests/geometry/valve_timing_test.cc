// Valvetrain conventions (geometry/valve_timing.h) against laws whose
// checking-height crossings, peak and ramp ends are known in closed form, at
// the cam and at a body the law is carried to (geometry/lift_chain.h).
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

// The carry itself (geometry/lift_chain.h): each step is max(r s − λ, p), the
// chain their composition, its slope the product of the ratios off the
// seats, its datum the last seat or the base circle carried.
TEST(LiftChain, EachStepIsTheRatioTimesTheLiftLessTheLashHeldAtTheSeat) {
  const LiftStep step{1.5, 0.0002, 0.0};
  EXPECT_EQ(step.carry(0.01), 1.5 * 0.01 - 0.0002);
  EXPECT_EQ(step.carry(0.0001), 0.0);  // 1.5 × 0.1 mm is within the lash: on the seat
  EXPECT_TRUE(step.lifted(0.01));
  EXPECT_FALSE(step.lifted(0.0001));
  const LiftStep free{2.0, 0.001, std::nullopt};
  EXPECT_EQ(free.carry(0.0), -0.001);  // no seat: it follows the link down
  EXPECT_TRUE(free.lifted(0.0));
}

TEST(LiftChain, TheChainComposesItsStepsAndTheSlopeIsTheRatiosOffTheSeats) {
  // A follower seated 0.2 mm above the base circle, a 1:1 pushrod with 0.3 mm lash, a 1.5 rocker to a valve
  // seated at 0: on the base circle the pushrod hangs 0.1 mm below its rocker, the valve sits on its seat.
  const LiftChain chain{{LiftStep{1.0, 0.0, 0.0002}, LiftStep{1.0, 0.0003, std::nullopt}, LiftStep{1.5, 0.0, 0.0}}};
  const double s = 0.009;
  EXPECT_EQ(chain.at(s), 1.5 * (s - 0.0003));
  EXPECT_EQ(chain.slope(s), 1.5);
  EXPECT_EQ(chain.at(0.0), 0.0);
  EXPECT_EQ(chain.slope(0.0), 0.0);      // held on the follower's seat
  EXPECT_EQ(chain.slope(0.00025), 0.0);  // off the follower's seat, the lash not yet taken up
  EXPECT_EQ(chain.datum(0.0), 0.0);      // the valve's seat
  const LiftChain unseated{{LiftStep{}, LiftStep{2.0, 0.001, std::nullopt}}};
  EXPECT_EQ(unseated.datum(0.0), -0.001);  // its position on the base circle
  EXPECT_EQ(LiftChain{}.at(0.004), 0.004);
  EXPECT_EQ(LiftChain{}.slope(0.004), 1.0);
  EXPECT_EQ(LiftChain{}.datum(0.001), 0.001);
}

// At a body behind links (geometry/lift_chain.h): a 1:1 pushrod with lash
// λ₁ and a 1.5 rocker with lash λ₂ to a valve seated at 0. The valve lifts
// 1.5 (s − λ₁) − λ₂ from its seat, so it reaches h where the cam reaches
// (h + λ₂) / 1.5 + λ₁; the ramps' velocities are the law's times 1.5 once
// off the seat, 0 on it.
TEST(ValveTiming, AtABodyTheLawIsCarriedThroughRatioAndLash) {
  constexpr double lift = 0.01, lash1 = 0.0002, lash2 = 0.0001, ratio = 1.5;
  const MotionLaw law = build(segments(
      {dwell(30), segment("rise", "cycloidal", 130, lift), segment("return", "cycloidal", 250, lift), dwell(360)}));
  const LiftChain chain{{LiftStep{}, LiftStep{1.0, lash1, std::nullopt}, LiftStep{ratio, lash2, 0.0}}};
  const std::vector<double> heights = {0.001, 0.01};
  const ValveTiming timing =
      valve_timing(law, heights, std::pair(40 * kDegToRad, 100 * kDegToRad), chain);  // 40°: on the seat
  EXPECT_EQ(timing.datum, 0.0);
  EXPECT_NEAR(timing.max_lift, ratio * (lift - lash1) - lash2, kLift);
  EXPECT_NEAR(timing.lobe_centre, 130 * kDegToRad, kPeak);
  const double rise_start = 30 * kDegToRad, rise = 100 * kDegToRad, ret_end = 250 * kDegToRad, ret = 120 * kDegToRad;
  for (std::size_t i = 0; i < heights.size(); ++i) {
    const double at_cam = (heights[i] + lash2) / ratio + lash1;
    const double opening = cycloid_crossing(rise_start, rise, lift, at_cam);
    const double closing = ret_end - cycloid_crossing(0.0, ret, lift, at_cam);
    ASSERT_TRUE(timing.heights[i].event.has_value()) << heights[i];
    EXPECT_NEAR(timing.heights[i].event->opening, opening, kCrossing) << heights[i];
    EXPECT_NEAR(timing.heights[i].event->closing, closing, kCrossing) << heights[i];
  }
  const double x100 = 0.7;  // where 100° falls in the rise
  ASSERT_LT(cycloid(40 * kDegToRad, rise_start, rise, lift), lash1 + lash2 / ratio);
  EXPECT_EQ(timing.opening_ramp->height, 0.0);
  EXPECT_EQ(timing.opening_ramp->velocity, 0.0);
  EXPECT_NEAR(timing.closing_ramp->height, ratio * (cycloid(100 * kDegToRad, rise_start, rise, lift) - lash1) - lash2,
              kLift);
  EXPECT_NEAR(timing.closing_ramp->velocity, ratio * lift / rise * (1.0 - std::cos(2.0 * kPi * x100)), 1e-12);
  // An empty chain is the cam: the same figures as without one.
  const ValveTiming cam = valve_timing(law, heights, std::nullopt, LiftChain{});
  const ValveTiming plain = valve_timing(law, heights);
  EXPECT_EQ(cam.max_lift, plain.max_lift);
  EXPECT_EQ(cam.heights[0].event->opening, plain.heights[0].event->opening);
}

// A valve held open: its seat below where the chain puts it on the base circle. Its lift from the seat never
// falls to 0, so every height below that is open all the way round.
TEST(ValveTiming, AValveHeldOffItsSeatIsOpenAllRound) {
  const MotionLaw law = build(segments(
      {dwell(30), segment("rise", "cycloidal", 130, 0.01), segment("return", "cycloidal", 250, 0.01), dwell(360)}));
  const LiftChain chain{{LiftStep{1.0, 0.0, std::nullopt}, LiftStep{1.0, 0.0, -0.0005}}};  // seat 0.5 mm below
  const ValveTiming timing = valve_timing(law, std::vector<double>{0.0004}, std::nullopt, chain);
  EXPECT_NEAR(timing.max_lift, 0.0105, kLift);
  EXPECT_NEAR(timing.heights.front().duration, 2 * kPi, kCrossing);
}

}  // namespace
}  // namespace camdyn
