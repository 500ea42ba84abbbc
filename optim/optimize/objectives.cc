#include "optim/optimize/objectives.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <numbers>
#include <numeric>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/contact_stress.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/model.h"
#include "geometry/cam_synthesis.h"
#include "geometry/motion_law.h"
#include "optim/optimize/lobe_bound.h"
#include "output/report.h"
#include "study/simulation_output.h"

namespace camdyn::optim {

namespace {

/// Residual of an invalid design, for every constraint: clearly violated but
/// finite, so that model-based algorithms (COBYLA's linear models) stay sane.
constexpr double kInvalidResidual = 100.0;
/// Floor of the separation normaliser, as a share of the lift: a baseline that
/// never separates still gives the separation measure a scale.
constexpr double kMeanGapFloor = 1e-4;
/// Rigid-model force samples per turn for the force normaliser.
constexpr int kForceSamples = 3600;

double max_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); }
double min_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

}  // namespace

EvaluationSettings loop_settings(const OptimizerConfig& config) {
  EvaluationSettings s;
  s.cycles = config.evaluation_cycles;
  s.rtol = config.evaluation_rtol;
  s.max_wall_time_s = config.evaluation_max_wall_time_s;
  return s;
}

DesignEvaluator::DesignEvaluator(const OptimizeStudyConfig& config, std::string file, SimulationPool& pool)
    : config_(config), file_(std::move(file)), pool_(pool) {
  using Sense = ConstraintSpec::Sense;
  const ConstraintsConfig& c = config.constraints;
  if (c.max_pressure_angle_deg)
    constraints_.push_back({"max_pressure_angle_deg", Sense::at_most, *c.max_pressure_angle_deg, "deg", false});
  if (c.min_radius_of_curvature)
    constraints_.push_back({"min_radius_of_curvature", Sense::at_least, *c.min_radius_of_curvature, "m", false});
  if (c.max_peak_contact_force)
    constraints_.push_back({"max_peak_contact_force", Sense::at_most, *c.max_peak_contact_force, "N", true});
  if (c.min_contact_force)
    constraints_.push_back({"min_contact_force", Sense::at_least, *c.min_contact_force, "N", true});
  if (c.no_separation) constraints_.push_back({"no_separation", Sense::zero, 0.0, "-", true});
  if (c.max_peak_jerk) constraints_.push_back({"max_peak_jerk", Sense::at_most, *c.max_peak_jerk, "m/rad^3", false});
  if (c.max_spring_force) constraints_.push_back({"max_spring_force", Sense::at_most, *c.max_spring_force, "N", true});
  if (c.max_seating_velocity)
    constraints_.push_back({"max_seating_velocity", Sense::at_most, *c.max_seating_velocity, "m/s", true});
  if (c.max_contact_stress)
    constraints_.push_back({"max_contact_stress", Sense::at_most, *c.max_contact_stress, "Pa", false});
  if (c.max_seat_bounce_height)
    constraints_.push_back({"max_seat_bounce_height", Sense::at_most, *c.max_seat_bounce_height, "m", true});
  if (c.max_take_up_bounces)
    constraints_.push_back({"max_take_up_bounces", Sense::at_most, *c.max_take_up_bounces, "per revolution", true});

  const ObjectiveConfig& o = config.objective;
  needs_simulation_ = o.separation > 0.0 || o.peak_contact_force > 0.0 || o.contact_force_margin > 0.0 ||
                      std::any_of(constraints_.begin(), constraints_.end(), [](const auto& s) { return s.dynamic; });
}

void DesignEvaluator::require_no_separation_at(const std::vector<double>& rpm) {
  if (rpm.empty()) return;
  proven_rpm_ = rpm;
  constraints_.push_back({"no_separation_where_proven", ConstraintSpec::Sense::zero, 0.0, "-", true});
  needs_simulation_ = true;
}

SceneConfig DesignEvaluator::at_speed(const SceneConfig& scene, double rpm, const EvaluationSettings& settings) {
  SceneConfig s = scene;
  s.mechanism.cam.rpm = rpm;
  if (settings.cycles) {
    s.simulation.cycles = *settings.cycles;
    s.simulation.duration.reset();
  }
  if (settings.rtol) s.integrator.rtol = *settings.rtol;
  if (settings.max_wall_time_s)
    s.integrator.max_wall_time_s = std::min(s.integrator.max_wall_time_s, *settings.max_wall_time_s);
  return s;
}

double DesignEvaluator::invalid_objective() const {
  const ObjectiveConfig& o = config_.objective;
  const double weights =
      o.separation + o.peak_contact_force + o.contact_force_margin + o.peak_acceleration + o.peak_jerk + o.lift_area;
  return 1000.0 * weights;
}

