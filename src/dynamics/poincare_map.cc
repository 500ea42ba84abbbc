#include "dynamics/poincare_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "common/constants.h"
#include "common/errors.h"

namespace camdyn {

namespace {

// The range of the law's lift over a revolution [m | rad], never below a
// thousandth of the base radius (so a cam with no lift still has a scale).
double lift_range(const Model& model) {
  double lo = model.law->eval(0.0).s, hi = lo;
  constexpr int kSamples = 720;
  for (int i = 1; i < kSamples; ++i) {
    const double s = model.law->eval(kTwoPi * i / kSamples).s;
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  const double floor = model.follower.oscillating() ? 1e-3 : 1e-3 * model.follower.base_radius;
  return std::max(hi - lo, floor);
}

}  // namespace

PoincareMap::PoincareMap(const SceneConfig& scene, const Model& model, const std::string& file)
    : scene_(scene), model_(model) {
  if (!(model.omega > 0.0))
    throw InputError(file, "mechanism.cam.rpm", "a periodic orbit needs a turning cam (rpm > 0)");
  if (model.drive.torque_motor())
    throw InputError(file, "mechanism.cam.drive.motor.type",
                     "a periodic orbit needs the drive to set the speed (a constant-speed motor); a torque-speed "
                     "motor finds its own speed");
  period_ = kTwoPi / model.omega;
  angle_per_revolution_ = model.theta(period_) - model.theta(0.0);
  const StateLayout& l = model.layout;
  const double lift = lift_range(model);
  coordinates_ = {StateLayout::kQ, StateLayout::kQDot};
  scales_ = {lift, model.omega * lift};
  if (l.spin) {
    coordinates_.push_back(*l.spin);
    scales_.push_back(model.omega * std::max(1.0, model.follower.base_radius / model.follower.radius));
  }
  if (l.cam_angle) {
    coordinates_.push_back(*l.cam_angle);
    scales_.push_back(1.0);  // [rad]
    coordinates_.push_back(*l.cam_speed);
    scales_.push_back(model.omega);
  }
  // The follower train's bodies and spring lumps (docs/model.md §12), on the follower's scales.
  for (std::size_t c = 1; c < model.train.coordinates.size(); ++c) {
    coordinates_.push_back(model.train.coordinates[c].position);
    scales_.push_back(lift);
    coordinates_.push_back(model.train.coordinates[c].velocity);
    scales_.push_back(model.omega * lift);
  }
}

std::vector<std::string> PoincareMap::coordinate_names() const {
  std::vector<std::string> names;
  for (int i : coordinates_) names.push_back(model_.layout.names[static_cast<std::size_t>(i)]);
  return names;
}

SectionPoint PoincareMap::point(const std::vector<double>& state, double approach_speed, double motor_phase,
                                int revolutions) const {
  SectionPoint p;
  p.approach_speed = approach_speed;
  p.motor_phase = motor_phase;
  for (int i : coordinates_) {
    double v = state[static_cast<std::size_t>(i)];
    if (model_.layout.cam_angle && i == *model_.layout.cam_angle)
      v -= model_.theta0 + revolutions * angle_per_revolution_;
    p.x.push_back(v);
  }
  return p;
}

SectionPoint PoincareMap::point(const SimulationResult& result) const {
  const int revolutions = static_cast<int>(std::lround(result.end_time / period_));
  return point(result.final_state, result.final_approach_speed, result.final_motor_phase, revolutions);
}

StartState PoincareMap::start(const SectionPoint& p) const {
  StartState s;
  s.y.assign(static_cast<std::size_t>(model_.layout.size), 0.0);
  for (std::size_t j = 0; j < coordinates_.size(); ++j) s.y[static_cast<std::size_t>(coordinates_[j])] = p.x[j];
  if (model_.layout.cam_angle) s.y[static_cast<std::size_t>(*model_.layout.cam_angle)] += model_.theta(0.0);
  s.approach_speed = p.approach_speed;
  s.motor_phase = p.motor_phase;
  return s;
}

SceneConfig PoincareMap::scene_for(double revolutions) const {
  SceneConfig s = scene_;
  s.simulation.duration.reset();
  s.simulation.cycles = revolutions;
  s.simulation.discard_cycles = 0;
  s.simulation.output_step.reset();
  s.simulation.output_step_deg = 360.0;
  return s;
}

MapResult PoincareMap::apply(const SectionPoint& p, int k, Workspace& ws) const {
  SimulationOptions options;
  options.record_series = false;
  options.step_metrics = false;
  options.quadratures = false;  // the map reads the state and the events
  options.start = std::make_shared<const StartState>(start(p));
  const SimulationResult r = simulate(scene_for(k), model_, ws, options);
  MapResult m;
  m.ok = r.solver.converged();
  m.message = r.solver.message;
  m.steps = r.solver.counters.steps;
  m.impacts = static_cast<long>(
      std::count_if(r.events.begin(), r.events.end(), [](const ContactEvent& e) { return e.onset && e.impact; }));
  if (m.ok) m.end = point(r);
  return m;
}

double PoincareMap::scaled_distance(std::span<const double> a, std::span<const double> b) const {
  return camdyn::scaled_distance(a, b, scales_);
}

double scaled_distance(std::span<const double> a, std::span<const double> b, std::span<const double> scales) {
  double d = 0.0;
  for (std::size_t j = 0; j < a.size(); ++j) {
    const double x = std::abs(a[j] - b[j]) / scales[j];
    if (std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    d = std::max(d, x);
  }
  return d;
}

double scaled_norm(std::span<const double> d, std::span<const double> scales) {
  double m = 0.0;
  for (std::size_t j = 0; j < d.size(); ++j) {
    const double x = std::abs(d[j]) / scales[j];
    if (std::isnan(x)) return std::numeric_limits<double>::quiet_NaN();
    m = std::max(m, x);
  }
  return m;
}

}  // namespace camdyn
