// Shared by map_sensitivity_test.cc and map_sensitivity_slowtest.cc: the
// sensitivity Jacobian of a Poincaré map against a careful finite-difference
// reference of the map itself.
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
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "common/errors.h"
#include "dynamics/map_sensitivity.h"
#include "io/config.h"
#include "study/periodic_study.h"
#include "study_paths.h"

namespace camdyn::test {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// Tolerance levels (see the header comment).
constexpr double kJacobianAgreement = 1e-6;  // ‖J_sens − R‖_F / ‖R‖_F beyond the reference's own error
constexpr double kReferenceSpread = 1e-5;    // the most the reference's own error may be, relative
constexpr double kTightRtol = 1e-12;

// A study file as a periodic study with a tight integrator.
inline PeriodicStudy read_tight(const std::string& file, const std::function<void(Json&)>& edit = {}) {
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

inline MapAt map_at(const PeriodicStudy& study, int revolutions) {
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

// D(h): central differences of P^k in scaled coordinates.
inline MatrixXd central(const PoincareMap& map, const SectionPoint& p, int k, double h) {
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

inline MatrixXd richardson(const PoincareMap& map, const SectionPoint& p, int k, double h) {
  return (4.0 * central(map, p, k, h / 2) - central(map, p, k, h)) / 3.0;
}

// The scaled Jacobian D⁻¹ J D.
inline MatrixXd scaled(const PoincareMap& map, const MatrixXd& J) {
  const VectorXd s = to_vector(map.scales());
  return s.cwiseInverse().asDiagonal() * J * s.asDiagonal();
}

// The sensitivity Jacobian of P^k at the point against Richardson's
// reference at step h; `integrated`: the same map with integrated flights,
// a second reference (null where the flight has no closed form).
// `spread_limit`: the most the reference's own error may be, relative.
inline void expect_sensitivity_matches_reference(const MapAt& s, int k, double h, const MapAt* integrated = nullptr,
                                                 double spread_limit = kReferenceSpread) {
  Workspace ws = make_workspace(s.model);
  const MapJacobian sens = sensitivity_jacobian(*s.map, s.point, k, ws);
  ASSERT_TRUE(sens.ok) << sens.reason;
  const MatrixXd reference = richardson(*s.map, s.point, k, h);
  double spread = (reference - richardson(*s.map, s.point, k, 2 * h)).norm();
  if (integrated) spread = std::max(spread, (reference - richardson(*integrated->map, s.point, k, h)).norm());
  const double norm = reference.norm();
  EXPECT_LT(spread, spread_limit * norm) << "the reference itself is not converged";
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

}  // namespace camdyn::test
