// Every rigid figure of a follower train is the held train's (docs/model.md
// §12, "Rigid figures of a train"), never the follower alone: on
// studies/valvetrain/bucket_tappet.json (a bucket whose valve spring has
// 45 g of coil mass) and on it with the spring moved to a valve behind the
// bucket (the valve train), the rigid contact force, its Hertz
// pressure and `mechanism.cam.limits.max_contact_stress`, and the spring
// sizing, each against the held train computed here from held_train +
// held_train_values.
#include "dynamics/held_train_force.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/hertz_pressure.h"
#include "dynamics/contact_stress.h"
#include "dynamics/held_train.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/spring_sizing.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

const std::string kBucket = kStudies + "valvetrain/bucket_tappet.json";
constexpr double kBucketRpm = 1000.0;  // the speed

SceneConfig bucket(double rpm, std::vector<std::string> more = {}) {
  more.push_back("mechanism.cam.rpm=" + std::to_string(rpm));
  return load_scene(kBucket, more);
}

/// The valve train: the bucket (35 g, no spring of its own) drives a
/// 50 g valve whose spring has the 45 g of coil mass in 8 lumps.
SceneConfig bucket_and_valve(double rpm, std::vector<std::string> more = {}) {
  more.insert(more.begin(),
              {"mechanism.follower.mass=0.035", "mechanism.follower.spring={\"stiffness\": 0, \"preload\": 0}",
               "mechanism.train=[{\"name\": \"valve\", \"mass\": 0.05, \"link\": {\"ratio\": 1, \"stiffness\": "
               "2e8, \"damping\": 20}, \"spring\": {\"stiffness\": 35000, \"preload\": 250, \"mass\": 0.045, "
               "\"coils\": 8, \"damping_ratio\": 0.03}}]"});
  return bucket(rpm, more);
}

/// The held train's cam contact force [N] at the `angles` grid angles (a translating follower: lever 1).
Eigen::VectorXd held_contact(const Model& model, double omega, int angles) {
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, angles);
  return held_train_values(held_train(model), law, omega)[0];
}

/// Hertz line pressure of a flat face on the cam [Pa]: κ = 1 / (r_b + s + s''), steel on steel, 12 mm.
double flat_face_pressure(const Model& model, double force, double theta) {
  const LawSample s = model.law->eval(theta);
  const double e_star = 2.1e11 / (2.0 * (1.0 - 0.3 * 0.3));  // [Pa]
  const double kappa = 1.0 / (0.02 + s.s + s.d2s);           // [1/m]
  return hertz_line_pressure(force, 0.012, e_star, kappa);
}

TEST(RigidFiguresOfATrain, ForceAndTorqueAreTheHeldTrainsAtItsGridAngles) {
  const Model model = build_model(bucket(kBucketRpm), kBucket);
  ASSERT_TRUE(rigid_figures_held(model));
  const RigidContactForce force(model, model.omega);
  ASSERT_EQ(force.grid_angles(), RigidContactForce::kHeldAngles);
  const Eigen::VectorXd held = held_contact(model, model.omega, RigidContactForce::kHeldAngles);
  double held_peak = 0.0, alone_peak = 0.0;
  for (int i = 0; i < RigidContactForce::kHeldAngles; i += 3) {
    const double theta = kTwoPi * i / RigidContactForce::kHeldAngles;
    EXPECT_NEAR(force.normal(theta), held[i], 1e-9 * std::abs(held[i]) + 1e-9);
    EXPECT_NEAR(force.torque(theta), held[i] * model.law->eval(theta).ds, 1e-9 * std::abs(held[i]) + 1e-9);
    held_peak = std::max(held_peak, held[i]);
    alone_peak = std::max(alone_peak, rigid_normal_force(model, theta));  // the 90 g follower alone
  }
  // The valve spring (250 N installed, 35 N/mm over 9 mm) is in the held force, not in the follower's.
  EXPECT_GT(held_peak, 250.0 + 35000.0 * 0.008);
  EXPECT_LT(alone_peak, 0.2 * held_peak);
}

