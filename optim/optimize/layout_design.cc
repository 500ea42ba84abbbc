#include "optim/optimize/layout_design.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <nlopt.hpp>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/cam_outline.h"
#include "dynamics/model.h"
#include "optim/halton_sequence.h"
#include "optim/search.h"

namespace camdyn::optim {

namespace {

/// One variable: its dotted path, its range and where it goes in a scene.
struct LayoutVariable {
  std::string name;
  double lower = 0.0, upper = 0.0;
  double* (*field)(SceneConfig&) = nullptr;
};

std::vector<LayoutVariable> variables_of(const LayoutConfig& l) {
  std::vector<LayoutVariable> v;
  auto add = [&](const std::optional<std::vector<double>>& range, const char* name, double* (*field)(SceneConfig&)) {
    if (range) v.push_back({name, (*range)[0], (*range)[1], field});
  };
  add(l.base_radius, "mechanism.cam.base_radius", [](SceneConfig& s) { return &s.mechanism.cam.base_radius; });
  add(l.offset, "mechanism.follower.offset", [](SceneConfig& s) { return &s.mechanism.follower.offset; });
  add(l.pivot_x, "mechanism.follower.pivot[0]", [](SceneConfig& s) { return &s.mechanism.follower.pivot[0]; });
  add(l.pivot_y, "mechanism.follower.pivot[1]", [](SceneConfig& s) { return &s.mechanism.follower.pivot[1]; });
  add(l.arm_length, "mechanism.follower.arm_length", [](SceneConfig& s) { return &s.mechanism.follower.arm_length; });
  return v;
}

SceneConfig with_values(SceneConfig s, const std::vector<LayoutVariable>& vars, const std::vector<double>& x) {
  for (std::size_t i = 0; i < vars.size(); ++i) *vars[i].field(s) = x[i];
  return s;
}

/// The cam's largest contour radius [m] and its figures at one layout.
LayoutPoint evaluate(const SceneConfig& scene, const std::vector<double>& x, const LayoutLimits& limits,
                     const std::string& file) {
  LayoutPoint p;
  p.values = x;
  try {
    const Model model = build_model(scene, file);
    const CamOutline outline = cam_outline(model, 720);
    for (std::size_t k = 0; k < outline.u.size(); ++k)
      p.cam_size = std::max(p.cam_size, std::hypot(outline.contour_x[k], outline.contour_y[k]));
    p.report = model.geometry;
    p.buildable = std::isfinite(p.cam_size);
  } catch (const InputError& e) {
    p.error = e.reason();
    return p;
  }
  if (limits.max_pressure_angle_deg)
    p.violation += std::max(0.0, p.report.max_pressure_angle_deg / *limits.max_pressure_angle_deg - 1.0);
  if (limits.min_radius_of_curvature)
    p.violation += std::max(0.0, 1.0 - p.report.min_radius_of_curvature / *limits.min_radius_of_curvature);
  return p;
}

/// Feasible first, then the smaller cam; among infeasible ones the smaller violation.
bool better_layout(const LayoutPoint& a, const LayoutPoint& b) {
  if (a.feasible() != b.feasible()) return a.feasible();
  if (a.feasible()) return a.cam_size < b.cam_size;
  if (a.buildable != b.buildable) return a.buildable;
  return a.violation < b.violation;
}

/// COBYLA's view: the cam size, with a penalty where the cam cannot be made;
/// the limits as one inequality constraint.
struct LayoutSearch {
  const SceneConfig& baseline;
  const std::vector<LayoutVariable>& vars;
  const LayoutLimits& limits;
  const std::string& file;
  LayoutPoint best;
  long evaluations = 0;

  const LayoutPoint& at(const std::vector<double>& x) {
    // The study's wall time caps the search (common/study_budget.h). Inside
    // NLopt only its own exceptions pass through: refine() says why it stopped.
    if (study_budget_exhausted()) {
      if (in_nlopt) throw nlopt::forced_stop();
      throw NumericalError(budget_text());
    }
    last = evaluate(with_values(baseline, vars, x), x, limits, file);
    ++evaluations;
    if (better_layout(last, best)) best = last;
    return last;
  }
  LayoutPoint last;
  bool in_nlopt = false;  ///< within refine()'s NLopt call