DesignEvaluation DesignEvaluator::evaluate(const SceneConfig& scene, const EvaluationSettings& settings,
                                           bool simulate) const {
  DesignEvaluation e;
  const double top = *std::max_element(config_.operating_rpm.begin(), config_.operating_rpm.end());
  e.scene = at_speed(scene, top, settings);
  // The design's geometry is built once, on this thread, and every operating
  // speed assembles its model on it (a cam that cannot be made, or breaks the
  // scene's limits, makes the design invalid before anything is simulated).
  std::shared_ptr<const CamGeometry> geometry;
  try {
    geometry = build_cam_geometry(e.scene, file_);
    e.kinematics = law_kinematics(*geometry->law, scene.mechanism.cam.motion_law.segments);
    const std::optional<DesignEventConfig>& ev = config_.design.event;
    constexpr double kRad = std::numbers::pi / 180.0;
    const double from = ev ? ev->from_deg * kRad : 0.0;                 // [rad]
    const double to = ev ? ev->to_deg * kRad : 2.0 * std::numbers::pi;  // [rad]
    e.lift_area = optim::lift_area(*geometry->law, from, to);
    e.highest_lift = optim::highest_lift(*geometry->law, from, to);
    e.geometry = geometry->geometry;
    e.valid = true;
  } catch (const InputError& err) {
    e.error = err.what();
  }
  simulate = simulate && e.valid;
  // The model too is assembled once, at the first operating speed, and each
  // speed sets its own in place on a copy (where it cannot be assembled, each
  // speed assembles its own and says why it fails at that speed).
  std::shared_ptr<const Model> model;
  if (e.valid && (simulate || config_.constraints.max_contact_stress)) {
    try {
      model = std::make_shared<const Model>(
          build_model(*geometry, at_speed(scene, config_.operating_rpm.front(), settings), file_));
    } catch (const InputError&) {
      model = nullptr;
    }
  }
  if (simulate) {
    std::vector<SceneConfig> scenes;
    for (double rpm : config_.operating_rpm) scenes.push_back(at_speed(scene, rpm, settings));
    SimulationOptions options;
    options.record_series = settings.record_series;
    JobStarts starts;
    if (settings.warm != nullptr && settings.warm->size() == scenes.size()) starts.warm = *settings.warm;
    starts.end_points = settings.end_points;
    pool_.submit(geometry, std::move(scenes), std::move(options), std::move(starts), model);
  }
  // The workers simulate while this thread computes the contact stress.
  if (e.valid && config_.constraints.max_contact_stress) {
    try {
      peak_contact_stress(*geometry, model.get(), e);
    } catch (const InputError& err) {
      e.valid = false;
      e.error = err.what();
    }
  }
  if (simulate) {
    std::vector<SimulationOutcome> outcomes = pool_.collect();
    e.simulated = e.valid;
    for (std::size_t i = 0; i < outcomes.size() && e.valid; ++i) {
      SimulationOutcome& out = outcomes[i];
      if (out.status != SimulationOutcome::Status::ok) {
        e.valid = false;
        e.error = "at " + format_number(config_.operating_rpm[i]) + " rpm: " + out.error;
        break;
      }
      const double window = out.result.metrics_duration();  // [s]
      // With a seat, the gaps of the lash and its bounces are no jump: the float's integral (docs/valvetrain.md).
      const Metrics& m = out.result.metrics;
      const double gap = window > 0.0 ? m.float_integral.value_or(m.separation_integral) / window : 0.0;
      e.speeds.push_back({config_.operating_rpm[i], std::max(gap, 0.0), std::move(out.result)});
      if (settings.end_points) e.end_points.push_back(std::move(out.end_point));
      if (out.warm) ++e.warm_speeds;
    }
    if (!e.valid) {
      e.speeds.clear();
      e.end_points.clear();
      e.warm_speeds = 0;
    }
  }
  score(e);
  return e;
}

void DesignEvaluator::peak_contact_stress(const CamGeometry& geometry, const Model* assembled,
                                          DesignEvaluation& e) const {
  Model model;
  if (assembled != nullptr) {
    model = *assembled;
    set_cam_speed(model, e.scene, file_);
  } else {
    model = build_model(geometry, e.scene, file_);
  }
  const LineContact contact = *line_contact(e.scene.mechanism.contact);  // check_optimize made sure
  e.peak_contact_stress = 0.0;
  for (const double rpm : config_.operating_rpm) {
    const double p = peak_rigid_contact_pressure(model, contact, rpm * 2.0 * std::numbers::pi / 60.0).pressure;
    if (p > e.peak_contact_stress) {
      e.peak_contact_stress = p;
      e.contact_stress_rpm = rpm;
    }
  }
}

