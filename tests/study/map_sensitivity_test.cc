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
// Tolerance. The reference is Richardson's extrapolation of central
// differences of the map itself, R(h) = (4 D(h/2) − D(h)) / 3 with D(h) =
// (P(x + h s e_j) − P(x − h s e_j)) / 2h, in coordinates scaled by the map's
// scales s (the scaled Jacobian D⁻¹ J D is dimensionless). Its error is the
// truncation O(h⁴) plus the integration error ε of P divided by h, and ε is
// not small: a stiff contact phase amplifies the integrator's local error,
// and at rtol = 1e-10 two integrations of the bouncing ball's map (or its
// sensitivities) differ by about 1e-5 of ‖J‖. Hence rtol = 1e-12 here (the
// bouncing ball's R(h) then agrees with itself over h = 3e-3 … 1e-2 to
// 3e-7 ‖J‖). The reference's own error u is measured, not assumed: the spread
// of R(h) against R(2h), and, where the flight has a closed form, against the
// same extrapolation on the map with integrated flights (a different
// integration of the same map). The test asks
//     ‖J_sens − R(h)‖_F ≤ 1e-6 ‖R(h)‖_F + u,   with u ≤ 1e-5 ‖R(h)‖_F,
// the second so that the first stays a real check. A sensitivity Jacobian
// without the saltation or the v₀ row is off by far more (percent).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <complex>
#include <string>
#include <vector>

#include "common/errors.h"
#include "dynamics/map_sensitivity.h"
#include "io/config.h"
#include "study/periodic_orbit.h"
#include "study/periodic_study.h"

namespace camdyn {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

const std::string kSource = std::string(CAMDYN_SOURCE_DIR);

// Tolerance levels (see the header comment).
constexpr double kJacobianAgreement = 1e-6;  // ‖J_sens − R‖_F / ‖R‖_F beyond the reference's own error
constexpr double kReferenceSpread = 1e-5;    // the most the reference's own error may be, relative
constexpr double kTightRtol = 1e-12;

// A study file as a periodic study with a tight integrator.
PeriodicStudy read_tight(const std::string& file, const std::function<void(Json&)>& edit = {}) {
  Json doc = load_config_json(file);
  doc["study"] = "periodic";
  doc["integrator"]["rtol"] = kTightRtol;
  doc["integrator"]["atol"] = 1e-16;
  doc.erase("periodic");
  if (edit) edit(doc);
  StudyContext ctx;
  ctx.config_file = file;
  ctx.source = config_source(file);
  return read_periodic_study(doc, ctx);
}

// A map and a section point after `revolutions` of transient from the scene's own start.
struct MapAt {
  Model model;
  std::unique_ptr<PoincareMap> map;
  SectionPoint point;
};

MapAt map_at(const PeriodicStudy& study, int revolutions) {
  MapAt s{build_model(study.geometry, study.scene, "test"), nullptr, {}};
  s.map = std::make_unique<PoincareMap>(study.scene, s.model, "test");
  Workspace ws = make_workspace(s.model);
  SimulationOptions run;
  run.record_series = false;
  const SimulationResult transient = simulate(s.map->scene_for(revolutions), s.model, ws, run);
  throw_if_failed(transient);
  s.point = s.map->point(transient);
  return s;
}

VectorXd to_vector(const std::vector<double>& x) { return Eigen::Map<const VectorXd>(x.data(), std::ssize(x)); }

// D(h): central differences of P^k in scaled coordinates.
MatrixXd central(const PoincareMap& map, const SectionPoint& p, int k, double h) {
  const int n = map.dimension();
  const VectorXd scales = to_vector(map.scales());
  Workspace ws = make_workspace(map.model());
  MatrixXd D(n, n);
  for (int j = 0; j < n; ++j) {
    VectorXd end[2];
    for (int side = 0; side < 2; ++side) {
      SectionPoint q = p;
      q.x[static_cast<std::size_t>(j)] += (side == 0 ? h : -h) * scales[j];
      const MapResult r = map.apply(q, k, ws);
      if (!r.ok) throw NumericalError(r.message);
      end[side] = to_vector(r.end.x).cwiseQuotient(scales);
    }
    D.col(j) = (end[0] - end[1]) / (2.0 * h);
  }
  return D;
}

MatrixXd richardson(const PoincareMap& map, const SectionPoint& p, int k, double h) {
  return (4.0 * central(map, p, k, h / 2) - central(map, p, k, h)) / 3.0;
}

// The scaled Jacobian D⁻¹ J D.
MatrixXd scaled(const PoincareMap& map, const MatrixXd& J) {
  const VectorXd s = to_vector(map.scales());
  return s.cwiseInverse().asDiagonal() * J * s.asDiagonal();
}

// The sensitivity Jacobian of P^k at the point against Richardson's
// reference at step h; `integrated`: the same map with integrated flights,
// a second reference (null where the flight has no closed form).
void expect_sensitivity_matches_reference(const MapAt& s, int k, double h, const MapAt* integrated = nullptr) {
  Workspace ws = make_workspace(s.model);
  const MapJacobian sens = sensitivity_jacobian(*s.map, s.point, k, ws);
  ASSERT_TRUE(sens.ok) << sens.reason;
  const MatrixXd reference = richardson(*s.map, s.point, k, h);
  double spread = (reference - richardson(*s.map, s.point, k, 2 * h)).norm();
  if (integrated) spread = std::max(spread, (reference - richardson(*integrated->map, s.point, k, h)).norm());
  const double norm = reference.norm();
  EXPECT_LT(spread, kReferenceSpread * norm) << "the reference itself is not converged";
  const MatrixXd J = scaled(*s.map, sens.jacobian);
  EXPECT_LT((J - reference).norm(), kJacobianAgreement * norm + spread) << "sensitivity:\n"
                                                                        << J << "\nreference:\n"
                                                                        << reference;
  // The sensitivity run is the map's run: the same end and impacts.
  const MapResult plain = s.map->apply(s.point, k, ws);
  ASSERT_TRUE(plain.ok);
  EXPECT_EQ(sens.impacts, plain.impacts);
  EXPECT_LT((to_vector(sens.end.x) - to_vector(plain.end.x)).cwiseQuotient(to_vector(s.map->scales())).norm(), 1e-6);
}

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
  const double distance =
      (to_vector(sens.orbit->fixed_point.x) - to_vector(fd.orbit->fixed_point.x)).cwiseQuotient(scales).cwiseAbs().maxCoeff();
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
  const PeriodicAnalysis a = find_periodic_orbit(*s.map, s.point, options);
  EXPECT_EQ(a.sensitivity_jacobians, 0);
  EXPECT_GT(a.finite_difference_jacobians, 0);
  EXPECT_NE(a.jacobian_fallback.find("friction"), std::string::npos) << a.jacobian_fallback;
  options.jacobian = JacobianMethod::sensitivity;
  EXPECT_THROW(find_periodic_orbit(*s.map, s.point, options), NumericalError);
}

}  // namespace
}  // namespace camdyn
