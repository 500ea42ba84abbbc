// The Poincaré map's Jacobian by forward sensitivities
// (dynamics/map_sensitivity.h) against a careful finite-difference Jacobian of
// the map itself, and the shooting with it against the shooting with central
// differences:
// * Holmes' bouncing ball (impacts, closed-form flights in the map's run);
// * the long-flight cam (a roller follower thrown off the cam that lands on it twice a revolution);
// * the fallbacks: a model it does not cover (friction) falls back to finite
//   differences and says why; forcing "sensitivity" there stops the study.
// The 8-coil valve train is in map_sensitivity_slowtest.cc.
//
// Tolerances: tests/study/map_jacobian_reference.h.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <complex>
#include <string>
#include <vector>

#include "common/errors.h"
#include "map_jacobian_reference.h"
#include "study/periodic_orbit.h"

namespace camdyn {
namespace {

using namespace test;  // NOLINT(google-build-using-namespace): the shared reference

TEST(MapSensitivity, BouncingBallJacobianMatchesRichardsonDifferences) {
  const std::string file = kSource + "/studies/periodic/bouncing_ball.json";
  const MapAt s = map_at(read_tight(file), 4);
  const MapAt integrated = map_at(read_tight(file, [](Json& doc) { doc["integrator"]["flight"] = "integrated"; }), 4);
  expect_sensitivity_matches_reference(s, 1, 1e-2, &integrated);
  expect_sensitivity_matches_reference(s, 2, 1e-2, &integrated);
}

// The long-flight cam (studies/peers/long_flight.json): a roller thrown off
// the rise, landing and bouncing once more each revolution, a map that
// stretches by ‖J‖ ≈ 27 (and bends: h = 5e-6 is needed for the extrapolation).
TEST(MapSensitivity, SeparatingRollerCamJacobianMatchesRichardsonDifferences) {
  const std::string file = kSource + "/studies/peers/long_flight.json";
  const MapAt s = map_at(read_tight(file), 2);
  const MapAt integrated = map_at(read_tight(file, [](Json& doc) { doc["integrator"]["flight"] = "integrated"; }), 2);
  Workspace ws = make_workspace(s.model);
  ASSERT_EQ(s.map->apply(s.point, 1, ws).impacts, 2) << "the follower is meant to leave the cam and land on it";
  expect_sensitivity_matches_reference(s, 1, 5e-6, &integrated);
}

// Shooting with the sensitivity Jacobian finds the orbit and the multipliers
// that shooting with central differences finds, and says how it took them.
TEST(MapSensitivity, ShootingWithSensitivitiesFindsTheFiniteDifferenceOrbit) {
  const PeriodicStudy study = read_tight(kSource + "/studies/periodic/bouncing_ball.json");
  const MapAt s = map_at(study, 4);
  PeriodicOptions options = study.config.options;
  options.lyapunov_revolutions = 0;
  options.jacobian = JacobianMethod::sensitivity;
  const PeriodicAnalysis sens = find_periodic_orbit(*s.map, s.point, options);
  options.jacobian = JacobianMethod::finite_difference;
  const PeriodicAnalysis fd = find_periodic_orbit(*s.map, s.point, options);
  ASSERT_TRUE(sens.orbit && fd.orbit);
  EXPECT_EQ(sens.orbit->jacobian_method, JacobianMethod::sensitivity);
  EXPECT_EQ(fd.orbit->jacobian_method, JacobianMethod::finite_difference);
  EXPECT_EQ(sens.finite_difference_jacobians, 0);
  EXPECT_GT(sens.sensitivity_jacobians, 0);
  EXPECT_EQ(fd.sensitivity_jacobians, 0);
  EXPECT_EQ(sens.orbit->period, fd.orbit->period);
  // Both converged to the shooting tolerance (scaled residual): the fixed points agree to a few times it.
  const VectorXd scales = to_vector(s.map->scales());
  const double distance = (to_vector(sens.orbit->fixed_point.x) - to_vector(fd.orbit->fixed_point.x))
                              .cwiseQuotient(scales)
                              .cwiseAbs()
                              .maxCoeff();
  EXPECT_LT(distance, 10 * options.tolerance);
  // The central differences' own error at their step 10 √rtol = 1e-4 is about
  // ε/h ≈ 1e-5 (header comment): the multipliers agree to that.
  ASSERT_EQ(sens.orbit->multipliers.size(), fd.orbit->multipliers.size());
  for (std::size_t i = 0; i < sens.orbit->multipliers.size(); ++i)
    EXPECT_NEAR(std::abs(sens.orbit->multipliers[i] - fd.orbit->multipliers[i]), 0.0, 1e-4) << i;
  // With fewer map runs: one sensitivity run per Jacobian instead of 2n.
  EXPECT_LT(sens.map_evaluations, fd.map_evaluations);
}

// Friction can stick: the sensitivity run does not cover it. "auto" falls
// back to central differences and says why; "sensitivity" stops instead.
// "auto" tries sensitivities only on a long map (sensitivity_min_coordinates).
TEST(MapSensitivity, FrictionFallsBackToFiniteDifferencesAndSaysWhy) {
  const PeriodicStudy study = read_tight(kSource + "/studies/periodic/bouncing_ball.json", [](Json& doc) {
    doc["mechanism"]["contact"]["friction"]["mu"] = 0.05;
    doc["integrator"]["rtol"] = 1e-10;
    doc["integrator"]["atol"] = 1e-13;
  });
  const MapAt s = map_at(study, 4);
  Workspace ws = make_workspace(s.model);
  const MapJacobian sens = sensitivity_jacobian(*s.map, s.point, 1, ws);
  EXPECT_FALSE(sens.ok);
  EXPECT_NE(sens.reason.find("friction"), std::string::npos) << sens.reason;
  PeriodicOptions options = study.config.options;
  options.lyapunov_revolutions = 0;
  options.max_period = 1;
  options.max_newton_iterations = 1;
  // "auto" on this 2-coordinate map takes central differences without trying sensitivities.
  const PeriodicAnalysis short_map = find_periodic_orbit(*s.map, s.point, options);
  EXPECT_EQ(short_map.sensitivity_jacobians, 0);
  EXPECT_GT(short_map.finite_difference_jacobians, 0);
  EXPECT_TRUE(short_map.jacobian_fallback.empty()) << short_map.jacobian_fallback;
  // As if the map were long enough for sensitivities: tried, not trusted, and why.
  options.sensitivity_min_coordinates = 1;
  const PeriodicAnalysis a = find_periodic_orbit(*s.map, s.point, options);
  EXPECT_EQ(a.sensitivity_jacobians, 0);
  EXPECT_GT(a.finite_difference_jacobians, 0);
  EXPECT_NE(a.jacobian_fallback.find("friction"), std::string::npos) << a.jacobian_fallback;
  options.jacobian = JacobianMethod::sensitivity;
  EXPECT_THROW(find_periodic_orbit(*s.map, s.point, options), NumericalError);
}

}  // namespace
}  // namespace camdyn