TEST(RigidFiguresOfATrain, PeakPressureIsTheHeldTrainsAndTheSceneLimitChecksIt) {
  const Model model = build_model(bucket_and_valve(kBucketRpm), kBucket);
  const LineContact contact = *line_contact(bucket_and_valve(kBucketRpm).mechanism.contact);
  const Eigen::VectorXd held = held_contact(model, model.omega, RigidContactForce::kHeldAngles);
  double held_peak = 0.0, alone_peak = 0.0;  // [Pa]
  for (int i = 0; i < RigidContactForce::kHeldAngles; ++i) {
    const double theta = kTwoPi * i / RigidContactForce::kHeldAngles;
    held_peak = std::max(held_peak, flat_face_pressure(model, held[i], theta));
    alone_peak = std::max(alone_peak, flat_face_pressure(model, rigid_normal_force(model, theta), theta));
  }
  EXPECT_NEAR(peak_rigid_contact_pressure(model, contact, model.omega).pressure / held_peak, 1.0, 1e-9);
  ASSERT_LT(alone_peak, 0.5 * held_peak);
  // A limit between the follower alone's pressure and the held train's fails, as it does for one follower
  // (the 300 MPa at 1000 rpm, which the follower alone passed).
  const double limit = 0.5 * (alone_peak + held_peak);
  try {
    build_model(bucket_and_valve(kBucketRpm, {"mechanism.cam.limits.max_contact_stress=" + std::to_string(limit)}),
                kBucket);
    FAIL() << "no InputError at a limit of " << limit << " Pa below the held train's " << held_peak << " Pa";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam.limits.max_contact_stress");
    EXPECT_NE(std::string(e.what()).find("held train's rigid-model Hertz contact pressure reaches"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(build_model(
      bucket_and_valve(kBucketRpm, {"mechanism.cam.limits.max_contact_stress=" + std::to_string(1.001 * held_peak)}),
      kBucket));
}

// With a Kelvin–Voigt contact of exponent 1 the held train's linearisation
// does not depend on the preload, so the sized preload is exact: with it the
// held contact force's minimum over the revolution is 0 at the speed it was
// set at and nowhere below 0 up to the top speed.
TEST(RigidFiguresOfATrain, SpringSizingIsTheHeldTrainsPreload) {
  const std::vector<std::string> kv = {"mechanism.contact.model=\"kelvin_voigt\"", "mechanism.contact.damping=2000"};
  const double rpm = 3000.0, omega_max = rpm * kTwoPi / 60.0;
  const Model model = build_model(bucket(rpm, kv), kBucket);
  const HeldSpringSizing s = size_held_spring(model, 0.0, omega_max);
  ASSERT_TRUE(s.available) << s.reason;
  EXPECT_EQ(s.spring, "mechanism.follower.spring");
  EXPECT_EQ(s.unit, "N");
  EXPECT_EQ(s.binding, "cam contact");
  ASSERT_GT(s.required_preload, 0.0);
  std::vector<std::string> sized = kv;
  sized.push_back("mechanism.follower.spring.preload=" + std::to_string(s.required_preload));
  const Model at = build_model(bucket(rpm, sized), kBucket);
  // The preload passes through text to 6 decimals: 1e-6 N, moving the force by about as much.
  const double tol = 1e-6 * s.required_preload + 1e-5;  // [N]
  EXPECT_NEAR(held_contact(at, s.preload_at_rpm * kTwoPi / 60.0, 1024).minCoeff(), 0.0, tol);
  for (int k = 0; k <= 20; ++k) EXPECT_GE(held_contact(at, omega_max * k / 20.0, 1024).minCoeff(), -tol) << k;
}

// Behind the bucket a valve with its own spring: the bucket's spring pulls it
// off the link, so the valve's is sized (its link and the cam contact both
// rise with it); without any spring there is nothing to size, and why.
TEST(RigidFiguresOfATrain, SpringSizingSizesTheSpringThatLoadsEveryHeldForce) {
  const std::string valve =
      "mechanism.train=[{\"name\": \"valve\", \"mass\": 0.05, \"link\": {\"ratio\": 1, \"stiffness\": 1e8}, "
      "\"spring\": {\"stiffness\": 35000, \"preload\": 250}}]";
  const HeldSpringSizing both =
      size_held_spring(build_model(bucket(kBucketRpm, {valve}), kBucket), 0.0, kBucketRpm * kTwoPi / 60.0);
  ASSERT_TRUE(both.available) << both.reason;
  EXPECT_EQ(both.spring, "mechanism.train[0].spring");
  EXPECT_EQ(both.body, 1);
  const HeldSpringSizing none = size_held_spring(
      build_model(bucket(kBucketRpm, {"mechanism.follower.spring={\"stiffness\": 0, \"preload\": 0}",
                                      "mechanism.train=[{\"name\": \"valve\", \"mass\": 0.05, \"link\": "
                                      "{\"ratio\": 1, \"stiffness\": 1e8}}]"}),
                  kBucket),
      0.0, kBucketRpm * kTwoPi / 60.0);
  EXPECT_FALSE(none.available);
  EXPECT_EQ(none.reason, "the scene has no spring to size");
}

}  // namespace
}  // namespace camdyn
