// The rigid stage on a follower train (optim/optimize/train_rows.h,
// docs/optimize.md "Trains"): the held train's predicted forces against
// camdyn's own steady-state simulation of the full nonlinear train, and the
// certificate's figures against the scene's jump speed and the closed form.
#include "optim/optimize/train_rows.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "../dynamics/linear_train_case.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "optim/optimize/design.h"
#include "optim/optimize/rigid_design.h"
#include "study/steady_state.h"

namespace camdyn::optim {
namespace {

constexpr double kRadPerRpm = std::numbers::pi / 30.0;

/// A rise and a return as degree-5 splines with random monotone control points.
MotionLawConfig random_spline_law(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto points = [&] {
    std::vector<double> c(6);
    for (double& x : c) x = u(rng);
    std::sort(c.begin(), c.end());
    return c;
  };
  MotionLawConfig law;
  law.segments = {{SegmentType::rise, SegmentLaw::spline, 120.0, test::kLift, std::nullopt, 5, points()},
                  {SegmentType::dwell, SegmentLaw::none, 160.0, std::nullopt, std::nullopt, 5, {}},
                  {SegmentType::return_, SegmentLaw::spline, 280.0, test::kLift, std::nullopt, 5, points()},
                  {SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}}};
  return law;
}

// Acceptance: a random spline law on a two-body train (follower and valve)
// whose valve spring has 8 coils: the held train's contact and link forces
// over a revolution (the rows' values) meet the steady state of the full
// nonlinear simulation within 0.5 % of the peak contact force.
TEST(TrainRows, PredictedForcesMeetTheSteadyStateOfTheNonlinearTrain) {
  test::LinearTrainCase c = test::linear_train_case(1, false, 8);
  SceneConfig& scene = c.scene;
  scene.mechanism.cam.motion_law = random_spline_law(7);
  scene.mechanism.cam.base_radius = 0.04;  // a flat face needs r_b + s + s'' > 0 for a random law
  const Model model = build_model(scene, "test");
  const double jump_rpm = model.train_jump_speed_rpm;
  ASSERT_TRUE(std::isfinite(jump_rpm));
  for (const double fraction : {0.5, 0.85}) {
    const double rpm = fraction * jump_rpm;
    SCOPED_TRACE(testing::Message() << rpm << " rpm (jump speed " << jump_rpm << ")");
    const HeldTrain held = held_train(model);
    const std::vector<Eigen::VectorXd> v = held_train_values(
        held, grid_signal([&](double theta) { return model.law->eval(theta); }, 2048), rpm * kRadPerRpm);
    scene.mechanism.cam.rpm = rpm;
    SimulationResult r = simulate_scene(scene, "test");
    ASSERT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
    apply_steady_state(scene, build_model(scene, "test"), r);
    ASSERT_EQ(r.metrics_over, "periodic_orbit") << r.metrics_note;
    ASSERT_TRUE(r.metrics.train);
    const double peak = v[0].maxCoeff();
    EXPECT_NEAR(r.metrics.peak_contact_force, peak, 5e-3 * peak);
    EXPECT_NEAR(r.metrics.min_contact_force, v[0].minCoeff(), 5e-3 * peak);
    for (std::size_t k = 0; k < held.quantities.size(); ++k) {
      if (held.quantities[k].kind == HeldQuantity::Kind::link) {
        EXPECT_NEAR(r.metrics.train->min_link_force, v[k].minCoeff(), 5e-3 * peak);
      }
      if (held.quantities[k].kind == HeldQuantity::Kind::spring_end) {
        EXPECT_NEAR(r.metrics.train->peak_spring_force, v[k].maxCoeff(), 5e-3 * peak);
      }
    }
  }
}

}  // namespace
}  // namespace camdyn::optim