namespace {

/// The weights are capped at validation (optimize_config.h); a term that is
/// itself not finite (a metric that overflowed) makes the design invalid,
/// naming the term, rather than put inf into the history and the search.
bool objective_not_finite(DesignEvaluation& e) {
  if (std::isfinite(e.objective)) return false;
  std::string which;
  for (const TermValue& t : e.terms)
    if (!std::isfinite(t.weight * t.normalised)) which += (which.empty() ? "" : ", ") + t.name;
  e.valid = false;
  e.error = "the weighted objective is not finite (term " + which + ")";
  return true;
}

}  // namespace

double DesignEvaluator::aggregate(const std::vector<double>& v, bool worst_is_max) const {
  if (v.empty()) return 0.0;
  if (config_.objective.aggregate == "mean")
    return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
  return worst_is_max ? max_of(v) : min_of(v);
}

namespace {

/// Each operating speed's figures that the terms and constraints aggregate.
struct SpeedFigures {
  std::vector<double> gap, peak, lowest, fraction, margin, spring, seating, bounce_height, take_ups;
};

SpeedFigures speed_figures(const DesignEvaluation& e, const Normalisation& norm) {
  SpeedFigures out;
  for (const SpeedResult& s : e.speeds) {
    const Metrics& m = s.result.metrics;
    out.gap.push_back(s.mean_gap);
    out.peak.push_back(m.peak_contact_force);
    // A train keeps every link loaded as well (docs/optimize.md "Trains"): its
    // smallest force is the least of the contact's and the links', and a link
    // that opens separates.
    out.lowest.push_back(m.train && m.train->links ? std::min(m.min_contact_force, m.train->min_link_force)
                                                   : m.min_contact_force);
    out.fraction.push_back(std::max(m.float_fraction.value_or(m.separation_fraction),  // float: docs/valvetrain.md
                                    m.train ? m.train->link_float_fraction : 0.0));
    out.spring.push_back(m.train ? m.train->peak_spring_force : 0.0);
    out.seating.push_back(m.train ? m.train->max_seating_velocity : 0.0);
    out.bounce_height.push_back(m.train ? m.train->max_seat_bounce_height : 0.0);
    const double revolutions = s.result.metrics_duration() * s.rpm / kSecondsPerMinute;
    out.take_ups.push_back(m.train && revolutions > 0.0 ? static_cast<double>(m.train->take_up_bounces) / revolutions
                                                        : 0.0);
    // Smallest contact force, continued below zero by the separation measure,
    // so it keeps a slope on both sides of the jump.
    out.margin.push_back(m.min_contact_force - norm.force * s.mean_gap / norm.mean_gap);
  }
  return out;
}

}  // namespace

