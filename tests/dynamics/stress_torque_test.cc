// The contact stress and drive metrics of a run (docs/model.md §8, "Contact
// stress and drive torque"): peak_contact_stress against Hertz's closed forms
// on a constant-curvature contact, the flat face's local cam radius
// r_b + s + s'' and face excursion max |s'|, and the drive torque and power
// against the run's own energy balance and the rigid model's virtual power.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "common/constants.h"
#include "contact/hertz_pressure.h"
#include "dynamics/contact_stress.h"
#include "dynamics/simulation.h"
#include "scenes.h"

namespace camdyn {
namespace {

constexpr double kSteelE = 210e9, kNu = 0.3, kWidth = 0.012;  // steel on steel, 12 mm wide [Pa, -, m]
const double kEStar = 1.0 / (2.0 * (1.0 - kNu * kNu) / kSteelE);

// The stress is computed from the same evaluation as the force: only
// rounding separates it from the closed form of that force.
constexpr double kClosedForm = 1e-12;  // relative
// Brief's acceptance level for the stress of a run (the peak force and the
// peak stress are folded from the same evaluations).
constexpr double kStressAcceptance = 1e-6;  // relative

/// Gives a scene's contact steel-on-steel materials: a line contact `kWidth`
/// wide, or a point contact without a width.
void use_steel(SceneConfig& s, bool line) {
  ContactConfig& c = s.mechanism.contact;
  c.stiffness.reset();
  c.from_materials = MaterialsConfig{kSteelE, kNu, kSteelE, kNu, line ? std::optional<double>(kWidth) : std::nullopt};
  c.exponent = line ? 1.0 : 1.5;
}

/// The model evaluated with the follower `depth` [m] into the cam on its law at
/// cam angle `theta` [rad], at rest (Newton tracking from θ).
Evaluation pressed_at(const Model& model, double theta, double depth) {
  Model newton = model;
  newton.tracking = Tracking::newton;
  Workspace ws = make_workspace(newton);
  ws.u_warm = theta;
  double y[StateLayout::kMax] = {};
  y[0] = model.law->eval(theta).s - depth;
  if (model.layout.u) y[*model.layout.u] = theta;
  Evaluation ev;
  evaluate(newton, ws, (theta - model.theta0) / (model.omega > 0.0 ? model.omega : 1.0), y, ev);
  return ev;
}

// A roller pressed onto the base circle (a circular arc: constant curvature)
// carries Hertz's line-contact pressure p₀ = √(F E* (1/r_b + 1/r) / (π L)).
TEST(ContactStress, RollerOnTheBaseCircleCarriesTheHertzLinePressure) {
  SceneConfig scene = test::cycloidal_cam_scene(0.0);
  use_steel(scene, true);
  scene.mechanism.cam.initial_angle_deg = 330.0;  // base-circle dwell
  const Model model = build_model(scene, "test");
  ASSERT_TRUE(model.hertz.has_value());
  const double theta = 330.0 * kPi / 180.0;
  const Evaluation ev = pressed_at(model, theta, 2e-6);
  ASSERT_GT(ev.normal_force, 0.0);
  const double curvature = 1.0 / scene.mechanism.cam.base_radius + 1.0 / scene.mechanism.follower.shape.radius;
  const double expected = std::sqrt(ev.normal_force * kEStar * curvature / (kPi * kWidth));
  EXPECT_NEAR(contact_pressure(model, *model.hertz, ev) / expected, 1.0, kClosedForm);
}

// Without a width the materials give a point contact:
// p₀ = (6 F E*² (1/r_b + 1/r)² / π³)^{1/3}.
TEST(ContactStress, WithoutAWidthTheContactIsAHertzPointContact) {
  SceneConfig scene = test::cycloidal_cam_scene(0.0);
  use_steel(scene, false);
  scene.mechanism.cam.initial_angle_deg = 330.0;  // base-circle dwell
  const Model model = build_model(scene, "test");
  ASSERT_TRUE(model.hertz.has_value());
  const Evaluation ev = pressed_at(model, 330.0 * kPi / 180.0, 1e-6);
  ASSERT_GT(ev.normal_force, 0.0);
  const double curvature = 1.0 / scene.mechanism.cam.base_radius + 1.0 / scene.mechanism.follower.shape.radius;
  const double expected =
      std::cbrt(6.0 * ev.normal_force * kEStar * kEStar * curvature * curvature / (kPi * kPi * kPi));
  EXPECT_NEAR(contact_pressure(model, *model.hertz, ev) / expected, 1.0, kClosedForm);
}

// A roller dropped onto the base circle of a cam held still bounces on a
// contact of constant curvature: the run's peak stress is the Hertz pressure
// of its own peak contact force.
TEST(ContactStress, RunOnAConstantCurvatureContactPeaksAtTheHertzPressureOfItsPeakForce) {
  SceneConfig scene = test::drop_scene(ContactModel::lankarani_nikravesh, 0.8);
  use_steel(scene, true);
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  ASSERT_TRUE(r.metrics.peak_contact_stress.has_value());
  const double curvature = 1.0 / scene.mechanism.cam.base_radius + 1.0 / scene.mechanism.follower.shape.radius;
  const double force = r.metrics.peak_contact_force;
  ASSERT_GT(force, 0.0);
  const double expected = std::sqrt(force * kEStar * curvature / (kPi * kWidth));
  EXPECT_NEAR(*r.metrics.peak_contact_stress / expected, 1.0, kStressAcceptance);
  EXPECT_FALSE(r.metrics.max_face_excursion.has_value());  // a roller has no face
}

// A translating flat face touches the cam where its local radius is
// r_b + s(θ) + s''(θ): the stress uses it.
TEST(ContactStress, FlatFaceUsesTheCamsLocalRadiusBaseRadiusPlusLiftPlusItsSecondDerivative) {
  SceneConfig scene = test::follower_scene("translating_flat", 600.0);
  use_steel(scene, true);
  const Model model = build_model(scene, "test");
  const double rb = scene.mechanism.cam.base_radius;
  for (const double deg : {20.0, 60.0, 100.0, 150.0, 200.0, 240.0, 290.0}) {
    SCOPED_TRACE(deg);
    const Evaluation ev = pressed_at(model, deg * kPi / 180.0, 1e-6);
    ASSERT_GT(ev.normal_force, 0.0);
    const LawSample s = model.law->eval(ev.pair.u);
    const double radius = rb + s.s + s.d2s;
    EXPECT_NEAR(contact_cam_radius_of_curvature(model, ev) / radius, 1.0, 1e-9);
    const double expected = std::sqrt(ev.normal_force * kEStar / (kPi * kWidth * radius));
    EXPECT_NEAR(contact_pressure(model, *model.hertz, ev) / expected, 1.0, 1e-9);
  }
}

// The contact point of a translating flat face sits s'(θ) from the face's
// centre whatever the follower does, so its largest excursion over whole
// revolutions is max |s'|; no materials, no stress metric.
TEST(ContactStress, FlatFaceExcursionIsTheLargestFirstDerivativeOfTheLift) {
  SceneConfig scene = test::follower_scene("translating_flat", 600.0);
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  const Model model = build_model(scene, "test");
  double largest = 0.0;
  for (int i = 0; i < 360000; ++i) largest = std::max(largest, std::abs(model.law->eval(2.0 * kPi * i / 360000).ds));
  ASSERT_TRUE(r.metrics.max_face_excursion.has_value());
  // The 0.001° grid misses the smooth maximum by ½ |s'''/s'| Δθ² ≈ 1e-9; the
  // tracked pair sits on θ to the tracking's drift (≪ 1e-7 rad at rtol 1e-9).
  EXPECT_NEAR(*r.metrics.max_face_excursion / largest, 1.0, 1e-6);
  EXPECT_LT(*r.metrics.max_face_excursion, 0.5 * scene.mechanism.follower.shape.face_width);
  EXPECT_FALSE(r.metrics.peak_contact_stress.has_value());
}

// A roller on a cycloidal cam with a viscous damper (no friction, an elastic
// Hertz contact: the damper alone dissipates). The rigid follower's drive
// torque is T = P s', so over a revolution ∫ T dθ = c ω ∫ s'² dθ: what the
// damper takes (spring, inertia and preload give back what they take).
SceneConfig damped_roller_scene(double rpm) {
  SceneConfig scene = test::cycloidal_cam_scene(rpm, ContactModel::hertz);
  scene.mechanism.follower.damping = 20.0;  // [N s/m]
  scene.simulation.cycles = 4;
  scene.simulation.discard_cycles = 2;
  scene.simulation.output_step_deg = 0.1;
  return scene;
}

TEST(DriveTorque, RigidTorqueIntegratesToTheDampersWorkOverARevolution) {
  const SceneConfig scene = damped_roller_scene(600.0);
  const Model model = build_model(scene, "test");
  const double c = scene.mechanism.follower.damping, omega = model.omega;
  constexpr int kN = 36000;
  double torque = 0.0, damper = 0.0;  // ∫ T dθ [J], c ω ∫ s'² dθ [J] by the trapezoid (periodic: spectral)
  for (int i = 0; i < kN; ++i) {
    const double theta = 2.0 * kPi * i / kN, ds = model.law->eval(theta).ds;
    torque += rigid_cam_torque(model, theta, omega) * 2.0 * kPi / kN;
    damper += c * omega * ds * ds * 2.0 * kPi / kN;
  }
  EXPECT_NEAR(torque / damper, 1.0, 1e-9);
}

/// ∫ f dt over uniformly spaced samples f[i0..i1] (Simpson where the count allows, else a trapezoid at the end).
double integrate_series(const std::vector<double>& t, const std::vector<double>& f, std::size_t i0, std::size_t i1) {
  double sum = 0.0;
  std::size_t i = i0;
  for (; i + 2 <= i1; i += 2) sum += (t[i + 2] - t[i]) / 6.0 * (f[i] + 4.0 * f[i + 1] + f[i + 2]);
  if (i < i1) sum += 0.5 * (t[i1] - t[i]) * (f[i] + f[i1]);
  return sum;
}

// At constant speed without friction the drive's mean power over the window
// is the damper's dissipation plus the change of the mechanical energy
// (kinetic, spring, Hertz contact), each from the run's own time series.
TEST(DriveTorque, MeanDrivePowerBalancesTheDissipationAtSteadyState) {
  const SceneConfig scene = damped_roller_scene(600.0);
  const Model model = build_model(scene, "test");
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  const TimeSeries& ts = r.series;
  const auto first = std::lower_bound(ts.time.begin(), ts.time.end(), r.evaluated_from * (1.0 - 1e-12));
  const std::size_t i0 = static_cast<std::size_t>(first - ts.time.begin()), i1 = ts.time.size() - 1;
  ASSERT_NEAR(ts.time[i0], r.evaluated_from, 1e-12);
  ASSERT_NEAR(ts.time[i1], r.end_time, 1e-12);
  const FollowerConfig& f = scene.mechanism.follower;
  const double k = f.spring.stiffness, x0 = f.spring.preload / k, K = *scene.mechanism.contact.stiffness;
  auto energy = [&](std::size_t i) {
    const double delta = std::max(0.0, -ts.gap[i]);
    return 0.5 * f.mass * ts.follower_velocity[i] * ts.follower_velocity[i] +
           0.5 * k * (ts.follower_position[i] + x0) * (ts.follower_position[i] + x0) + K * std::pow(delta, 2.5) / 2.5;
  };
  std::vector<double> damper_power(ts.time.size());
  for (std::size_t i = 0; i < ts.time.size(); ++i)
    damper_power[i] = f.damping * ts.follower_velocity[i] * ts.follower_velocity[i];
  const double window = r.end_time - r.evaluated_from;
  const double dissipated = integrate_series(ts.time, damper_power, i0, i1);
  const double balance = (dissipated + energy(i1) - energy(i0)) / window;
  // Energy-balance level: the run's residual at rtol 1e-9 is ~1e-7 of its
  // energy scale (a few J against ~0.7 J dissipated a revolution; measured
  // 6e-8 here); Simpson on the 0.1° series adds (Δt)⁴-small terms.
  constexpr double kEnergyBalance = 1e-6;
  EXPECT_NEAR(r.metrics.mean_drive_power / balance, 1.0, kEnergyBalance);
  EXPECT_LT(r.metrics.energy_residual, 1e-6);
  // |mean T| ≤ RMS: at constant speed the mean power is ω times the mean torque.
  EXPECT_LE(r.metrics.mean_drive_power, model.omega * r.metrics.rms_cam_torque);
}

// A stiff contact at moderate speed follows the rigid model: the run's peak
// and RMS drive torque are the rigid model's to the rigid-comparison level.
TEST(DriveTorque, PeakAndRmsTorqueFollowTheRigidModel) {
  const SceneConfig scene = damped_roller_scene(600.0);
  const Model model = build_model(scene, "test");
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  constexpr int kN = 36000;
  double peak = 0.0, squares = 0.0, mean = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double t = rigid_cam_torque(model, 2.0 * kPi * i / kN, model.omega);
    peak = std::max(peak, std::abs(t));
    squares += t * t / kN;
    mean += t / kN;
  }
  EXPECT_NEAR(r.metrics.peak_cam_torque / peak, 1.0, test::kRigidForceAcceptance);
  EXPECT_NEAR(r.metrics.rms_cam_torque / std::sqrt(squares), 1.0, test::kRigidForceAcceptance);
  EXPECT_NEAR(r.metrics.mean_drive_power / (model.omega * mean), 1.0, test::kRigidForceAcceptance);
}

// The per-step stress and torque run inside the observer at every step: no heap.
TEST(ContactStress, PerStepStressAndTorqueAllocateNothing) {
  for (const std::string kind : {"translating_roller", "translating_flat", "oscillating_mushroom"}) {
    SCOPED_TRACE(kind);
    SceneConfig scene = test::follower_scene(kind, 600.0);
    use_steel(scene, kind.find("roller") != std::string::npos || kind.find("flat") != std::string::npos);
    const Model model = build_model(scene, "test");
    const Evaluation ev = pressed_at(model, 1.0, 1e-6);
    double sum = 0.0;
    const long before = test::allocation_count();
    for (int i = 0; i < 100; ++i) sum += contact_pressure(model, *model.hertz, ev) + cam_drive_torque(ev);
    EXPECT_EQ(test::allocation_count() - before, 0);
    EXPECT_TRUE(std::isfinite(sum));
  }
}

}  // namespace
}  // namespace camdyn
