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

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "study/steady_state.h"
#include "tests/dynamics/linear_train_case.h"

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

namespace camdyn::optim {
namespace {

OptimizeStudy train_study(const std::vector<std::string>& overrides = {}) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_train.json";
  return read_optimize_study(load_config_json(file, overrides),
                             ConfigSource{file, CAMDYN_SOURCE_DIR "/studies/valvetrain"});
}

// The certificate on a train: with P_min = 0 the baseline's figure is the
// scene's jump_speed_rpm (one definition, physics §8); the family and the
// rich spline are at least the baseline's (it is in neither family exactly,
// but both can copy it closely), the 16-point bound at least near the
// 8-point one, and the rigid design's own held-train figure is what the stage
// says it is.
TEST(TrainCertificate, FiguresOfTheTrainStudy) {
  const OptimizeStudy study = train_study({"constraints.min_contact_force=null", "constraints.no_separation=false"});
  const DesignSpace space(study.baseline, study.config.design, "optimize_train.json");
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, "optimize_train.json");
  const Certificate& c = r.certificate;
  ASSERT_TRUE(c.available) << c.reason;
  EXPECT_EQ(c.model, "held train");
  EXPECT_EQ(c.min_contact_force, 0.0);
  const Model model = build_model(study.baseline, "optimize_train.json");
  EXPECT_NEAR(c.baseline_rpm, model.train_jump_speed_rpm, 1e-4 * model.train_jump_speed_rpm);
  EXPECT_GT(c.family_rpm, c.baseline_rpm);
  EXPECT_GE(c.any_law_rpm, 0.99 * c.family_rpm);
  EXPECT_GE(c.any_law_rpm, 0.99 * c.any_law_coarse_rpm);
  EXPECT_LE(c.train_truncation, 1e-3);
  ASSERT_TRUE(r.design.have);
  // The design checked on a 4096-angle grid: jump-free at every operating speed, as the programme said.
  for (const double m : r.design.verified_margin) EXPECT_GE(m, -1e-3 * 300.0);
  EXPECT_GE(r.design.jump_free_rpm, 0.999 * 6000.0);
}

}  // namespace
}  // namespace camdyn::optim

namespace camdyn::optim {
namespace {

/// The seating velocity of `scene` at its steady state [m/s].
double seating_velocity(SceneConfig scene, double rpm) {
  scene.mechanism.cam.rpm = rpm;
  SimulationResult r = simulate_scene(scene, "test");
  EXPECT_EQ(r.solver.termination, Termination::converged) << r.solver.message;
  apply_steady_state(scene, build_model(scene, "test"), r);
  EXPECT_TRUE(r.metrics.train);
  EXPECT_GT(r.metrics.train->seat_impacts, 0);
  return r.metrics.train ? r.metrics.train->max_seating_velocity : 0.0;
}

// Acceptance: a closing flank designed on the held train with
// max_seating_velocity 0.3 m/s seats at or below it in the full nonlinear
// simulation (lash take-up, the seat's contact, the one-sided link), within
// the model gap of docs/optimize.md "Trains" (the held model stops at the
// seat; 10 % is allowed for the seat's compliance and the link's lash);
// the baseline's cycloidal return seats well above it.
TEST(TrainSeating, DesignedClosingFlankSeatsAtTheLimit) {
  const std::string file = std::string(CAMDYN_TEST_DATA_DIR) + "/optimize/seated_valve.json";
  const OptimizeStudy study =
      read_optimize_study(load_config_json(file), ConfigSource{file, CAMDYN_TEST_DATA_DIR "/optimize"});
  const DesignSpace space(study.baseline, study.config.design, file);
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, file);
  ASSERT_TRUE(r.design.have);
  const double limit = *study.config.constraints.max_seating_velocity;
  const double baseline = seating_velocity(study.baseline, 3000.0);
  const double designed = seating_velocity(space.scene(r.design.x), 3000.0);
  RecordProperty("baseline_seating_velocity", std::to_string(baseline));
  RecordProperty("designed_seating_velocity", std::to_string(designed));
  EXPECT_GT(baseline, 1.3 * limit);
  EXPECT_LE(designed, 1.1 * limit);
}

}  // namespace
}  // namespace camdyn::optim
