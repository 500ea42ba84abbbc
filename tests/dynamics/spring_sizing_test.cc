// Spring sizing on the rigid model against closed forms (docs/model.md §11):
// the required preload of an undamped rest-to-rest law is
// max over θ of (−M ω² s'' − k s) + P_min; a harmonic law's is
// P_min + max(0, h (M ω² π² / (2 β²) − k)) with β its shortest segment.
#include "dynamics/spring_sizing.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

constexpr double kSizingLift = 0.02;  // h [m]
constexpr double kMass = 0.3;         // M [kg]
constexpr double kRate = 5000;        // k [N/m]
constexpr double kPmin = 50.0;        // P_min [N]
constexpr double kOmega = 150;        // ω [rad/s] (1432 rpm)

MotionLaw law_of(SegmentLaw law, double rise_end_deg, double return_start_deg, double return_end_deg) {
  MotionLawConfig c;
  c.segments = {{SegmentType::rise, law, rise_end_deg, kSizingLift, std::nullopt, 5, {}},
                {SegmentType::dwell, SegmentLaw::none, return_start_deg, std::nullopt, std::nullopt, 5, {}},
                {SegmentType::return_, law, return_end_deg, kSizingLift, std::nullopt, 5, {}},
                {SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}}};
  return build_motion_law(c, "test.json");
}

RigidSpringLoad undamped_load(double stiffness, double preload = 0.0) {
  RigidSpringLoad l;
  l.mass = kMass;
  l.stiffness = stiffness;
  l.preload = preload;
  l.min_force = kPmin;
  return l;
}

// An undamped cycloidal rise over β: the closed-form s and s'' on a grid of
// 10⁶ intervals, independent of the motion-law code. The grid misses a smooth
// maximum by ≈ f'' Δx² / 8 ≈ 1e-11 of the force scale.
double cycloidal_preload_reference(double beta, double omega) {
  constexpr int kGrid = 1000000;
  double best = 0.0;  // the dwells: s = 0, s'' = 0 (and −k h on the top dwell)
  for (int i = 0; i <= kGrid; ++i) {
    const double x = static_cast<double>(i) / kGrid;
    for (const double sign : {1.0, -1.0}) {  // rise, and the return as its mirror
      const double s = sign > 0 ? kSizingLift * (x - std::sin(2 * kPi * x) / (2 * kPi))
                                : kSizingLift * (1 - x + std::sin(2 * kPi * x) / (2 * kPi));
      const double d2s = sign * kSizingLift * 2 * kPi / (beta * beta) * std::sin(2 * kPi * x);
      best = std::max(best, -kMass * omega * omega * d2s - kRate * s);
    }
  }
  return best + kPmin;
}

TEST(SpringSizing, UndampedCycloidalPreloadIsTheMaximumOfTheInertiaLessTheSpring) {
  const MotionLaw law = law_of(SegmentLaw::cycloidal, 120.0, 180.0, 300.0);
  const SpringSizing s = size_spring(law, undamped_load(kRate), kOmega);
  const double expected = cycloidal_preload_reference(120.0 * kPi / 180.0, kOmega);
  EXPECT_NEAR(s.required_preload, expected, test::kConverged * expected);
  // On the decelerating half of the rise (or its mirror on the return).
  EXPECT_TRUE((s.preload_at_deg > 60.0 && s.preload_at_deg < 120.0) ||
              (s.preload_at_deg > 180.0 && s.preload_at_deg < 240.0))
      << s.preload_at_deg;
}

TEST(SpringSizing, HarmonicPreloadAndRateMatchTheirClosedForms) {
  // Harmonic rise over 120°, return over 150°: the shorter one decelerates
  // hardest, −h π²/(2 β²) at its top.
  const MotionLaw law = law_of(SegmentLaw::harmonic, 120.0, 180.0, 330.0);
  const double beta = 120.0 * kPi / 180.0;
  const double inertia = kMass * kOmega * kOmega * kPi * kPi / (2 * beta * beta);  // [N/m]
  ASSERT_GT(inertia, kRate);  // the spring alone does not hold the follower
  const SpringSizing s = size_spring(law, undamped_load(kRate), kOmega);
  const double expected = kPmin + kSizingLift * (inertia - kRate);
  EXPECT_NEAR(s.required_preload, expected, test::kConverged * expected);
  EXPECT_NEAR(s.preload_at_deg, 120.0, 1e-6);
  // With F₀ ≥ P_min the rate is set at the top: k h + F₀ = P_min + inertia h.
  const double preload = 80.0;
  const SpringSizing r = size_spring(law, undamped_load(kRate, preload), kOmega);
  const double rate = inertia + (kPmin - preload) / kSizingLift;
  EXPECT_NEAR(r.required_stiffness, rate, test::kConverged * rate);
  // Below the speed where the spring holds it, P_min alone is needed (the dwells).
  const SpringSizing slow = size_spring(law, undamped_load(kRate), 0.5 * kOmega * std::sqrt(kRate / inertia));
  EXPECT_NEAR(slow.required_preload, kPmin, test::kConverged * kPmin);
}

TEST(SpringSizing, NoRateHoldsWhenThePreloadIsBelowTheForceToKeep) {
  const MotionLaw law = law_of(SegmentLaw::harmonic, 120.0, 180.0, 330.0);
  EXPECT_TRUE(std::isinf(size_spring(law, undamped_load(kRate, 0.5 * kPmin), kOmega).required_stiffness));
}

// With P_min = 0 the sized preload puts the rigid-model jump speed of the
// model (dynamics/rigid_jump_speed.h, an independent search over θ at the
// root in ω) at the speed it was sized for.
TEST(SpringSizing, SizedPreloadPutsTheJumpSpeedAtTheSizingSpeed) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0);
  const Model model0 = build_model(scene, "test.json");
  const SpringSizing s = size_spring(*model0.law, *rigid_spring_load(model0, 0.0), kOmega);
  scene.mechanism.follower.spring.preload = s.required_preload;
  const Model model = build_model(scene, "test.json");
  EXPECT_NEAR(jump_speed_rpm(model), kOmega * 30.0 / kPi, test::kRigidJumpGrid * kOmega * 30.0 / kPi);
}

// With a damper the demand is the worst over every speed up to ω_max (c ω s'
// is not monotone in ω): a brute-force maximum over a grid of speeds.
TEST(SpringSizing, DampedDemandIsTheWorstOverEverySpeedUpToTheTop) {
  const MotionLaw law = law_of(SegmentLaw::cycloidal, 120.0, 180.0, 300.0);
  RigidSpringLoad load = undamped_load(kRate);
  load.damping = 40.0;  // [N s/m]: c ω s' ≈ 90 N on the return at ω
  const SpringSizing s = size_spring(law, load, kOmega);
  double brute = 0.0;
  for (int j = 0; j <= 400; ++j) {
    const double w = kOmega * j / 400.0;
    for (int i = 0; i <= 3600; ++i) {
      const LawSample x = law.eval(2 * kPi * i / 3600.0);
      brute = std::max(brute, kPmin - (kMass * w * w * x.d2s + load.damping * w * x.ds) - kRate * x.s);
    }
  }
  EXPECT_GE(s.required_preload, brute - test::kConverged * brute);
  // The grid of speeds and angles misses the maximum by ≲ 1e-3 of it.
  EXPECT_LE(s.required_preload, brute * (1 + 1e-3));
}

}  // namespace
}  // namespace camdyn
