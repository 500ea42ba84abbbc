// A translating roller follower on a running cam, against the rigid model of
// docs/model.md §9 computed here independently of the library.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/constants.h"
#include "dynamics/simulation.h"
#include "geometry/motion_law.h"
#include "scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// Independent rigid-model quantities for the test scene (no offset, ccw).
struct Rigid {
  const SceneConfig& scene;
  MotionLaw law;
  explicit Rigid(const SceneConfig& s) : scene(s), law(build_motion_law(s.mechanism.cam.motion_law, "test")) {}

  double force(double theta, double omega) const {
    const auto& f = scene.mechanism.follower;
    const LawSample s = law.eval(theta);
    const double x0 = f.spring.preload / f.spring.stiffness;
    const double axial = f.mass * omega * omega * s.d2s + f.damping * omega * s.ds + f.spring.stiffness * (s.s + x0) +
                         f.mass * scene.gravity;
    const double y0 = scene.mechanism.cam.base_radius + f.shape.radius;
    const double phi = std::atan((s.ds - f.offset) / (y0 + s.s));
    return axial / std::cos(phi);
  }

  double jump_rpm() const {
    const auto& f = scene.mechanism.follower;
    double best = INFINITY;
    for (int i = 0; i < 36000; ++i) {
      const LawSample s = law.eval(kTwoPi * i / 36000);
      if (s.d2s < 0)
        best = std::min(
            best, std::sqrt(f.spring.stiffness * (s.s + f.spring.preload / f.spring.stiffness) / (-f.mass * s.d2s)));
    }
    return best * 60 / kTwoPi;
  }
};

void expect_finite(const TimeSeries& ts) {
  const auto names = TimeSeries::column_names();
  const auto columns = ts.columns();
  for (size_t c = 0; c < columns.size(); ++c) {
    ASSERT_FALSE(columns[c]->empty()) << names[c];
    for (double v : *columns[c]) ASSERT_TRUE(std::isfinite(v)) << names[c];
  }
}

TEST(CamScene, LowSpeedFollowsTheLawAndRigidForce) {
  SceneConfig scene = test::cycloidal_cam_scene(100.0, ContactModel::lankarani_nikravesh);
  const SimulationResult r = simulate_scene(scene, "test");
  expect_finite(r.series);
  const Rigid rigid(scene);
  const double omega = 100.0 * kTwoPi / 60.0;
  EXPECT_EQ(r.metrics.separation_fraction, 0.0);
  EXPECT_EQ(r.metrics.impact_count, 0);
  double worst = 0.0, f_max = 0.0;
  for (size_t i = 0; i < r.series.time.size(); ++i) {
    if (r.series.time[i] < r.evaluated_from) continue;
    const double expected = rigid.force(r.series.cam_angle_deg[i] * kTwoPi / 360.0, omega);
    worst = std::max(worst, std::abs(r.series.contact_force[i] / expected - 1.0));
    f_max = std::max(f_max, expected);
  }
  EXPECT_LT(worst, test::kRigidForceAcceptance);  // acceptance: within 0.5 % of the rigid-model force
  const double static_deflection = std::pow(f_max / *scene.mechanism.contact.stiffness, 1.0 / 1.5);
  EXPECT_LT(r.metrics.max_kinematic_error, 2.0 * static_deflection);
  EXPECT_NEAR(r.metrics.peak_contact_force / f_max, 1.0, test::kRigidForceAcceptance);
}

TEST(CamScene, JumpSpeedMatchesIndependentRigidModel) {
  const SceneConfig scene = test::cycloidal_cam_scene(1000.0);
  const SimulationResult r = simulate_scene(scene, "test");
  EXPECT_NEAR(r.metrics.jump_speed_rpm / Rigid(scene).jump_rpm(), 1.0, test::kRigidJumpGrid);
}

