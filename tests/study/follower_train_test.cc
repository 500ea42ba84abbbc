// The follower train of docs/model.md §12 against closed forms written
// independently of the library: on an exactly harmonic lift with Kelvin–Voigt
// contacts and every one-sided force held, the train is linear and its
// periodic steady state is its mean plus one harmonic
// (tests/dynamics/linear_train_reference.h, each coordinate's equation written
// as its own row); the surge mode of a spring with mass; a follower seated
// above its base circle by a cycloidal ramp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "../dynamics/linear_train_reference.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "study/steady_state.h"

namespace camdyn {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kLift = 0.008;  // [m]

/// A flat translating follower on a harmonic rise and return (s = h/2 (1 − cos θ)),
/// Kelvin–Voigt cam contact of exponent 1, and `bodies` train bodies.
struct LinearTrainCase {
  SceneConfig scene;
  test::ReferenceTrain reference;
};

SpringConfig spring(double k, double preload, double mass = 0.0, int coils = 0, double zeta = 0.0) {
  SpringConfig s;
  s.stiffness = k;
  s.preload = preload;
  if (mass > 0.0) {
    s.mass = mass;
    s.coils = coils;
    s.damping_ratio = zeta;
  }
  return s;
}

test::ReferenceSpring reference_spring(const SpringConfig& s) {
  return {s.stiffness, s.preload, s.mass.value_or(0.0), s.coils.value_or(0), s.damping_ratio.value_or(0.0)};
}

LinearTrainCase linear_train_case(int bodies, bool follower_spring_mass = false) {
  LinearTrainCase c;
  SceneConfig& s = c.scene;
  s.name = "linear-train";
  s.mechanism.cam.base_radius = 0.02;
  s.mechanism.cam.motion_law.segments = {
      {SegmentType::rise, SegmentLaw::harmonic, 180.0, kLift, std::nullopt, 5, {}},
      {SegmentType::return_, SegmentLaw::harmonic, 360.0, kLift, std::nullopt, 5, {}}};
  FollowerConfig& f = s.mechanism.follower;
  f.shape.type = FollowerShape::flat;
  f.shape.face_width = 0.06;
  f.mass = 0.05;
  f.damping = 1.0;
  f.spring = follower_spring_mass ? spring(5000.0, 50.0, 0.02, 5, 0.05) : spring(5000.0, 50.0);
  ContactConfig& contact = s.mechanism.contact;
  contact.model = ContactModel::kelvin_voigt;
  contact.stiffness = 1e8;
  contact.exponent = 1.0;
  contact.damping = 300.0;
  const std::vector<TrainBodyConfig> chain = {
      {"valve", 0.08, 2.0, {1.5, 2e7, 100.0, 0.0, true}, spring(30000.0, 300.0, 0.04, 6, 0.03), {}, {}},
      {"tip", 0.03, 0.0, {1.0, 5e7, 50.0, 0.0, true}, spring(8000.0, 80.0), {}, {}},
      {"end", 0.02, 0.5, {0.8, 3e7, 60.0, 0.0, true}, spring(4000.0, 40.0), {}, {}}};
  s.mechanism.train.assign(chain.begin(), chain.begin() + bodies);
  s.simulation.cycles = 5;
  s.simulation.discard_cycles = 2;
  s.simulation.output_step_deg = 1.0;
  s.simulation.steady_state = true;
  s.integrator.rtol = 1e-9;
  s.integrator.atol = 1e-13;

  test::ReferenceTrain& r = c.reference;
  r.mass = f.mass;
  r.damper = f.damping;
  r.spring = reference_spring(f.spring);
  r.contact_stiffness = *contact.stiffness;
  r.contact_damping = *contact.damping;
  for (const TrainBodyConfig& b : s.mechanism.train) {
    test::ReferenceBody rb;
    rb.ratio = b.link.ratio;
    rb.link_stiffness = b.link.stiffness;
    rb.link_damping = b.link.damping;
    rb.mass = b.mass;
    rb.damper = b.damping;
    rb.spring = reference_spring(b.spring);
    r.bodies.push_back(rb);
  }
  return c;
}

/// The steady state's metrics at `rpm`.
SimulationResult steady_run(SceneConfig scene, double rpm) {
  scene.mechanism.cam.rpm = rpm;
  const Model model = build_model(scene, "test");
  SimulationResult r = simulate_scene(scene, "test");
  EXPECT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
  const SteadyStateOutcome o = apply_steady_state(scene, model, r);
  EXPECT_EQ(r.metrics_over, "periodic_orbit") << r.metrics_note;
  return r;
}

class LinearTrainSteadyState : public ::testing::TestWithParam<int> {};

TEST_P(LinearTrainSteadyState, ForcesAndJumpSpeedMatchTheClosedForm) {
  const int bodies = GetParam();
  const LinearTrainCase c = linear_train_case(bodies, bodies <= 1);
  const Model model = build_model(c.scene, "test");
  const double jump = test::reference_jump_speed(c.reference, kLift, 1e4) * 60.0 / kTwoPi;  // [rpm]
  ASSERT_TRUE(std::isfinite(jump));
  EXPECT_NEAR(model.train_jump_speed_rpm, jump, 2e-3 * jump);
  for (double fraction : {0.3, 0.6, 0.9}) {
    const double rpm = fraction * jump;
    const SimulationResult r = steady_run(c.scene, rpm);
    const test::ReferenceResponse ref = test::reference_response(c.reference, kLift, rpm * kTwoPi / 60.0);
    SCOPED_TRACE(testing::Message() << bodies << " bodies at " << rpm << " rpm");
    EXPECT_NEAR(r.metrics.min_contact_force, ref.min_contact, 5e-3 * std::abs(ref.min_contact));
    ASSERT_TRUE(r.metrics.train);
    const TrainMetrics& t = *r.metrics.train;
    if (bodies > 0) {
      const double min_link = *std::min_element(ref.min_link.begin(), ref.min_link.end());
      EXPECT_NEAR(t.min_link_force, min_link, 5e-3 * std::abs(min_link));
    }
    const double peak = *std::max_element(ref.peak_spring.begin(), ref.peak_spring.end());
    EXPECT_NEAR(t.peak_spring_force, peak, 5e-3 * peak);
    EXPECT_EQ(r.metrics.separation_fraction, 0.0);
  }
  // Just above the jump speed the train lets go somewhere.
  const SimulationResult above = steady_run(c.scene, 1.02 * jump);
  const TrainMetrics& t = *above.metrics.train;
  EXPECT_GT(above.metrics.separation_fraction + t.link_separation_fraction, 0.0);
}

INSTANTIATE_TEST_SUITE_P(Bodies, LinearTrainSteadyState, ::testing::Values(0, 1, 2, 3));

}  // namespace
}  // namespace camdyn
