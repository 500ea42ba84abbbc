// The plausibility checks of dynamics/plausibility.h against closed forms:
// the contact load of the rigid model, the penetration limit at which a
// stiffness can no longer carry the preload, and which warnings appear.
#include "dynamics/plausibility.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>

#include "common/errors.h"
#include "scenes.h"

namespace camdyn {
namespace {

/// The cycloidal test cam held still: the largest rigid-model load is on the
/// top dwell, k (h + x₀) = 5000 N/m · (0.02 m + 40 N / 5000 N/m) = 140 N,
/// with the follower moving along the normal there (∂g/∂q = 1).
constexpr double kTopDwellForce = 140.0;  // [N]
constexpr double kSamplingTolerance = 1e-9;

bool has_cause(const std::vector<PlausibilityWarning>& warnings, const std::string& cause, const std::string& field) {
  for (const PlausibilityWarning& w : warnings)
    if (w.cause == cause && w.field == field) return true;
  return false;
}

TEST(Plausibility, ContactLoadIsTheRigidModelsSpringLoadAndHertzPenetration) {
  const SceneConfig scene = test::cycloidal_cam_scene(0.0);
  const Model model = build_model(scene, "test");
  const ContactLoad load = contact_load(model);
  EXPECT_NEAR(load.static_force, kTopDwellForce, kSamplingTolerance * kTopDwellForce);
  EXPECT_NEAR(load.peak_force, kTopDwellForce, kSamplingTolerance * kTopDwellForce);  // ω = 0: the same
  const double delta = std::pow(kTopDwellForce / 1e10, 1.0 / 1.5);                    // δ = (F / K)^(1/n) [m]
  EXPECT_NEAR(load.peak_penetration, delta, kSamplingTolerance * delta);
  // Linearised contact k_c = n F / δ on the 0.3 kg follower.
  const double frequency = std::sqrt(1.5 * kTopDwellForce / delta / 0.3) / (2.0 * std::numbers::pi);
  EXPECT_NEAR(load.contact_frequency, frequency, kSamplingTolerance * frequency);
}

// Half the 10 mm roller radius is the penetration limit: K = F / (5 mm)^1.5.
TEST(Plausibility, StiffnessThatCannotCarryThePreloadIsRefusedNamingTheStiffness) {
  SceneConfig scene = test::cycloidal_cam_scene(0.0);
  const double limit_stiffness = kTopDwellForce / std::pow(0.005, 1.5);  // [N/m^1.5]
  scene.mechanism.contact.stiffness = 1.01 * limit_stiffness;
  EXPECT_NO_THROW(build_model(scene, "test"));
  scene.mechanism.contact.stiffness = 0.99 * limit_stiffness;
  try {
    build_model(scene, "test");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.contact.stiffness");
    EXPECT_NE(e.reason().find("cannot carry the preload"), std::string::npos) << e.reason();
  }
}

TEST(Plausibility, MicrometreRollerIsRefusedNamingTheRadius) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0);
  scene.mechanism.follower.shape.radius = 1e-6;
  try {
    build_model(scene, "test");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.shape.radius");
  }
}

TEST(Plausibility, RestitutionIgnoredByTheLawIsWarned) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0, ContactModel::hertz);
  scene.mechanism.contact.restitution = 0.5;
  EXPECT_TRUE(
      has_cause(input_warnings(scene, build_model(scene, "test")), "ignored_field", "mechanism.contact.restitution"));
  scene.mechanism.contact.model = ContactModel::lankarani_nikravesh;
  EXPECT_TRUE(input_warnings(scene, build_model(scene, "test")).empty());
}

TEST(Plausibility, StiffnessOutsideTheUsualRangeIsWarned) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0);
  scene.mechanism.contact.stiffness = 1e6;
  EXPECT_TRUE(
      has_cause(input_warnings(scene, build_model(scene, "test")), "contact_stiffness", "mechanism.contact.stiffness"));
}