TEST(CamScene, NoSeparationBelowJumpSpeedSeparationAbove) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  {
    const SimulationResult r =
        simulate_scene(test::cycloidal_cam_scene(0.9 * jump, ContactModel::lankarani_nikravesh), "test");
    EXPECT_EQ(r.metrics.separation_fraction, 0.0);
    EXPECT_GT(r.metrics.min_contact_force, 0.0);
  }
  {
    const SceneConfig scene = test::cycloidal_cam_scene(1.15 * jump, ContactModel::lankarani_nikravesh);
    const SimulationResult r = simulate_scene(scene, "test");
    EXPECT_GT(r.metrics.separation_fraction, 0.0);
    EXPECT_EQ(r.metrics.min_contact_force, 0.0);
    const double evaluated_cycles = *scene.simulation.cycles - scene.simulation.discard_cycles;
    EXPECT_GE(static_cast<double>(r.metrics.impact_count), evaluated_cycles);
    EXPECT_GT(r.metrics.max_impact_velocity, 0.0);
  }
}

TEST(CamScene, ConservativeSceneClosesEnergyBalance) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  SceneConfig scene = test::cycloidal_cam_scene(1.15 * jump, ContactModel::hertz);  // with impacts
  const SimulationResult r = simulate_scene(scene, "test");
  EXPECT_GT(r.metrics.impact_count, 0);
  EXPECT_LT(r.metrics.energy_residual, 1e-6);
}

TEST(CamScene, DampedFrictionalSceneClosesEnergyBalance) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  SceneConfig scene = test::cycloidal_cam_scene(1.15 * jump, ContactModel::lankarani_nikravesh);
  scene.mechanism.follower.damping = 5.0;
  scene.mechanism.follower.shape.inertia = 2e-6;
  scene.mechanism.contact.friction.mu = 0.1;
  scene.mechanism.contact.friction.regularization_velocity = 1e-3;
  const SimulationResult r = simulate_scene(scene, "test");
  EXPECT_GT(r.metrics.impact_count, 0);
  EXPECT_LT(r.metrics.energy_residual, 1e-6);
  double max_friction = 0.0;
  for (double f : r.series.friction_force) max_friction = std::max(max_friction, std::abs(f));
  EXPECT_GT(max_friction, 0.0);  // friction acts (skidding at impacts)
}

class TrackingModes : public ::testing::TestWithParam<double> {};

