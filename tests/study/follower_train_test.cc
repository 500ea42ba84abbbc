// The follower train of docs/model.md §12 against closed forms written
// independently of the library: on an exactly harmonic lift with Kelvin–Voigt
// contacts and every one-sided force held, the train is linear and its
// periodic steady state is its mean plus one harmonic
// (tests/dynamics/linear_train_reference.h, each coordinate's equation written
// as its own row); the surge mode of a spring with mass; a follower seated
// above its base circle by a cycloidal ramp.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "study/steady_state.h"
#include "tests/dynamics/linear_train_case.h"

namespace camdyn {
namespace {

using test::kLift;
using test::linear_train_case;
using test::LinearTrainCase;
using test::spring;

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
  // The sanitised build (20x slower on these long steady runs) checks the
  // speed nearest the jump speed only; the optimised build checks all three.
  const std::vector<double> fractions =
      CAMDYN_SANITIZED ? std::vector<double>{0.9} : std::vector<double>{0.3, 0.6, 0.9};
  for (double fraction : fractions) {
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

// The spring with mass alone, its body held: the lump block of the model's
// own Jacobian has the chain's fixed-fixed modes, the lowest at
// ω₁ = 2 √(k_s N / m_s) sin(π / (2 (N + 1))). This lumping approaches the
// continuous spring's π √(k / m_s) from below with relative error 1/(2N) to
// first order (π √(N / (N + 1))): docs/model.md §12.
TEST(SpringWithMass, LumpedSurgeModeIsTheChainsClosedForm) {
  const double k = 40000.0, m_s = 0.05;                             // [N/m], [kg]
  const double continuous = std::numbers::pi * std::sqrt(k / m_s);  // [rad/s]
  double previous_error = 1.0;
  for (int coils : {1, 2, 4, 8, 16, 32}) {
    LinearTrainCase c = linear_train_case(0, false);
    c.scene.mechanism.follower.spring = spring(k, 300.0, m_s, coils, 0.0);
    c.scene.mechanism.cam.rpm = 1000.0;
    const Model model = build_model(c.scene, "test");
    Workspace ws = make_workspace(model);
    std::vector<double> x(static_cast<std::size_t>(model.layout.size), 0.0);
    const int n = model.layout.size;
    std::vector<double> jacobian(static_cast<std::size_t>(n * n));
    state_jacobian(model, ws, 0.0, x.data(), jacobian.data());
    // The lumps' states, the follower (the body) held.
    const int first = model.layout.core_size, lumps = n - first;
    ASSERT_EQ(lumps, 2 * coils);
    Eigen::MatrixXd block(lumps, lumps);
    for (int j = 0; j < lumps; ++j)
      for (int i = 0; i < lumps; ++i) block(i, j) = jacobian[static_cast<std::size_t>(first + i + n * (first + j))];
    const Eigen::VectorXcd eigenvalues = block.eigenvalues();
    double lowest = INFINITY;
    for (const std::complex<double>& l : eigenvalues) {
      EXPECT_NEAR(l.real(), 0.0, 1e-9 * std::abs(l));  // undamped (damping_ratio 0)
      if (l.imag() > 0.0) lowest = std::min(lowest, l.imag());
    }
    const double omega1 = test::surge_omega1(k, m_s, coils);
    EXPECT_NEAR(lowest, omega1, 1e-9 * omega1) << coils << " coils";
    const double error = (continuous - lowest) / continuous;
    EXPECT_GT(error, 0.0);
    EXPECT_NEAR(error * 2.0 * coils, 1.0, 0.8 / coils) << coils << " coils";  // 1/(2N) to first order
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
}

/// A flat follower with a cycloidal opening ramp (0.3 mm over 20°), an 8 mm
/// cycloidal rise and return, a cycloidal closing ramp, and a seat at the
/// ramps' mid height: the valve lash (docs/model.md §12).
SceneConfig seated_follower_scene(double rpm, const SeatConfig& seat) {
  LinearTrainCase c = linear_train_case(0, false);
  SceneConfig s = c.scene;
  s.mechanism.cam.rpm = rpm;
  s.mechanism.cam.base_radius = 0.03;
  s.mechanism.cam.motion_law.segments = {
      {SegmentType::rise, SegmentLaw::cycloidal, 20.0, 3e-4, std::nullopt, 5, {}},
      {SegmentType::rise, SegmentLaw::cycloidal, 110.0, 0.008, std::nullopt, 5, {}},
      {SegmentType::return_, SegmentLaw::cycloidal, 200.0, 0.008, std::nullopt, 5, {}},
      {SegmentType::return_, SegmentLaw::cycloidal, 220.0, 3e-4, std::nullopt, 5, {}},
      {SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}}};
  FollowerConfig& f = s.mechanism.follower;
  f.mass = 0.1;
  f.spring = spring(10000.0, 100.0);
  f.seat = seat;
  ContactConfig& contact = s.mechanism.contact;
  contact.model = ContactModel::lankarani_nikravesh;
  contact.stiffness = 1e10;
  contact.exponent = 1.5;
  contact.restitution = 0.3;  // the lash take-up at the opening ramp does not throw the follower off
  contact.damping.reset();
  s.simulation.cycles = 4;
  s.simulation.discard_cycles = 1;
  s.simulation.steady_state = false;
  return s;
}

SeatConfig seat_at(double position, ContactModel model, double stiffness, double exponent) {
  SeatConfig seat;
  seat.position = position;
  seat.model = model;
  seat.stiffness = stiffness;
  seat.exponent = exponent;
  return seat;
}

TEST(Seat, SeatsAtTheRampsKinematicSpeedOncePerRevolutionAndLashIsNotSeparation) {
  const double ramp = 3e-4, beta = 20.0 * std::numbers::pi / 180.0;  // [m], [rad]
  // Overdamped Kelvin–Voigt seat: lands without bounce.
  SeatConfig seat = seat_at(0.5 * ramp, ContactModel::kelvin_voigt, 1e9, 1.0);
  seat.damping = 2.0 * 2.0 * std::sqrt(1e9 * 0.1);  // twice critical [N s/m]
  for (double rpm : {600.0, 1200.0}) {
    SCOPED_TRACE(testing::Message() << rpm << " rpm");
    const SceneConfig scene = seated_follower_scene(rpm, seat);
    const SimulationResult r = simulate_scene(scene, "test");
    ASSERT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
    const double omega = rpm * kTwoPi / 60.0;
    const double kinematic = 2.0 * ramp * omega / beta;  // cycloid's speed at mid-ramp [m/s]
    ASSERT_TRUE(r.metrics.train);
    const TrainMetrics& t = *r.metrics.train;
    EXPECT_NEAR(t.max_seating_velocity, kinematic, 0.02 * kinematic);
    const double revolutions = *scene.simulation.cycles - scene.simulation.discard_cycles;
    EXPECT_EQ(t.seat_impacts, static_cast<long>(revolutions));
    EXPECT_LT(r.metrics.energy_residual, 1e4 * scene.integrator.rtol);
    if (rpm > 1000.0) continue;  // there the lash take-up at 0.22 m/s throws the follower off the cam: a real jump
    // On the base circle the cam's gap is open (lash), but no separation, no impact.
    EXPECT_GT(*std::max_element(r.series.gap.begin(), r.series.gap.end()), 0.9 * 0.5 * ramp);
    EXPECT_EQ(r.metrics.separation_fraction, 0.0);
    EXPECT_EQ(r.metrics.max_separation_gap, 0.0);
    EXPECT_EQ(r.metrics.impact_count, 0);
    EXPECT_GT(r.metrics.min_contact_force, 0.0);
  }
  // An underdamped seat at a fast ramp bounces: more than one onset per revolution.
  SeatConfig bouncy = seat_at(0.5 * ramp, ContactModel::hunt_crossley, 1e10, 1.5);
  bouncy.restitution = 0.9;
  const SceneConfig scene = seated_follower_scene(1800.0, bouncy);
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
  const double revolutions = *scene.simulation.cycles - scene.simulation.discard_cycles;
  EXPECT_GT(r.metrics.train->seat_impacts, static_cast<long>(2 * revolutions));
}

// The energy balance of a train closes like a single follower's: its
// residual falls with the integrator's tolerance.
TEST(FollowerTrainEnergy, ResidualScalesWithTolerance) {
  LinearTrainCase c = linear_train_case(2, true);
  c.scene.mechanism.cam.rpm = 2000.0;
  c.scene.simulation.steady_state = false;
  c.scene.simulation.cycles = 2;
  double previous = INFINITY;
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    c.scene.integrator.rtol = rtol;
    c.scene.integrator.atol = 1e-4 * rtol;
    const SimulationResult r = simulate_scene(c.scene, "test");
    ASSERT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
    EXPECT_LT(r.metrics.energy_residual, 100.0 * rtol) << "rtol " << rtol;
    EXPECT_LT(r.metrics.energy_residual, previous) << "rtol " << rtol;
    previous = r.metrics.energy_residual;
  }
}

}  // namespace
}  // namespace camdyn