void DesignEvaluator::score(DesignEvaluation& e) const {
  e.terms.clear();
  e.constraints.assign(constraints_.size(), ConstraintValue{});
  e.objective = 0.0;
  e.feasible = false;
  if (!e.valid) {
    e.objective = invalid_objective();
    for (ConstraintValue& c : e.constraints) c.residual = kInvalidResidual;
    return;
  }

  const SpeedFigures figures = speed_figures(e, norm_);
  const std::vector<double>&gap = figures.gap, &peak = figures.peak, &lowest = figures.lowest,
        &fraction = figures.fraction, &margin = figures.margin, &spring = figures.spring, &seating = figures.seating,
        &bounce_height = figures.bounce_height, &take_ups = figures.take_ups;

  const ObjectiveConfig& o = config_.objective;
  auto term = [&](const char* name, double weight, double value, double normalised, const std::string& unit) {
    if (weight <= 0.0) return;
    e.terms.push_back({name, weight, value, normalised, unit});
    e.objective += weight * normalised;
  };
  if (e.simulated) {
    const double g = aggregate(gap, true), f = aggregate(peak, true), mg = aggregate(margin, false);
    term("separation", o.separation, g, g / norm_.mean_gap, "m");
    term("peak_contact_force", o.peak_contact_force, f, f / norm_.force, "N");
    term("contact_force_margin", o.contact_force_margin, mg, -mg / norm_.force, "N");
  }
  // The law's derivatives are in q per radian of cam angle: an arm's in rad/rad^n.
  const CoordinateUnits units = coordinate_units(e.scene);
  term("peak_acceleration", o.peak_acceleration, e.kinematics.peak_acceleration,
       e.kinematics.peak_acceleration / norm_.acceleration, units.per_cam_radian(2, true));
  term("peak_jerk", o.peak_jerk, e.kinematics.peak_jerk, e.kinematics.peak_jerk / norm_.jerk,
       units.per_cam_radian(3, true));
  // Maximised: baseline area / area, 1 for the baseline, smaller for more area.
  term("lift_area", o.lift_area, e.lift_area, norm_.lift_area / std::max(e.lift_area, 1e-6 * norm_.lift_area),
       std::string(units.position) + " rad");
  if (objective_not_finite(e)) return score(e);  // scored as invalid

  e.feasible = true;
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    const ConstraintSpec& spec = constraints_[i];
    ConstraintValue& c = e.constraints[i];
    if (spec.dynamic && !e.simulated) {  // not measured: neither holds nor pushes the search
      c.holds = false;
      c.residual = 0.0;
      e.feasible = false;
      continue;
    }
    const double limit = spec.limit;
    if (spec.name == "max_pressure_angle_deg") {
      c.value = e.geometry.max_pressure_angle_deg;
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "min_radius_of_curvature") {
      c.value = e.geometry.min_radius_of_curvature;
      c.residual = (limit - c.value) / limit;
    } else if (spec.name == "max_contact_stress") {
      c.value = e.peak_contact_stress;
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "max_peak_jerk") {
      c.value = e.kinematics.peak_jerk;
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "max_spring_force") {
      c.value = max_of(spring);
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "max_seating_velocity") {
      c.value = max_of(seating);
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "max_seat_bounce_height") {
      c.value = max_of(bounce_height);
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "max_take_up_bounces") {
      c.value = max_of(take_ups);
      c.residual = (c.value - limit) / std::max(limit, 1.0);  // a limit of 0 bounces is allowed
    } else if (spec.name == "max_peak_contact_force") {
      c.value = max_of(peak);
      c.residual = (c.value - limit) / limit;
    } else if (spec.name == "min_contact_force") {
      c.value = min_of(lowest);
      // The floor, continued by the separation measure while the follower
      // separates (the smallest force is then stuck at 0 and has no slope).
      c.residual = -1e300;
      for (std::size_t k = 0; k < lowest.size(); ++k)
        c.residual = std::max(c.residual, (limit - lowest[k]) / limit + gap[k] / norm_.mean_gap);
    } else if (spec.name == "no_separation_where_proven") {
      // As no_separation, over the speeds the rigid stage proved jump-free only.
      c.value = 0.0;
      c.residual = 0.0;
      for (std::size_t k = 0; k < e.speeds.size(); ++k) {
        if (std::find(proven_rpm_.begin(), proven_rpm_.end(), e.speeds[k].rpm) == proven_rpm_.end()) continue;
        c.value = std::max(c.value, fraction[k]);
        c.residual = std::max(c.residual, std::max(gap[k] / norm_.mean_gap, fraction[k]));
      }
    } else {  // no_separation
      c.value = max_of(fraction);
      c.residual = std::max(max_of(gap) / norm_.mean_gap, c.value);
    }
    switch (spec.sense) {
      case ConstraintSpec::Sense::at_most:
        c.margin = limit - c.value;
        break;
      case ConstraintSpec::Sense::at_least:
        c.margin = c.value - limit;
        break;
      case ConstraintSpec::Sense::zero:
        c.margin = 0.0 - c.value;
        break;  // not −0
    }
    c.holds = spec.sense == ConstraintSpec::Sense::zero ? c.value <= 0.0 : c.margin >= 0.0;
    e.feasible = e.feasible && c.holds;
  }
}

Normalisation DesignEvaluator::normalisation_from(const DesignEvaluation& baseline) const {
  if (!baseline.valid) throw InputError(file_, "mechanism", "the baseline design is invalid: " + baseline.error);
  Normalisation n;
  // Peak rigid-model contact force at the top speed.
  const Model model = build_model(baseline.scene, file_);
  std::vector<double> angles(kForceSamples);  // [rad]
  for (int i = 0; i < kForceSamples; ++i)
    angles[static_cast<std::size_t>(i)] = 2.0 * std::numbers::pi * i / kForceSamples;
  double force = 0.0;
  for (const double p : rigid_contact_force(model, angles)) force = std::max(force, std::abs(p));  // a train: held
  n.force = force > 0.0 ? force : 1.0;
  std::vector<double> gap;
  for (const SpeedResult& s : baseline.speeds) gap.push_back(s.mean_gap);
  const double lift = std::max(model.law->lift(), 1e-12);
  n.mean_gap = std::max(aggregate(gap, true), kMeanGapFloor * lift);
  n.acceleration = baseline.kinematics.peak_acceleration > 0.0 ? baseline.kinematics.peak_acceleration : 1.0;
  n.jerk = baseline.kinematics.peak_jerk > 0.0 ? baseline.kinematics.peak_jerk : 1.0;
  n.lift_area = baseline.lift_area > 0.0 ? baseline.lift_area : 1.0;
  return n;
}

}  // namespace camdyn::optim
