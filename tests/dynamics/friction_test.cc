// Friction where it acts (docs/model.md §4): sliding at a flat face or a
// mushroom, guide friction of a translating follower, pivot friction of an
// oscillating one; each against a rigid-model or kinematic result computed
// here, and each closing the energy balance with its work.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/constants.h"
#include "dynamics/simulation.h"
#include "geometry/motion_law.h"
#include "rigid_follower.h"
#include "scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

TEST(Friction, FlatFaceSlipIsTheCamSurfaceSpeedAndFrictionIsMuTimesNormalForce) {
  // A translating flat face touches the cam at its support point, height
  // r_b + s(θ) (the face is δ lower, interfering): the cam surface there moves
  // across the face at ω (r_b + s), and the face does not move across.
  SceneConfig scene = test::follower_scene("translating_flat", 600.0, ContactModel::lankarani_nikravesh);
  scene.mechanism.contact.friction.mu = 0.1;
  scene.mechanism.contact.friction.regularization_velocity = 1e-4;
  const Model model = build_model(scene, "test");
  Workspace ws;
  const double omega = 600.0 * kTwoPi / 60.0;
  for (double theta_deg : {20.0, 90.0, 150.0, 250.0}) {
    const double t = theta_deg / 360.0 * kTwoPi / omega;
    const LawSample s = model.law->eval(model.theta(t));
    const double y = s.s - 4e-6;
    double state[StateLayout::kMax] = {y, omega * s.ds, model.theta(t)};
    ws.u_warm = model.theta(t);
    Evaluation ev;
    evaluate(model, ws, t, state, ev);
    ASSERT_GT(ev.normal_force, 0.0);
    EXPECT_NEAR(std::abs(ev.slip), omega * (scene.mechanism.cam.base_radius + s.s), test::kAmplifiedRoundoff * omega);
    EXPECT_NEAR(std::abs(ev.friction_force), 0.1 * ev.normal_force, 1e-9 * ev.normal_force);
    EXPECT_GT(ev.power_friction, 0.0);
  }
}

TEST(Friction, SlidingFrictionClosesTheEnergyBalance) {
  for (const char* kind : {"translating_flat", "translating_mushroom", "oscillating_flat", "oscillating_mushroom"}) {
    SceneConfig scene = test::follower_scene(kind, 800.0, ContactModel::lankarani_nikravesh);
    scene.mechanism.contact.friction.mu = 0.1;
    scene.mechanism.contact.friction.regularization_velocity = 1e-3;
    const SimulationResult r = simulate_scene(scene, "test");
    EXPECT_LT(r.metrics.energy_residual, 1e-6) << kind;
    // The friction peak is read from the 0.5° output series, the force peak at the integrator's steps.
    constexpr double kSampledPeaks = 2e-3;
    double max_friction = 0.0;
    for (double f : r.series.friction_force) max_friction = std::max(max_friction, std::abs(f));
    EXPECT_NEAR(max_friction / r.metrics.peak_contact_force, 0.1, kSampledPeaks) << kind;
  }
}

/// Largest relative difference between the simulated contact force and
/// `rigid(θ, ẏ_law)` where the law's rate is well outside the regularisation band.
template <class Rigid>
double worst_force_error(const SimulationResult& r, const MotionLaw& law, double omega, double band,
                         const Rigid& rigid) {
  double worst = 0.0;
  for (size_t i = 0; i < r.series.time.size(); ++i) {
    if (r.series.time[i] < r.evaluated_from) continue;
    const double theta = r.series.cam_angle_deg[i] * kTwoPi / 360.0;
    const LawSample s = law.eval(theta);
    if (std::abs(omega * s.ds) < band) continue;
    worst = std::max(worst, std::abs(r.series.contact_force[i] / rigid(theta, s) - 1.0));
  }
  return worst;
}

TEST(Friction, GuideFrictionMatchesTheRigidModel) {
  // Rigid: m ÿ = F_n cos φ − μ_g F_n |sin φ| sgn ẏ − k (y + x₀), so
  // F_n = P / (cos φ − μ_g |sin φ| sgn ẏ) with φ = atan((s' − e)/(y₀ + s)).
  SceneConfig scene = test::cycloidal_cam_scene(100.0, ContactModel::lankarani_nikravesh);
  scene.mechanism.follower.offset = 0.01;
  scene.mechanism.follower.guide_friction = GuideFrictionConfig{0.3, 1e-5};
  const SimulationResult r = simulate_scene(scene, "test");
  const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test");
  const FollowerConfig& f = scene.mechanism.follower;
  const double omega = 100.0 * kTwoPi / 60.0, e = f.offset;
  const double y0 = std::sqrt(0.05 * 0.05 - e * e);
  auto rigid = [&](double, const LawSample& s) {
    const double phi = std::atan((s.ds - e) / (y0 + s.s));
    const double p = f.mass * omega * omega * s.d2s + f.spring.stiffness * s.s + f.spring.preload;
    return p / (std::cos(phi) - 0.3 * std::abs(std::sin(phi)) * (s.ds > 0 ? 1.0 : -1.0));
  };
  EXPECT_LT(worst_force_error(r, law, omega, 1e-3, rigid), 5e-3);
  EXPECT_EQ(r.metrics.separation_fraction, 0.0);
  SceneConfig fast = scene;
  fast.mechanism.cam.rpm = 900.0;
  fast.mechanism.follower.guide_friction->regularization_velocity = 1e-3;
  EXPECT_LT(simulate_scene(fast, "test").metrics.energy_residual, 1e-6);
}

TEST(Friction, PivotFrictionMatchesTheRigidModel) {
  // Rigid: I φ̈ = F_n ∂g/∂φ − μ_p r_pin F_n sgn φ̇ − k (φ + x₀), the pin
  // reaction taken as the contact force: F_n = Q / (∂g/∂φ − μ_p r_pin sgn φ̇),
  // the lever ∂g/∂φ from the arm's geometry (rigid_follower.h).
  SceneConfig scene = test::follower_scene("oscillating_roller", 100.0, ContactModel::lankarani_nikravesh);
  scene.mechanism.follower.pivot_friction = PivotFrictionConfig{0.3, 0.008, 1e-5};
  const SimulationResult r = simulate_scene(scene, "test");
  const test::Rigid rigid(scene);
  const double omega = 100.0 * kTwoPi / 60.0;
  auto expected = [&](double theta, const LawSample& s) {
    return rigid.generalised(theta, omega) / (rigid.lever(theta) - 0.3 * 0.008 * (s.ds > 0 ? 1.0 : -1.0));
  };
  EXPECT_LT(worst_force_error(r, rigid.law, omega, 1e-3 / 0.008, expected), 5e-3);
  EXPECT_EQ(r.metrics.separation_fraction, 0.0);
  SceneConfig fast = scene;
  fast.mechanism.cam.rpm = 900.0;
  fast.mechanism.follower.pivot_friction->regularization_velocity = 1e-3;
  EXPECT_LT(simulate_scene(fast, "test").metrics.energy_residual, 1e-6);
}

}  // namespace
}  // namespace camdyn
