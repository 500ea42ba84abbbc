// The follower train's plausibility warnings (dynamics/plausibility.h,
// docs/warnings.md "Follower trains"): a seat softer than the spring it holds,
// a link far softer than the cam contact, a spring with mass in too few coils.
// Each fires on a bad scene, names the dotted field, and stays silent on the
// good one; the thresholds are checked from their closed forms on either side.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dynamics/plausibility.h"
#include "scenes.h"

namespace camdyn {
namespace {

/// Either side of a threshold: 1 % below fires, 1 % above does not.
constexpr double kBelow = 0.99, kAbove = 1.01;

/// The cycloidal test cam's flat follower (20 mm lift; 5 kN/m spring,
/// 40 N preload; Hertz-type K = 1e10 N/m^1.5) held still, with a seat 0.2 mm
/// above the base circle, a 16 kN/m spring with mass in 8 coils on the follower
/// and a valve behind a 1.5:1 link: a plausible bucket tappet with a lever.
SceneConfig good_train_scene() {
  SceneConfig s = test::follower_scene("translating_flat", 0.0);
  FollowerConfig& f = s.mechanism.follower;
  f.spring.mass = 0.02;
  f.spring.coils = 8;
  f.seat = test::hunt_crossley_seat(2e-4);
  TrainBodyConfig valve;
  valve.name = "valve";
  valve.mass = 0.06;
  valve.link = {1.5, 2e7, 40.0, 0.0, true};
  valve.spring.stiffness = 30000.0;
  valve.spring.preload = 300.0;
  SeatConfig valve_seat;
  valve_seat.model = ContactModel::hunt_crossley;
  valve_seat.stiffness = 1e9;
  valve_seat.exponent = 1.5;
  valve_seat.restitution = 0.3;
  valve.seat = valve_seat;
  s.mechanism.train = {valve};
  return s;
}

std::vector<PlausibilityWarning> warnings_of(const SceneConfig& scene) {
  return input_warnings(scene, build_model(scene, "test"));
}

int count(const std::vector<PlausibilityWarning>& warnings, const std::string& cause, const std::string& field) {
  int n = 0;
  for (const PlausibilityWarning& w : warnings) n += w.cause == cause && w.field == field;
  return n;
}

int count_cause(const std::vector<PlausibilityWarning>& warnings, const std::string& cause) {
  int n = 0;
  for (const PlausibilityWarning& w : warnings) n += w.cause == cause;
  return n;
}

TEST(TrainPlausibility, GoodTrainHasNoTrainWarnings) {
  const std::vector<PlausibilityWarning> w = warnings_of(good_train_scene());
  EXPECT_EQ(count_cause(w, "seat_stiffness"), 0);
  EXPECT_EQ(count_cause(w, "link_stiffness"), 0);
  EXPECT_EQ(count_cause(w, "spring_coils"), 0);
}

// Exponent 1: the seat's stiffness is K itself, against 10 × the 5 kN/m spring.
TEST(TrainPlausibility, LinearSeatBelowTenTimesItsSpringRateIsWarnedNamingTheSeat) {
  SceneConfig s = good_train_scene();
  const double threshold = 10.0 * s.mechanism.follower.spring.stiffness;  // [N/m]
  s.mechanism.follower.seat->stiffness = kAbove * threshold;
  EXPECT_EQ(count(warnings_of(s), "seat_stiffness", "mechanism.follower.seat.stiffness"), 0);
  s.mechanism.follower.seat->stiffness = kBelow * threshold;
  EXPECT_EQ(count(warnings_of(s), "seat_stiffness", "mechanism.follower.seat.stiffness"), 1);
}

// Exponent 1.5: linearised under the spring's load at the seat, F = F₀ (the
// valve's seat at x = 0): k_seat = n K^(1/n) F^((n−1)/n) = 10 k gives
// K = (10 k / (n F^((n−1)/n)))^n.
TEST(TrainPlausibility, HertzSeatIsLinearisedUnderItsSpringsLoad) {
  SceneConfig s = good_train_scene();
  TrainBodyConfig& valve = s.mechanism.train[0];
  const double n = valve.seat->exponent, F = valve.spring.preload, k = valve.spring.stiffness;
  const double threshold = std::pow(10.0 * k / (n * std::pow(F, (n - 1.0) / n)), n);  // [N/m^1.5]
  valve.seat->stiffness = kAbove * threshold;
  EXPECT_EQ(count(warnings_of(s), "seat_stiffness", "mechanism.train[0].seat.stiffness"), 0);
  valve.seat->stiffness = kBelow * threshold;
  const std::vector<PlausibilityWarning> w = warnings_of(s);
  EXPECT_EQ(count(w, "seat_stiffness", "mechanism.train[0].seat.stiffness"), 1);
  EXPECT_EQ(count(w, "seat_stiffness", "mechanism.follower.seat.stiffness"), 0);
}

// Cam held still, translating flat face (∂g/∂q = 1): the contact's load is
// the springs' at full lift, F = (F₀ + k h) + r (F₀ᵥ + kᵥ r h), its linearised
// stiffness k_c = n K^(1/n) F^((n−1)/n); the link warns below 1e-3 k_c / r².
TEST(TrainPlausibility, LinkFarSofterThanTheCamContactIsWarnedNamingTheLink) {
  SceneConfig s = good_train_scene();
  const double h = 0.02, r = 1.5, K = 1e10, n = 1.5;
  const TrainBodyConfig& v = s.mechanism.train[0];
  const double F = (40.0 + 5000.0 * h) + r * (v.spring.preload + v.spring.stiffness * r * h);  // [N]
  const double k_c = n * std::pow(K, 1.0 / n) * std::pow(F, (n - 1.0) / n);                    // [N/m]
  const double threshold = 1e-3 * k_c / (r * r);                                               // [N/m]
  s.mechanism.train[0].link.stiffness = kAbove * threshold;
  EXPECT_EQ(count(warnings_of(s), "link_stiffness", "mechanism.train[0].link.stiffness"), 0);
  s.mechanism.train[0].link.stiffness = kBelow * threshold;
  EXPECT_EQ(count(warnings_of(s), "link_stiffness", "mechanism.train[0].link.stiffness"), 1);
}

TEST(TrainPlausibility, SpringWithMassInFewerThanFourCoilsIsWarnedNamingTheCoils) {
  SceneConfig s = good_train_scene();
  s.mechanism.follower.spring.coils = 4;
  EXPECT_EQ(count(warnings_of(s), "spring_coils", "mechanism.follower.spring.coils"), 0);
  s.mechanism.follower.spring.coils = 3;
  EXPECT_EQ(count(warnings_of(s), "spring_coils", "mechanism.follower.spring.coils"), 1);
  s.mechanism.train[0].spring.mass = 0.04;
  s.mechanism.train[0].spring.coils = 1;
  const std::vector<PlausibilityWarning> w = warnings_of(s);
  EXPECT_EQ(count(w, "spring_coils", "mechanism.train[0].spring.coils"), 1);
  EXPECT_EQ(count_cause(w, "spring_coils"), 2);
}

// A massless spring has no coils to resolve: no warning whatever `coils` says.
TEST(TrainPlausibility, MasslessSpringIsNotWarnedForItsCoils) {
  SceneConfig s = good_train_scene();
  s.mechanism.follower.spring.mass.reset();
  s.mechanism.follower.spring.coils = 1;
  EXPECT_EQ(count_cause(warnings_of(s), "spring_coils"), 0);
}

// The cam picks a follower up off its lash seat with an impact every
// revolution, far below the rigid-model jump speed (≈ 8900 rpm here): the
// onset is physics, not the numerical separation the jump-speed check is for.
TEST(TrainPlausibility, PickupOffALashSeatIsNotChatter) {
  SceneConfig s = test::follower_scene("translating_flat", 3000.0);
  s.mechanism.cam.base_radius = 0.018;
  s.mechanism.cam.motion_law.segments = {
      {SegmentType::rise, SegmentLaw::cycloidal, 120.0, 0.008, std::nullopt, 5, {}},
      {SegmentType::return_, SegmentLaw::cycloidal, 240.0, 0.008, std::nullopt, 5, {}},
      {SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}}};
  s.mechanism.follower.shape.face_width = 0.03;
  s.mechanism.follower.mass = 0.05;
  s.mechanism.follower.spring.stiffness = 35000.0;
  s.mechanism.follower.spring.preload = 250.0;
  s.mechanism.follower.seat = good_train_scene().mechanism.follower.seat;
  s.mechanism.contact.model = ContactModel::hunt_crossley;
  s.simulation.cycles = 2;
  s.integrator.rtol = 1e-8;
  s.integrator.atol = 1e-12;
  const Model model = build_model(s, "test");
  const SimulationResult r = simulate_scene(s, "test");
  ASSERT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
  ASSERT_GE(r.metrics.impact_count, 1);
  EXPECT_EQ(count_cause(result_warnings(s, model, r), "chatter"), 0);
  // Without the seat the follower stays on the cam: no onsets, no warning either.
  s.mechanism.follower.seat.reset();
  const SimulationResult on_law = simulate_scene(s, "test");
  EXPECT_EQ(on_law.metrics.impact_count, 0);
}

}  // namespace
}  // namespace camdyn