TEST_P(TrackingModes, DifferentialAndNewtonAgree) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  SceneConfig scene = test::cycloidal_cam_scene(GetParam() * jump, ContactModel::lankarani_nikravesh);
  scene.integrator.rtol = 1e-10;
  scene.integrator.atol = 1e-15;
  scene.mechanism.contact.tracking = Tracking::differential;
  const SimulationResult d = simulate_scene(scene, "test");
  scene.mechanism.contact.tracking = Tracking::newton;
  const SimulationResult n = simulate_scene(scene, "test");
  expect_finite(d.series);
  expect_finite(n.series);
  // Agreement to within the integration tolerance, propagated: the runs differ
  // by their own integration errors only (rtol 1e-10), amplified by the
  // sensitivity of the flight after a separation; 1e-5 relative covers it.
  const double tol = test::integrator_tolerance(scene.integrator.rtol, 1e5);
  const Metrics& a = d.metrics;
  const Metrics& b = n.metrics;
  EXPECT_NEAR(a.peak_contact_force, b.peak_contact_force, tol * b.peak_contact_force);
  EXPECT_NEAR(a.min_contact_force, b.min_contact_force, tol * b.peak_contact_force);
  EXPECT_NEAR(a.separation_fraction, b.separation_fraction, tol);
  EXPECT_NEAR(a.max_separation_gap, b.max_separation_gap, tol * std::max(b.max_separation_gap, 1e-6));
  EXPECT_NEAR(a.max_penetration, b.max_penetration, tol * b.max_penetration);
  EXPECT_NEAR(a.max_kinematic_error, b.max_kinematic_error, tol * b.max_kinematic_error);
  EXPECT_EQ(a.impact_count, b.impact_count);
  EXPECT_NEAR(a.max_impact_velocity, b.max_impact_velocity, tol * std::max(b.max_impact_velocity, 1e-3));
  EXPECT_LT(d.metrics.energy_residual, 1e-6);
  EXPECT_LT(n.metrics.energy_residual, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(BelowAndAboveJump, TrackingModes, ::testing::Values(0.5, 1.15));

TEST(CamScene, ModelHoldsOnlyWhatTheSceneNeeds) {
  SceneConfig scene = test::cycloidal_cam_scene(500.0);
  scene.mechanism.contact.tracking = Tracking::newton;
  Model m = build_model(scene, "test");
  EXPECT_EQ(m.layout.size, 2);
  EXPECT_EQ(m.elements, (std::vector<std::string>{"follower_mass", "spring", "contact:hertz"}));
  scene.mechanism.contact.tracking = Tracking::differential;
  EXPECT_EQ(build_model(scene, "test").layout.size, 3);
  scene.mechanism.contact.friction.mu = 0.2;  // no roller inertia: rolls freely, no friction work
  EXPECT_EQ(build_model(scene, "test").layout.size, 3);
  scene.mechanism.follower.shape.inertia = 1e-6;
  m = build_model(scene, "test");
  EXPECT_EQ(m.layout.size, 4);
  EXPECT_EQ(m.elements.back(), "friction:coulomb_tanh");
  scene.mechanism.follower.damping = 1.0;
  scene.gravity = 9.81;
  m = build_model(scene, "test");
  EXPECT_NE(std::find(m.elements.begin(), m.elements.end(), "damper"), m.elements.end());
  EXPECT_NE(std::find(m.elements.begin(), m.elements.end(), "gravity"), m.elements.end());
}

}  // namespace
}  // namespace camdyn

