// Every follower type (translating roller, flat, mushroom; oscillating roller,
// flat, mushroom) on a running cam, against the rigid model of
// rigid_follower.h computed independently of the library.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <string>

#include "common/constants.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "geometry/motion_law.h"
#include "rigid_follower.h"
#include "scenes.h"

namespace camdyn {
namespace {

using test::Rigid;

/// Records a measured number in the test's XML output (--gtest_output=xml).
void record(const std::string& key, double value) {
  std::ostringstream text;
  text << std::setprecision(4) << value;
  ::testing::Test::RecordProperty(key, text.str());
}

class FollowerType : public ::testing::TestWithParam<std::string> {};

TEST_P(FollowerType, LowSpeedFollowsTheLawWithTheRigidForce) {
  const SceneConfig scene = test::follower_scene(GetParam(), 100.0, ContactModel::lankarani_nikravesh);
  const SimulationResult r = simulate_scene(scene, "test");
  const Rigid rigid(scene);
  const double omega = 100.0 * kTwoPi / 60.0;
  EXPECT_EQ(r.metrics.separation_fraction, 0.0);
  double worst_force = 0.0, f_max = 0.0, worst_normal_error = 0.0;
  for (size_t i = 0; i < r.series.time.size(); ++i) {
    if (r.series.time[i] < r.evaluated_from) continue;
    const double theta = r.series.cam_angle_deg[i] * kTwoPi / 360.0;
    const double expected = rigid.force(theta, omega);
    ASSERT_GT(expected, 0.0);
    worst_force = std::max(worst_force, std::abs(r.series.contact_force[i] / expected - 1.0));
    f_max = std::max(f_max, expected);
    // Deviation from the law along the contact normal: |q − s| ∂g/∂q (translating: |y − s| cos φ ≤ |y − s|).
    const double deviation = std::abs(r.series.follower_position[i] - r.series.kinematic_position[i]);
    worst_normal_error = std::max(worst_normal_error, rigid.oscillating ? deviation * rigid.lever(theta) : deviation);
  }
  // Acceptance: the contact force within 0.5 % of the rigid-model force, and
  // the follower on the law within twice the static contact deflection.
  EXPECT_LT(worst_force, test::kRigidForceAcceptance);
  const double static_deflection = std::pow(f_max / *scene.mechanism.contact.stiffness, 1.0 / 1.5);
  record("worst_force_error", worst_force);
  record("worst_normal_deviation_m", worst_normal_error);
  record("static_deflection_m", static_deflection);
  EXPECT_LT(worst_normal_error, 2.0 * static_deflection);
  EXPECT_NEAR(r.metrics.peak_contact_force / f_max, 1.0, test::kRigidForceAcceptance);
}

TEST_P(FollowerType, JumpSpeedMatchesTheIndependentRigidModel) {
  const SceneConfig scene = test::follower_scene(GetParam(), 1000.0);
  const Model model = build_model(scene, "test");
  EXPECT_NEAR(jump_speed_rpm(model) / Rigid(scene).jump_rpm(), 1.0, test::kRigidJumpGrid);
}

TEST_P(FollowerType, NoSeparationJustBelowTheJumpSpeedSeparationJustAbove) {
  const double jump = Rigid(test::follower_scene(GetParam(), 1000.0)).jump_rpm();
  {
    const SimulationResult r =
        simulate_scene(test::follower_scene(GetParam(), 0.98 * jump, ContactModel::lankarani_nikravesh), "test");
    EXPECT_EQ(r.metrics.separation_fraction, 0.0);
    EXPECT_GT(r.metrics.min_contact_force, 0.0);
  }
  {
    const SimulationResult r =
        simulate_scene(test::follower_scene(GetParam(), 1.02 * jump, ContactModel::lankarani_nikravesh), "test");
    EXPECT_GT(r.metrics.separation_fraction, 0.0);
    EXPECT_EQ(r.metrics.min_contact_force, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(AllFollowers, FollowerType, ::testing::ValuesIn(test::follower_kinds()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(FlatFace, ContactPointTravelsAcrossTheFaceBySPrime) {
  // Physics identity of the translating flat-faced follower (ccw, on the law):
  // the contact point is s'(θ) from the follower axis.
  SceneConfig scene = test::follower_scene("translating_flat", 60.0, ContactModel::lankarani_nikravesh);
  scene.simulation.cycles = 2;
  const SimulationResult r = simulate_scene(scene, "test");
  const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test");
  double worst = 0.0, travel = 0.0;
  for (size_t i = 0; i < r.series.time.size(); ++i) {
    const double ds = law.eval(r.series.cam_angle_deg[i] * kTwoPi / 360.0).ds;
    worst = std::max(worst, std::abs(r.series.contact_offset[i] - ds));
    travel = std::max(travel, std::abs(ds));
  }
  EXPECT_GT(travel, 0.01);
  EXPECT_LT(worst, 1e-9);
  record("worst_travel_error_m", worst);
}

TEST(FlatFace, ContactPointTravelHoldsForBothTrackingModes) {
  for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
    SceneConfig scene = test::follower_scene("translating_flat", 60.0, ContactModel::lankarani_nikravesh);
    scene.mechanism.contact.tracking = tracking;
    scene.mechanism.cam.direction = RotationDirection::cw;  // mirror image: the contact point is at −s'
    scene.simulation.cycles = 2;
    const SimulationResult r = simulate_scene(scene, "test");
    const MotionLaw law = build_motion_law(scene.mechanism.cam.motion_law, "test");
    double worst = 0.0;
    for (size_t i = 0; i < r.series.time.size(); ++i)
      worst = std::max(worst,
                       std::abs(r.series.contact_offset[i] + law.eval(r.series.cam_angle_deg[i] * kTwoPi / 360.0).ds));
    EXPECT_LT(worst, 1e-9) << to_string(tracking);
    EXPECT_LT(r.metrics.energy_residual, 1e-6) << to_string(tracking);
  }
}

}  // namespace
}  // namespace camdyn