/// The Richardson warning of a run whose error estimate differs by `position`
/// (in the follower coordinate), or null when there is none.
std::optional<PlausibilityWarning> error_estimate_warning(const SceneConfig& scene, double position) {
  const Model model = build_model(scene, "test");
  SimulationResult result;  // no impacts, no penetration, a closed energy balance: no other warning
  result.error.richardson = true;
  result.error.position = position;
  for (const PlausibilityWarning& w : result_warnings(scene, model, result))
    if (w.cause == "error_estimate") return w;
  return std::nullopt;
}

std::string percent_text(double share) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g %%", 100.0 * share);
  return buffer;
}

/// The test cams' lift: 12° of arm rotation, 20 mm of travel (scenes.h).
constexpr double kArmLift = 12.0 * std::numbers::pi / 180.0;  // [rad]
constexpr double kLift = 0.02;                                // [m]

// A user's arm: an error of 0.00638 rad was reported as a share of the lift
// in metres (12.2 %) and printed without its unit; it is 0.00638 rad against
// the arm's lift in rad.
TEST(Plausibility, ArmsErrorEstimateIsInRadAgainstItsLiftInRad) {
  const double error = 0.00638;  // [rad]
  const std::optional<PlausibilityWarning> w =
      error_estimate_warning(test::follower_scene("oscillating_roller", 1000.0), error);
  ASSERT_TRUE(w);
  EXPECT_EQ(w->field, "integrator.rtol");
  EXPECT_NE(w->message.find("0.00638 rad in position"), std::string::npos) << w->message;
  EXPECT_NE(w->message.find(percent_text(error / kArmLift) + " of the lift (0.209 rad)"), std::string::npos)
      << w->message;
  EXPECT_EQ(w->message.find(" m "), std::string::npos) << w->message;
  EXPECT_EQ(w->message.find(" m,"), std::string::npos) << w->message;
}

// 1e-3 rad is 0.48 % of the 12° lift: below the 1 % threshold, though it is
// 6 % of the lift's arc in metres (0.209 rad × 80 mm).
TEST(Plausibility, ArmsErrorBelowOnePercentOfItsLiftInRadIsNotWarned) {
  EXPECT_FALSE(error_estimate_warning(test::follower_scene("oscillating_roller", 1000.0), 1e-3));
  EXPECT_TRUE(error_estimate_warning(test::follower_scene("oscillating_roller", 1000.0), 0.011 * kArmLift));
}

TEST(Plausibility, TranslatingFollowersErrorEstimateIsInMetresAgainstItsLiftInMetres) {
  const double error = 1e-3;  // [m]
  const std::optional<PlausibilityWarning> w =
      error_estimate_warning(test::follower_scene("translating_roller", 1000.0), error);
  ASSERT_TRUE(w);
  EXPECT_NE(w->message.find("0.001 m in position, " + percent_text(error / kLift) + " of the lift (0.02 m)"),
            std::string::npos)
      << w->message;
  EXPECT_EQ(w->message.find("rad"), std::string::npos) << w->message;
  EXPECT_FALSE(error_estimate_warning(test::follower_scene("translating_roller", 1000.0), 0.009 * kLift));
}

// The tolerance warning gives the penetration of an arm in rad of its rotation.
TEST(Plausibility, ArmsUnresolvedContactIsGivenInRad) {
  SceneConfig scene = test::follower_scene("oscillating_roller", 1000.0);
  scene.integrator.rtol = 1e-3;
  scene.integrator.atol = 1e-3;
  const Model model = build_model(scene, "test");
  for (const PlausibilityWarning& w : input_warnings(scene, model))
    if (w.cause == "tolerance") {
      EXPECT_NE(w.message.find("rad of arm rotation"), std::string::npos) << w.message;
      EXPECT_NE(w.message.find("rad)"), std::string::npos) << w.message;
      return;
    }
  FAIL() << "no tolerance warning";
}

}  // namespace
}  // namespace camdyn