namespace camdyn {
namespace {

TEST(CamScene, SeparationIntegralMatchesTheGapTimeSeries) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  const SimulationResult below = simulate_scene(test::cycloidal_cam_scene(0.9 * jump), "test");
  EXPECT_EQ(below.metrics.separation_integral, 0.0);
  SceneConfig scene = test::cycloidal_cam_scene(1.15 * jump, ContactModel::lankarani_nikravesh);
  scene.simulation.output_step_deg = 0.05;
  const SimulationResult r = simulate_scene(scene, "test");
  double trapezoid = 0.0;
  const TimeSeries& ts = r.series;
  for (size_t i = 1; i < ts.time.size(); ++i) {
    if (ts.time[i - 1] < r.evaluated_from) continue;
    trapezoid += 0.5 * (std::max(ts.gap[i], 0.0) + std::max(ts.gap[i - 1], 0.0)) * (ts.time[i] - ts.time[i - 1]);
  }
  // The trapezoid rule on a 0.05° grid is accurate to well under 1 % here.
  constexpr double kTrapezoid = 1e-2;
  EXPECT_GT(r.metrics.separation_integral, 0.0);
  EXPECT_NEAR(r.metrics.separation_integral / trapezoid, 1.0, kTrapezoid);
}

TEST(CamScene, SamplesAtRequestedTimesMatchTheOutputGrid) {
  SceneConfig scene = test::cycloidal_cam_scene(800.0, ContactModel::lankarani_nikravesh);
  SimulationOptions options;
  const SimulationResult grid = simulate_scene(scene, "test");
  for (size_t i = 10; i < grid.series.time.size(); i += 97) options.sample_times.push_back(grid.series.time[i]);
  const SimulationResult sampled = simulate_scene(scene, "test", options);
  ASSERT_EQ(sampled.samples.time.size(), options.sample_times.size());
  for (size_t k = 0; k < options.sample_times.size(); ++k) {
    const size_t i = 10 + 97 * k;
    EXPECT_EQ(sampled.samples.time[k], grid.series.time[i]);
    EXPECT_DOUBLE_EQ(sampled.samples.contact_force[k], grid.series.contact_force[i]);
    EXPECT_DOUBLE_EQ(sampled.samples.follower_position[k], grid.series.follower_position[i]);
  }
}

// The jumping scene (1.15 × the jump speed: events) with `tracking`, sampled
// at every 7th output time, run with `options` and again after `change`.
std::pair<SimulationResult, SimulationResult> run_twice(Tracking tracking, SimulationOptions options,
                                                        void (*change)(SimulationOptions&)) {
  const double jump = Rigid(test::cycloidal_cam_scene(1000.0)).jump_rpm();
  SceneConfig scene = test::cycloidal_cam_scene(1.15 * jump, ContactModel::lankarani_nikravesh);
  scene.mechanism.contact.tracking = tracking;
  options.record_series = false;
  const SimulationResult grid = simulate_scene(scene, "test");
  for (size_t i = 3; i < grid.series.time.size(); i += 7) options.sample_times.push_back(grid.series.time[i]);
  SimulationResult first = simulate_scene(scene, "test", options);
  change(options);
  return {std::move(first), simulate_scene(scene, "test", options)};
}

// The same run to the last bit: steps, right-hand sides, events and every
// sampled column but the energy residual.
void expect_same_run(const SimulationResult& a, const SimulationResult& b) {
  ASSERT_TRUE(b.solver.converged());
  ASSERT_GT(a.events.size(), 1u);  // it jumps and lands
  EXPECT_EQ(b.solver.counters.steps, a.solver.counters.steps);
  EXPECT_EQ(b.solver.counters.rhs_evaluations, a.solver.counters.rhs_evaluations);
  ASSERT_EQ(b.events.size(), a.events.size());
  for (size_t k = 0; k < a.events.size(); ++k) EXPECT_EQ(b.events[k].time, a.events[k].time) << k;
  const std::vector<const std::vector<double>*> ca = a.samples.columns(), cb = b.samples.columns();
  const std::vector<std::string> names = TimeSeries::column_names();
  for (size_t c = 0; c < names.size(); ++c) {
    if (names[c] == "energy_residual") continue;  // scaled by the energy followed over every step
    ASSERT_EQ(cb[c]->size(), ca[c]->size()) << names[c];
    for (size_t i = 0; i < ca[c]->size(); ++i) ASSERT_EQ((*cb[c])[i], (*ca[c])[i]) << names[c] << " sample " << i;
  }
}

// Identification asks for the samples alone (step_metrics off): the run must
// be the same run to the last bit, with either tracking.
TEST(CamScene, SamplesOnlyRunIsTheSameRunToTheBit) {
  for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
    SCOPED_TRACE(tracking == Tracking::newton ? "newton" : "differential");
    const auto [every_step, samples_only] =
        run_twice(tracking, SimulationOptions{}, [](SimulationOptions& o) { o.step_metrics = false; });
    expect_same_run(every_step, samples_only);
  }
}

// Without the quadratures (identification's fit runs) the run is the same
// run to the last bit: the quadratures are integrated beside the state, not
// by the integrator, so they cannot change its steps. The figures they give
// are unknown (NaN), not zero.
TEST(CamScene, RunWithoutQuadraturesIsTheSameRunAndLeavesTheEnergyUnknown) {
  for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
    SCOPED_TRACE(tracking == Tracking::newton ? "newton" : "differential");
    SimulationOptions options;
    options.step_metrics = false;
    const auto [with, without] = run_twice(tracking, options, [](SimulationOptions& o) { o.quadratures = false; });
    expect_same_run(with, without);
    EXPECT_TRUE(std::isnan(without.metrics.energy_residual));
    EXPECT_TRUE(std::isnan(without.metrics.separation_integral));
    EXPECT_TRUE(std::isnan(without.samples.energy_residual.front()));
    EXPECT_FALSE(std::isnan(with.metrics.energy_residual));
  }
}

}  // namespace
}  // namespace camdyn