  std::string budget_text() const {
    return study_budget_text() + " after " + std::to_string(evaluations) + " evaluations of the layout search";
  }
};

double objective(unsigned n, const double* x, double* grad, void* data) {
  if (grad) throw std::invalid_argument("the layout search is derivative-free");
  auto& s = *static_cast<LayoutSearch*>(data);
  const LayoutPoint& p = s.at(std::vector<double>(x, x + n));
  return p.buildable ? p.cam_size : 1e3;  // [m]: far above any cam
}

double limits_constraint(unsigned n, const double* x, double* grad, void* data) {
  if (grad) throw std::invalid_argument("the layout search is derivative-free");
  auto& s = *static_cast<LayoutSearch*>(data);
  const std::vector<double> v(x, x + n);
  const LayoutPoint& p = s.last.values == v ? s.last : s.at(v);
  return p.buildable ? p.violation : 1.0;
}

/// COBYLA from x within the ranges; the best point goes into `search`.
void refine(LayoutSearch& search, const std::vector<LayoutVariable>& vars, std::vector<double> x) {
  const std::size_t n = vars.size();
  nlopt::opt opt(nlopt::LN_COBYLA, static_cast<unsigned>(n));
  std::vector<double> lo(n), hi(n);
  for (std::size_t i = 0; i < n; ++i) {
    lo[i] = vars[i].lower;
    hi[i] = vars[i].upper;
    x[i] = std::clamp(x[i], lo[i], hi[i]);
  }
  opt.set_lower_bounds(lo);
  opt.set_upper_bounds(hi);
  opt.set_min_objective(objective, &search);
  opt.add_inequality_constraint(limits_constraint, &search, 0.0);
  opt.set_xtol_rel(1e-6);
  opt.set_maxeval(200);
  double f = 0.0;
  search.in_nlopt = true;
  try {
    const nlopt::result status = opt.optimize(x, f);
    search.in_nlopt = false;
    if (status < 0) throw NumericalError("layout search: NLopt " + nlopt_result_name(status));
  } catch (const nlopt::forced_stop&) {
    throw NumericalError(search.budget_text());
  } catch (const nlopt::roundoff_limited&) {
    // The best point found is kept.
  } catch (const std::invalid_argument& e) {
    throw NumericalError(std::string("layout search: NLopt refused the problem: ") + e.what());
  }
  search.in_nlopt = false;
}

}  // namespace

void check_layout(const SceneConfig& scene, const LayoutConfig& layout, const std::string& file) {
  const bool oscillating = scene.mechanism.follower.motion == FollowerMotion::oscillating;
  auto check = [&](const std::optional<std::vector<double>>& range, const char* key, bool applies, bool positive) {
    if (!range) return;
    const std::string at = std::string("design.layout.") + key;
    if (!applies)
      throw InputError(file, at,
                       oscillating ? "a translating follower's field: this follower oscillates"
                                   : "an oscillating follower's field: this follower translates");
    if (range->size() != 2 || !((*range)[0] < (*range)[1]))
      throw InputError(file, at, "expected [lower, upper] with lower < upper");
    if (positive && !((*range)[0] > 0.0)) throw InputError(file, at, "the lower bound must be > 0");
  };
  check(layout.base_radius, "base_radius", true, true);
  check(layout.offset, "offset", !oscillating, false);
  check(layout.pivot_x, "pivot_x", oscillating, false);
  check(layout.pivot_y, "pivot_y", oscillating, false);
  check(layout.arm_length, "arm_length", oscillating, true);
  if (variables_of(layout).empty())
    throw InputError(file, "design.layout",
                     "give at least one range (base_radius, offset, pivot_x, pivot_y, arm_length)");
}

LayoutResult design_layout(const SceneConfig& baseline, const LayoutConfig& layout, const LayoutLimits& limits,
                           const std::string& file) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<LayoutVariable> vars = variables_of(layout);
  const std::size_t n = vars.size();
  LayoutResult r;
  for (const LayoutVariable& v : vars) r.names.push_back(v.name);
  std::vector<double> x0(n);
  SceneConfig probe = baseline;
  for (std::size_t i = 0; i < n; ++i) x0[i] = *vars[i].field(probe);
  LayoutSearch search{baseline, vars, limits, file, {}, 0, {}, false};
  r.baseline = search.at(x0);
  search.best = r.baseline;
  // A space-filling design over the ranges finds the feasible region ...
  const int samples = 60 * static_cast<int>(n);
  std::vector<LayoutPoint> sampled;
  for (int k = 1; k <= samples; ++k) {
    std::vector<double> x(n);
    for (std::size_t i = 0; i < n; ++i)
      x[i] = vars[i].lower + halton(k, kHaltonBases[i]) * (vars[i].upper - vars[i].lower);
    sampled.push_back(search.at(x));
  }
  // ... and COBYLA shrinks the cam from the best few points found (the
  // problem is not convex: each start may end in a different local minimum).
  std::sort(sampled.begin(), sampled.end(), better_layout);
  constexpr std::size_t kStarts = 4;
  for (std::size_t s = 0; s < std::min(kStarts, sampled.size()); ++s) refine(search, vars, sampled[s].values);
  refine(search, vars, r.baseline.values);
  r.best = search.best;
  r.scene = with_values(baseline, vars, r.best.values);
  r.evaluations = search.evaluations;
  r.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace camdyn::optim
