#include "study/simulation_output.h"

#include <camdyn/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <type_traits>

#include "common/constants.h"
#include "common/parallel.h"
#include "dynamics/contact_stress.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/held_train_force.h"
#include "dynamics/plausibility.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/spring_sizing.h"
#include "dynamics/train_jump_speed.h"
#include "io/atomic_file.h"
#include "io/csv_writer.h"
#include "io/json_writer.h"
#include "output/cam_plots.h"
#include "output/valvetrain_figures.h"
#include "study/train_report.h"

namespace camdyn {

namespace {

Json finite_or_null(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }

std::string format(double v, const char* unit = "") {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g%s%s", v, *unit ? " " : "", unit);
  return buffer;
}

Json error_estimate_json(const ErrorEstimate& e) {
  Json j{{"energy_residual", e.energy_residual}};
  if (e.richardson) {
    j["method"] = "richardson";
    j["position"] = e.position;
    j["peak_contact_force"] = e.peak_contact_force;
    j["tight_run_time_s"] = e.tight_run_time_s;
  } else {
    j["method"] = "energy";
  }
  return j;
}

}  // namespace

Json warnings_json(const std::vector<PlausibilityWarning>& warnings) {
  Json list = Json::array();
  for (const PlausibilityWarning& w : warnings)
    list.push_back(Json{{"cause", w.cause}, {"field", w.field}, {"message", w.message}});
  return list;
}

/// A follower train's metrics (docs/model.md §12), each where the scene has its element.
void add_train_metrics(const TrainMetrics& t, Json& j) {
  for_each_train_metric(t, [&](const char* name, double value, bool count, const char*) {
    j[name] = count ? Json(static_cast<long>(value)) : Json(value);
  });
  if (t.lash) j["held_open"] = t.held_open;
  Json lift = Json::object();
  for (std::size_t i = 0; i < t.bodies.size(); ++i) lift[t.bodies[i]] = t.max_lift_error[i];
  j["max_lift_error"] = lift;
  if (!t.separates_first.empty())
    j["separates_first"] = Json{{"where", t.separates_first}, {"cam_angle_deg", t.separates_first_deg}};
}

Json metrics_json(const Metrics& m) {
  Json j = Json::object();
  for_each_metric(m, [&](const char* name, const auto& value, const MetricInfo& info) {
    using T = std::remove_cvref_t<decltype(value)>;
    if constexpr (std::is_same_v<T, std::optional<double>>) {
      if (value) j[name] = finite_or_null(*value);  // absent where it does not apply (docs/outputs-and-resume.md)
    } else if constexpr (std::is_floating_point_v<T>) {
      j[name] = info.infinite_is_null ? finite_or_null(value) : Json(value);
    } else {
      j[name] = value;
    }
  });
  if (m.train) add_train_metrics(*m.train, j);
  return j;
}

std::vector<double> rigid_contact_force(const Model& model, const std::vector<double>& thetas) {
  const RigidContactForce force(model, model.omega);
  std::vector<double> out;
  out.reserve(thetas.size());
  for (const double theta : thetas) out.push_back(force.normal(theta));
  return out;
}

std::string follower_name(const Model& model) {
  const FollowerGeometry& f = model.follower;
  return std::string(f.oscillating() ? "oscillating_" : "translating_") + to_string(f.shape);
}

std::string drive_name(const Model& model) {
  if (model.drive.shaft())
    return model.drive.motor == Motor::torque_speed ? "shaft:torque_speed_motor" : "shaft:constant_speed_motor";
  return model.omega > 0.0 ? "constant_speed" : "stationary";
}

std::string contact_pair_name(const Model& model) {
  const bool flat = model.reduction == ContactReduction::line;
  const std::string shape(model.follower.traits().label);
  const std::string cam = model.contour ? "the fitted contour" : flat ? "the cam contour" : "the pitch curve";
  if (model.pair_form == PairForm::general)
    return shape + ": " + (flat ? "face segment" : "circle") + " against the cam contour (general two-parameter pair)";
  if (flat) return shape + ": line against " + cam + " (one-parameter reduction)";
  return shape + ": circle centre against " + cam + (model.contour ? " offset by its radius" : "") +
         " (one-parameter reduction)";
}

namespace {

/// Distance of each contour point from the fitted curve [m].
std::vector<double> contour_residuals(const ContourCam& cam) {
  std::vector<double> r(cam.points().size());
  for (std::size_t i = 0; i < r.size(); ++i)
    r[i] = (cam.points()[i] - cam.at(cam.point_parameter(static_cast<int>(i))).r).norm();
  return r;
}

Json contour_fit_json(const Model& model) {
  const ContourFitReport& f = model.contour->report();
  Json concave = Json::array();
  for (const ConcavePortion& c : f.concave)
    concave.push_back(Json{{"angle_begin_deg", c.angle_begin_deg},
                           {"angle_end_deg", c.angle_end_deg},
                           {"point_begin", c.point_begin},
                           {"point_end", c.point_end},
                           {"min_abs_radius", c.min_abs_radius},
                           {"min_abs_radius_angle_deg", c.min_abs_radius_angle_deg}});
  return Json{{"points", f.points},
              {"degree", f.degree},
              {"control_points", f.control_points},
              {"rms_residual", f.rms_residual},
              {"max_residual", f.max_residual},
              {"max_residual_point", f.max_residual_point},
              {"min_radius_of_curvature", finite_or_null(f.min_radius_of_curvature)},
              {"min_radius_of_curvature_angle_deg", f.min_radius_of_curvature_angle_deg},
              {"min_convex_radius", finite_or_null(f.min_convex_radius)},
              {"min_convex_radius_angle_deg", f.min_convex_radius_angle_deg},
              {"concave", concave},
              {"base_radius", model.follower.base_radius},
              {"lowest_angle_deg", model.contour_lift->lowest_angle() * kRadToDeg},
              {"law_interpolation_error", model.law_interpolation_error}};
}

}  // namespace

namespace {

/// spring_sizing of a follower train: the held train's preload, or null and why (docs/model.md §12).
Json held_spring_sizing_json(const Model& model) {
  const HeldSpringSizing s = size_held_spring(model, 0.0, model.omega);
  Json j{{"model", "held train"},
         {"spring", s.spring.empty() ? Json(nullptr) : Json(s.spring)},
         {"required_preload", s.available ? Json(s.required_preload) : Json(nullptr)},
         {"required_preload_unit", s.unit},
         {"required_stiffness", nullptr},
         {"required_stiffness_unavailable",
          "not sized on a train: a rate changes the held train's modes, so the force is not linear in it"},
         {"min_contact_force", 0.0},
         {"up_to_rpm", model.omega * 60.0 / (2.0 * std::numbers::pi)}};
  if (s.available) {
    j["required_preload_at_deg"] = s.preload_at_deg;
    j["required_preload_at_rpm"] = s.preload_at_rpm;
    j["required_preload_binding"] = s.binding;
  } else {
    j["required_preload_unavailable"] = s.reason;
  }
  return j;
}

}  // namespace

Json spring_sizing_json(const Model& model) {
  if (rigid_figures_held(model)) return held_spring_sizing_json(model);
  const std::optional<RigidSpringLoad> load = rigid_spring_load(model, 0.0);
  if (!load)
    return Json{{"required_preload", nullptr},
                {"required_preload_unit", coordinate_units(model).force},
                {"required_preload_unavailable", kNoLinearPart},
                {"required_stiffness", nullptr},
                {"min_contact_force", 0.0},
                {"up_to_rpm", model.omega * 60.0 / (2.0 * std::numbers::pi)}};
  const SpringSizing s = size_spring(*model.law, *load, model.omega);
  const Json rate = std::isfinite(s.required_stiffness) ? Json(s.required_stiffness) : Json(nullptr);
  return Json{{"required_preload", s.required_preload},
              {"required_preload_unit", coordinate_units(model).force},
              {"required_preload_at_deg", s.preload_at_deg},
              {"required_stiffness", rate},
              {"min_contact_force", 0.0},
              {"up_to_rpm", model.omega * 60.0 / (2.0 * std::numbers::pi)}};
}

Json summary_json(const SceneConfig& scene, const Model& model, const SimulationResult& result) {
  const SolverSummary& s = result.solver;
  Json summary;
  summary["name"] = scene.name;
  summary["study"] = "simulate";
  summary["camdyn_version"] = CAMDYN_VERSION;
  summary["metrics"] = metrics_json(result.metrics);
  summary["metrics_over"] = result.metrics_over;
  if (!result.metrics_note.empty()) summary["steady_state"] = result.metrics_note;
  summary["solver"] = Json{{"method", s.method},
                           {"rtol", s.rtol},
                           {"atol", s.atol},
                           {"steps", s.counters.steps},
                           {"rhs_evaluations", s.counters.rhs_evaluations},
                           {"events", s.events},
                           {"tracking_resets", s.tracking_resets},
                           {"run_time_s", s.run_time_s},
                           {"error_estimate", error_estimate_json(result.error)},
                           {"error_test_failures", s.counters.error_test_failures},
                           {"nonlinear_iterations", s.counters.nonlinear_iterations},
                           {"jacobian_evaluations", s.counters.jacobian_evaluations},
                           {"restarts", s.counters.reinitialisations},
                           {"tracking_projections", s.projections},
                           {"flights", s.flights},
                           {"flight_intervals", s.flight_intervals},
                           {"tracking", model.tracking == Tracking::newton ? "newton" : "differential"},
                           {"simulated_time_s", result.end_time},
                           {"evaluated_from_s", result.evaluated_from},
                           {"termination", to_string(s.termination)},
                           {"message", s.message}};
  summary["model"] = Json{{"state_size", model.layout.size},
                          {"states", model.layout.names},
                          {"elements", model.elements},
                          {"quadratures", integrated_quadratures(model)},
                          {"cam", drive_name(model)},
                          {"follower", follower_name(model)},
                          {"contact_pair", contact_pair_name(model)}};
  if (model.contour) summary["contour_fit"] = contour_fit_json(model);
  summary["warnings"] = warnings_json(run_warnings(scene, model, result));
  // The contact stiffness the model uses [N/m^n], given or from materials (docs/config.md).
  summary["resolved"] =
      Json{{"contact_stiffness", model.contact.stiffness},
           {"contact_stiffness_from", scene.mechanism.contact.from_materials ? "materials" : "config"}};
  // The rigid single-mass sizing does not describe a train (docs/model.md §12).
  summary["spring_sizing"] = spring_sizing_json(model);  // on a train the held train's (docs/model.md §12)
  if (scene.outputs.valvetrain) summary["valvetrain"] = valvetrain_json(scene, model, &result);
  summary["config"] = to_json(scene);
  return summary;
}

namespace {

/// The contour cam's fit: a table, the points against the fitted curve, and the residual per point.
void add_contour_fit(const Model& model, Report& report) {
  const ContourCam& cam = *model.contour;
  const ContourFitReport& f = cam.report();
  Table fit{"Contour fit", {"quantity", "value", "unit"}, {}, false};
  fit.rows = {
      {"points", std::to_string(f.points), "–"},
      {"spline degree / control points", std::to_string(f.degree) + " / " + std::to_string(f.control_points), "–"},
      {"rms residual", format(f.rms_residual * 1e6), "µm"},
      {"max residual", format(f.max_residual * 1e6) + " (point " + std::to_string(f.max_residual_point) + ")", "µm"},
      {"smallest radius of curvature",
       format(f.min_radius_of_curvature * 1e3) + " at " + format(f.min_radius_of_curvature_angle_deg) + "°", "mm"},
      {"concave portions", std::to_string(f.concave.size()), "–"},
      {"base radius (derived)", format(model.follower.base_radius * 1e3), "mm"},
      {"law interpolation error", format(model.law_interpolation_error * 1e9), "nm"}};
  report.tables.push_back(std::move(fit));
  constexpr int kCurveSamples = 720;
  Series curve{"fitted spline", {}, {}, "lines", PlotRole::fitted},
      points{"given points", {}, {}, "points", PlotRole::measured};
  for (int i = 0; i <= kCurveSamples; ++i) {
    const Eigen::Vector2d r = cam.at(2.0 * std::numbers::pi * i / kCurveSamples).r;
    curve.x.push_back(r.x() * 1e3);
    curve.y.push_back(r.y() * 1e3);
  }
  Series residual{"distance to the fitted spline", {}, {}, "linespoints"};
  const std::vector<double> distances = contour_residuals(cam);
  for (std::size_t i = 0; i < cam.points().size(); ++i) {
    points.x.push_back(cam.points()[i].x() * 1e3);
    points.y.push_back(cam.points()[i].y() * 1e3);
    residual.x.push_back(static_cast<double>(i));
    residual.y.push_back(distances[i]);  // [m] until the unit is known
  }
  report.plots.push_back(Plot{"Cam contour: given points and fitted spline (cam frame at angle 0)",
                              "x [mm]",
                              "y [mm]",
                              {std::move(curve), std::move(points)}});
  const LengthUnit unit = length_unit({&residual.y});
  residual.y = unit.of(residual.y);
  report.plots.push_back(
      Plot{"Contour fit residual per point", "point index [-]", unit.axis("residual"), {std::move(residual)}});
}

}  // namespace

namespace {

/// `deg` in [0, 360) [deg].
double wrap_deg(double deg) {
  const double w = std::fmod(deg, 360.0);
  return w < 0.0 ? w + 360.0 : w;
}

std::string angle_text(double deg, const std::optional<CrankScale>& crank) { return verdict_angle_text(deg, crank); }

std::string rpm_text(double rpm) {
  return std::isfinite(rpm) ? format_number(rpm, 5) + " rpm" : jump_speed_text(rpm, 5);
}

/// Index of the smallest contact force at or after `from` [s] where the cam
/// touches, over the law above the take-up windows with a seat (where the
/// metric is taken, docs/valvetrain.md); the series' size if there is none.
std::size_t min_force_index(const Model& model, const TimeSeries& ts, double from) {
  std::size_t best = ts.time.size();
  for (std::size_t i = 0; i < ts.time.size(); ++i)
    if (ts.time[i] >= from && std::isfinite(ts.contact_force[i]) && !(ts.gap[i] > 0.0) &&
        (!model.take_up.applies ||
         !in_take_up_windows(model.take_up, model.law->eval(ts.cam_angle_deg[i] / kRadToDeg))) &&
        (best == ts.time.size() || ts.contact_force[i] < ts.contact_force[best]))
      best = i;
  return best;
}

/// A drop test (cam held still): where the follower lands, the peak force, the rebounds.
Verdict drop_verdict(const SimulationResult& result) {
  const Metrics& m = result.metrics;
  Verdict v;
  const auto landing =
      std::find_if(result.events.begin(), result.events.end(), [](const ContactEvent& e) { return e.onset; });
  const long rebounds = std::count_if(landing, result.events.end(), [](const ContactEvent& e) { return !e.onset; });
  if (landing == result.events.end()) {
    const bool touching = m.peak_contact_force > 0.0;
    v.tone = touching ? Verdict::Tone::good : Verdict::Tone::warning;
    v.headline =
        touching ? "drop test: stays in contact, peak contact force " + format_number(m.peak_contact_force, 4) + " N"
                 : "drop test: the follower does not reach the cam within " + format_number(result.end_time, 4) + " s";
  } else {
    v.tone = Verdict::Tone::neutral;
    v.headline = "drop test: lands at t = " + format_number(landing->time, 4) + " s at " +
                 format_number(landing->speed, 4) + " m/s, peak contact force " +
                 format_number(m.peak_contact_force, 4) + " N";
    const auto rebound = std::find_if(landing, result.events.end(), [](const ContactEvent& e) { return !e.onset; });
    v.headline += rebound == result.events.end()
                      ? "; comes to rest without a rebound"
                      : "; rebounds " + std::to_string(rebounds) + " time" + (rebounds == 1 ? "" : "s") +
                            " (first at " + format_number(rebound->speed, 4) + " m/s, highest gap " +
                            format_number(m.max_separation_gap * 1e3, 4) + " mm)";
  }
  v.details.push_back("largest penetration " + format_number(m.max_penetration * 1e6, 4) + " µm over " +
                      format_number(result.end_time, 4) + " s simulated");
  return v;
}

/// A valve the law cannot seat (docs/valvetrain.md): red whatever the run did.
void held_open_verdict(const Model& model, Verdict& v) {
  v.tone = Verdict::Tone::bad;
  v.headline = take_up_window_problem(model.train, model.take_up);
  v.details.push_back(
      "check the seat positions and the links' lash: every valve must rest on its seat on the base circle");
}

/// The first float in the window: where the follower lets go, where it lands.
void separation_verdict(const SimulationResult& result, const VerdictAngles& at, const std::optional<CrankScale>& crank,
                        Verdict& v) {
  const Metrics& m = result.metrics;
  v.tone = Verdict::Tone::bad;
  if (at.lift_off_deg) {
    v.headline = "separates at " + angle_text(*at.lift_off_deg, crank) +
                 (at.landing_deg ? ", lands at " + angle_text(*at.landing_deg, crank) + " at " +
                                       format_number(at.landing_speed, 4) + " m/s"
                                 : ", still airborne when the run ends");
  } else if (at.lets_go_deg) {
    v.headline = "the train lets go at its " + at.lets_go_where + " first, at " + angle_text(*at.lets_go_deg, crank);
  } else {
    v.headline = "separated for part of the evaluated window";
  }
  if (at.lets_go_deg && at.lets_go_where != "cam contact")
    v.details.push_back("the train lets go first at its " + at.lets_go_where + ", at " +
                        angle_text(*at.lets_go_deg, crank) + "; links open " +
                        format_number(100.0 * m.train->link_separation_fraction, 3) + " % of the evaluated time");
  const std::string floating =
      m.float_fraction ? " (float " + format_number(100.0 * *m.float_fraction, 3) + " %)" : std::string();
  v.details.push_back("airborne " + format_number(100.0 * m.separation_fraction, 3) + " % of the evaluated time" +
                      floating + ", " + std::to_string(m.impact_count) + " impact" + (m.impact_count == 1 ? "" : "s") +
                      ", highest impact speed " + format_number(m.max_impact_velocity, 4) +
                      " m/s, peak contact force " + format_number(m.peak_contact_force, 4) + " N");
}

/// The lash's own lines (docs/valvetrain.md): take-up bounces are not a
/// jump; a seat bounce turns a green verdict amber.
void bounce_lines(const Metrics& m, Verdict& v) {
  if (!m.train || !m.train->lash) return;
  const TrainMetrics& t = *m.train;
  v.details.push_back(t.take_up_bounces == 0
                          ? std::string("lash take-up: no bounce")
                          : "lash take-up: " + std::to_string(t.take_up_bounces) + " take-up bounce" +
                                (t.take_up_bounces == 1 ? "" : "s") + " in the evaluated window (not a jump)");
  if (t.seat_bounces == 0) {
    v.details.push_back("seat bounce: none");
    return;
  }
  v.details.push_back("seat bounce: " + std::to_string(t.seat_bounces) + " in the evaluated window, highest " +
                      format_number(t.max_seat_bounce_height * 1e3, 4) + " mm off the seat");
  if (v.tone == Verdict::Tone::good) v.tone = Verdict::Tone::warning;
}

}  // namespace

std::string verdict_angle_text(double cam_deg, const std::optional<CrankScale>& crank) {
  std::string text = format_number(wrap_deg(cam_deg), 4) + "°";
  if (crank) text += " (" + format_number(crank->of_deg(cam_deg), 4) + "° crank)";
  return text;
}

VerdictAngles verdict_angles(const Model& model, const SimulationResult& result) {
  VerdictAngles at;
  const Metrics& m = result.metrics;
  if (model.omega <= 0.0 || model.take_up.held_open_body >= 0) return at;
  if (!separates(m)) {
    const std::size_t i = min_force_index(model, result.series, result.evaluated_from);
    if (i < result.series.time.size()) at.min_force_deg = wrap_deg(result.series.cam_angle_deg[i]);
    return at;
  }
  const std::vector<ContactEvent>& events = result.events;
  const auto lift_off = std::find_if(events.begin(), events.end(), [&](const ContactEvent& e) {
    return e.time >= result.evaluated_from && !e.onset && e.cause == SeparationCause::float_gap;
  });
  if (lift_off != events.end()) {
    at.lift_off_deg = wrap_deg(lift_off->cam_angle_deg);
    const auto landing = std::find_if(lift_off, events.end(), [](const ContactEvent& e) { return e.onset; });
    if (landing != events.end()) {
      at.landing_deg = wrap_deg(landing->cam_angle_deg);
      at.landing_speed = landing->speed;
    }
  }
  // The train's first place to let go, where the verdict names it: in the
  // headline without a lift-off of the cam contact, else on a line of its own
  // when it is a link.
  if (m.train && !m.train->separates_first.empty() && (!at.lift_off_deg || m.train->separates_first != "cam contact")) {
    at.lets_go_deg = wrap_deg(m.train->separates_first_deg);
    at.lets_go_where = m.train->separates_first;
  }
  return at;
}

Verdict simulation_verdict(const SceneConfig& scene, const Model& model, const SimulationResult& result) {
  if (model.omega <= 0.0) return drop_verdict(result);
  const Metrics& m = result.metrics;
  const double rpm = scene.mechanism.cam.rpm;
  const std::string jump = std::string(jump_speed_name(model)) + " " + rpm_text(m.jump_speed_rpm) +
                           " (this run is at " + format_number(rpm, 5) + " rpm)";
  const VerdictAngles at = verdict_angles(model, result);
  const std::optional<CrankScale> crank = scene_crank_scale(scene);
  Verdict v;
  if (model.take_up.held_open_body >= 0) {
    held_open_verdict(model, v);
  } else if (!separates(m)) {
    v.tone = Verdict::Tone::good;
    v.headline = "stays in contact, minimum contact force " + format_number(m.min_contact_force, 4) + " N" +
                 (at.min_force_deg ? " at " + angle_text(*at.min_force_deg, crank) : "");
    v.details.push_back(jump);
  } else {
    separation_verdict(result, at, crank, v);
    v.headline += "; " + jump;
  }
  bounce_lines(m, v);
  if (!result.solver.converged()) {
    v.tone = Verdict::Tone::bad;
    v.details.push_back("the run stopped early (" + to_string(result.solver.termination) +
                        "): " + result.solver.message);
  }
  return v;
}

namespace {

std::vector<double> scaled(const std::vector<double>& v, double k) {
  std::vector<double> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = v[i] * k;
  return out;
}

/// The last revolution of a run on a 0–360° axis: the series' points from
/// one revolution before its end, with a break where the angle wraps.
struct LastRevolution {
  std::vector<double> angle;         ///< [deg] in [0, 360], NaN at the wrap
  std::vector<std::size_t> index;    ///< into the series; the series' size at the wrap
  double begin_deg = 0.0, base = 0;  ///< first cam angle of the revolution, offset that maps it onto 0–360 [deg]

  double map(double deg) const {
    const double a = deg - base;
    return a < 0.0 ? a + 360.0 : a;
  }
};

LastRevolution last_revolution(const TimeSeries& ts) {
  LastRevolution r;
  const double last = ts.cam_angle_deg.back();
  r.begin_deg = last - 360.0;
  r.base = 360.0 * std::floor((last - 1e-9) / 360.0);
  double previous = -1.0;
  for (std::size_t i = 0; i < ts.time.size(); ++i) {
    if (ts.cam_angle_deg[i] < r.begin_deg - 1e-9) continue;
    const double a = r.map(ts.cam_angle_deg[i]);
    if (a < previous) {
      r.angle.push_back(std::numeric_limits<double>::quiet_NaN());
      r.index.push_back(ts.time.size());
    }
    r.angle.push_back(a);
    r.index.push_back(i);
    previous = a;
  }
  return r;
}

/// `column` at the revolution's points, NaN at the wrap, times `k`.
std::vector<double> pick(const LastRevolution& r, const std::vector<double>& column, double k = 1.0) {
  std::vector<double> out(r.index.size());
  for (std::size_t j = 0; j < out.size(); ++j)
    out[j] = r.index[j] < column.size() ? column[r.index[j]] * k : std::numeric_limits<double>::quiet_NaN();
  return out;
}

/// Lift-off and impact markers of the revolution's events, at height 0.
std::vector<Series> event_markers(const LastRevolution& r, const std::vector<ContactEvent>& events) {
  Series lift_off{"lift-off", {}, {}, "points", PlotRole::lift_off},
      impact{"impact", {}, {}, "points", PlotRole::impact};
  for (const ContactEvent& e : events) {
    if (e.cam_angle_deg < r.begin_deg - 1e-9 || (e.onset && !e.impact)) continue;
    Series& s = e.onset ? impact : lift_off;
    s.x.push_back(r.map(e.cam_angle_deg));
    s.y.push_back(0.0);
  }
  std::vector<Series> out;
  for (Series* s : {&lift_off, &impact})
    if (!s->x.empty()) out.push_back(std::move(*s));
  return out;
}

/// What an engineer reads first: the last revolution on 0–360° (follower
/// against the law, contact force against the rigid model with a panel zoomed
/// to the rigid-model range when an impact spike would squash it, gap), with
/// the lift-off and impact markers.
void add_revolution_plots(const Model& model, const SimulationResult& result, Report& report) {
  const TimeSeries& ts = result.series;
  if (ts.time.empty()) return;
  const std::size_t first_plot = report.plots.size();
  const LastRevolution rev = last_revolution(ts);
  const std::vector<Series> markers = event_markers(rev, result.events);
  const bool arm = model.follower.oscillating();  // follower columns in rad: plotted in degrees
  const LengthUnit lift = length_unit({&ts.follower_position, &ts.kinematic_position});
  const double motion_scale = arm ? kRadToDeg : lift.per_metre;
  const auto xrange = std::make_pair(0.0, 360.0);
  report.plots.push_back(
      Plot{"Last revolution: follower against the motion law",
           "cam angle [deg]",
           arm ? "arm angle [deg]" : lift.axis("displacement"),
           {{"follower", rev.angle, pick(rev, ts.follower_position, motion_scale), "lines", PlotRole::dynamic},
            {"motion law", rev.angle, pick(rev, ts.kinematic_position, motion_scale), "dashes", PlotRole::rigid}},
           false,
           false,
           xrange});
  std::vector<double> rigid(rev.index.size(), std::numeric_limits<double>::quiet_NaN());
  double rigid_lo = 0.0, rigid_hi = 0.0, peak = 0.0;
  const RigidContactForce rigid_force(model, model.omega);  // on a train the held train's (docs/model.md §12)
  for (std::size_t j = 0; j < rigid.size(); ++j) {
    if (rev.index[j] >= ts.time.size()) continue;
    rigid[j] = rigid_force.normal(ts.cam_angle_deg[rev.index[j]] / kRadToDeg);
    rigid_lo = std::min(rigid_lo, rigid[j]);
    rigid_hi = std::max(rigid_hi, rigid[j]);
    peak = std::max(peak, ts.contact_force[rev.index[j]]);
  }
  Plot force{"Last revolution: contact force and the rigid-model force",
             "cam angle [deg]",
             "force [N]",
             {{"contact force", rev.angle, pick(rev, ts.contact_force), "lines", PlotRole::dynamic},
              {"rigid model", rev.angle, rigid, "dashes", PlotRole::rigid}},
             false,
             false,
             xrange};
  force.series.insert(force.series.end(), markers.begin(), markers.end());
  const double pad = 0.25 * (rigid_hi - rigid_lo);
  if (pad > 0.0 && peak > rigid_hi + pad) {  // one spike would flatten the rest: a zoomed copy
    Plot zoom = force;
    zoom.title = "Last revolution: contact force zoomed to the rigid-model range (impact spikes run off the top)";
    zoom.yrange = std::make_pair(rigid_lo - pad, rigid_hi + pad);
    report.plots.push_back(std::move(force));
    report.plots.push_back(std::move(zoom));
  } else {
    report.plots.push_back(std::move(force));
  }
  const std::vector<double> revolution_gap = pick(rev, ts.gap);  // [m]
  const LengthUnit gap_unit = length_unit({&revolution_gap});
  Plot gap{"Last revolution: gap between follower and cam (> 0 separated, < 0 penetration)",
           "cam angle [deg]",
           gap_unit.axis("gap"),
           {{"gap", rev.angle, gap_unit.of(revolution_gap), "lines", PlotRole::dynamic}},
           false,
           false,
           xrange};
  gap.series.insert(gap.series.end(), markers.begin(), markers.end());
  report.plots.push_back(std::move(gap));
  // Every point of the revolution is drawn (the whole-run plots are reduced
  // per pixel column): the shape of each impact is what these plots show.
  for (std::size_t i = first_plot; i < report.plots.size(); ++i) report.plots[i].full_resolution = true;
}

/// A constant line across the revolution at height `y`.
Series level_line(std::string label, double y) {
  return {std::move(label), {0.0, 360.0}, {y, y}, "dashes", PlotRole::limit};
}

/// The rigid model's `f(θ)` at the revolution's points, NaN at the wrap.
template <class F>
std::vector<double> rigid_at(const LastRevolution& rev, const TimeSeries& ts, F&& f) {
  std::vector<double> out(rev.index.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t j = 0; j < out.size(); ++j)
    if (rev.index[j] < ts.time.size()) out[j] = f(ts.cam_angle_deg[rev.index[j]] / kRadToDeg);
  return out;
}

/// The last revolution's contact stress (with materials: the dynamic Hertz
/// pressure, the rigid model's and `mechanism.cam.limits.max_contact_stress`),
/// drive torque (dynamic, rigid and the motor's with a shaft) and, for a flat
/// face, the contact point's place across it against its half-width
/// (docs/model.md §8, "Contact stress and drive torque").
void add_stress_torque_plots(const SceneConfig& scene, const Model& model, const SimulationResult& result,
                             Report& report) {
  const TimeSeries& ts = result.series;
  if (ts.time.empty() || !(model.omega > 0.0)) return;
  const LastRevolution rev = last_revolution(ts);
  const auto xrange = std::make_pair(0.0, 360.0);
  const std::size_t first_plot = report.plots.size();
  constexpr double kMPa = 1e-6;                             // Pa → MPa
  const RigidContactForce rigid_force(model, model.omega);  // on a train the held train's (docs/model.md §12)
  if (model.hertz) {
    Plot stress{"Last revolution: contact stress (Hertz) and the rigid model's",
                "cam angle [deg]",
                "contact stress [MPa]",
                {},
                false,
                false,
                xrange};
    if (ts.contact_stress.size() == ts.time.size())
      stress.series.push_back(
          {"contact stress", rev.angle, pick(rev, ts.contact_stress, kMPa), "lines", PlotRole::dynamic});
    stress.series.push_back(
        {"rigid model", rev.angle,
         rigid_at(rev, ts,
                  [&](double theta) { return kMPa * rigid_contact_pressure(model, *model.hertz, rigid_force, theta); }),
         "dashes", PlotRole::rigid});
    if (const std::optional<double> limit = scene.mechanism.cam.limits.max_contact_stress)
      stress.series.push_back(level_line("limit (mechanism.cam.limits.max_contact_stress)", *limit * kMPa));
    report.plots.push_back(std::move(stress));
  }
  Plot torque{"Last revolution: drive torque on the cam and the rigid model's",
              "cam angle [deg]",
              "torque [N m]",
              {},
              false,
              false,
              xrange};
  if (ts.cam_torque.size() == ts.time.size())
    torque.series.push_back({"drive torque", rev.angle, pick(rev, ts.cam_torque), "lines", PlotRole::dynamic});
  torque.series.push_back({"rigid model", rev.angle, rigid_at(rev, ts, [&](double t) { return rigid_force.torque(t); }),
                           "dashes", PlotRole::rigid});
  if (model.drive.shaft() && ts.motor_torque.size() == ts.time.size())
    torque.series.push_back({"motor", rev.angle, pick(rev, ts.motor_torque)});
  report.plots.push_back(std::move(torque));
  if (!model.follower.circle()) {
    const double half_width = 0.5 * model.follower.face_width * 1e3;  // [mm]
    report.plots.push_back(Plot{"Last revolution: contact point across the flat face, with the face's half-width",
                                "cam angle [deg]",
                                "contact offset from the face centre [mm]",
                                {{"contact point", rev.angle, pick(rev, ts.contact_offset, 1e3)},
                                 level_line("face edge (+face_width / 2)", half_width),
                                 level_line("face edge (−face_width / 2)", -half_width)},
                                false,
                                false,
                                xrange});
  }
  for (std::size_t i = first_plot; i < report.plots.size(); ++i) report.plots[i].full_resolution = true;
}

/// The whole run against time: follower motion (the transient), and for a
/// drop test the gap and the contact force; then the energy residual.
void add_run_plots(const Model& model, const SimulationResult& result, Report& report) {
  const TimeSeries& ts = result.series;
  const bool arm = model.follower.oscillating();
  const LengthUnit lift = length_unit({&ts.follower_position, &ts.kinematic_position});
  const double motion_scale = arm ? kRadToDeg : lift.per_metre;
  report.plots.push_back(
      Plot{"Whole run: follower motion against the motion law",
           "time [s]",
           arm ? "arm angle [deg]" : lift.axis("displacement"),
           {{"follower", ts.time, scaled(ts.follower_position, motion_scale), "lines", PlotRole::dynamic},
            {"motion law", ts.time, scaled(ts.kinematic_position, motion_scale), "dashes", PlotRole::rigid}}});
  if (model.omega <= 0.0) {
    const LengthUnit gap_unit = length_unit({&ts.gap});
    report.plots.push_back(Plot{"Gap between follower and cam (> 0 separated, < 0 penetration)",
                                "time [s]",
                                gap_unit.axis("gap"),
                                {{"gap", ts.time, gap_unit.of(ts.gap), "lines", PlotRole::dynamic}}});
    Plot force{"Contact force",
               "time [s]",
               "force [N]",
               {{"contact force", ts.time, ts.contact_force, "lines", PlotRole::dynamic}}};
    if (model.friction.present) force.series.push_back({"friction force", ts.time, ts.friction_force});
    report.plots.push_back(std::move(force));
  } else if (model.friction.present) {
    report.plots.push_back(
        Plot{"Whole run: friction force", "time [s]", "force [N]", {{"friction force", ts.time, ts.friction_force}}});
  }
  report.plots.push_back(Plot{"Energy balance residual (docs/model.md §7)",
                              "time [s]",
                              "(E − E₀) / scale [–]",
                              {{"energy residual", ts.time, ts.energy_residual}}});
}

Table solver_table(const SolverSummary& s) {
  Table solver{"Solver", {"counter", "value"}, {}, false};
  auto count = [&](const char* name, long v) { solver.rows.push_back({name, std::to_string(v)}); };
  count("steps", s.counters.steps);
  count("rhs_evaluations", s.counters.rhs_evaluations);
  count("events", s.events);
  count("restarts", s.counters.reinitialisations);
  count("tracking_resets", s.tracking_resets);
  count("tracking_projections", s.projections);
  count("flights", s.flights);
  count("error_test_failures", s.counters.error_test_failures);
  return solver;
}

/// The train's metrics in the report's table (every one summary.json has,
/// docs/valvetrain.md), with where it lets go first.
void add_train_metric_rows(const Metrics& m, const char* position_unit, const std::optional<CrankScale>& crank,
                           Table& table) {
  if (!m.train) return;
  const TrainMetrics& t = *m.train;
  for_each_train_metric(t, [&](const char* name, double value, bool count, const char* unit) {
    table.rows.push_back({name, count ? std::to_string(static_cast<long>(value)) : format_number(value), unit});
  });
  for (std::size_t i = 0; i < t.bodies.size(); ++i)
    table.rows.push_back({"max_lift_error: " + t.bodies[i], format_number(t.max_lift_error[i]), position_unit});
  if (t.lash) table.rows.push_back({"held_open", t.held_open ? "yes" : "no", "–"});
  table.rows.push_back({"separates_first",
                        t.separates_first.empty()
                            ? "nowhere (no float)"
                            : t.separates_first + " at " + angle_text(t.separates_first_deg, crank),
                        "–"});
}

}  // namespace

Report simulation_report(const SceneConfig& scene, const Model& model, const SimulationResult& result) {
  const Metrics& m = result.metrics;
  Report report;
  report.title = "camdyn: " + scene.name;
  std::string follower = follower_name(model);
  for (char& c : follower)
    if (c == '_') c = ' ';
  report.subtitle = "simulate — " + follower + " follower, contact model " + to_string(scene.mechanism.contact.model);
  report.verdict = simulation_verdict(scene, model, result);
  report.facts = {{"cam speed", format(scene.mechanism.cam.rpm, "rpm")},
                  {jump_speed_name(model), std::isnan(m.jump_speed_rpm) ? jump_speed_text(m.jump_speed_rpm, 6)
                                                                        : format(m.jump_speed_rpm, "rpm")},
                  {"simulated", format(result.end_time, "s")},
                  {"metrics from", format(result.evaluated_from, "s")},
                  {"integrator", result.solver.method + ", rtol " + format(result.solver.rtol)},
                  {"run time", format(result.solver.run_time_s, "s")},
                  {"energy residual", format(m.energy_residual)}};

  Table metrics{result.metrics_over == "periodic_orbit" ? "Metrics (one period of the periodic orbit)"
                                                        : "Metrics (evaluated cycles)",
                {"metric", "value", "unit"},
                {},
                true};
  const CoordinateUnits units = coordinate_units(model);
  for_each_metric(m, [&](const char* name, const auto& value, const MetricInfo& info) {
    if (const std::optional<double> v = metric_value(value))
      metrics.rows.push_back({name, format(*v), info.in_coordinate ? units.position : info.unit});
  });
  add_train_metric_rows(m, units.position, scene_crank_scale(scene), metrics);
  report.tables.push_back(std::move(metrics));

  if (model.omega > 0.0) add_revolution_plots(model, result, report);
  add_stress_torque_plots(scene, model, result, report);
  add_run_plots(model, result, report);
  add_train_plots(scene, model, result, report);
  // The cam itself: to scale, its pressure angle and curvature with the scene's limits, the law's SVAJ.
  for (Plot& plot : cam_plots(model, scene.mechanism.cam.limits, scene.mechanism.cam.rpm))
    report.plots.push_back(std::move(plot));
  if (model.contour) add_contour_fit(model, report);
  add_valvetrain_report(scene, model, report, &result);
  report.appendix.push_back(solver_table(result.solver));
  report.notes.push_back("Model: " + std::to_string(model.layout.size) + " states; elements assembled: " + [&] {
    std::string list;
    for (const auto& e : model.elements) list += (list.empty() ? "" : ", ") + e;
    return list;
  }());
  return report;
}

void write_timeseries_csv(const std::filesystem::path& path, const TimeSeries& series) {
  CsvWriter csv(path, series.all_names());
  csv.rows_from_columns(series.all_columns());
  csv.commit();
}

void write_events_csv(const std::filesystem::path& path, const std::vector<ContactEvent>& events) {
  CsvWriter csv(path, {"time", "cam_angle_deg", "kind", "speed", "impact", "grazing", "lash", "cause"});
  for (const ContactEvent& e : events)
    csv.row({CsvCell(e.time), CsvCell(e.cam_angle_deg), CsvCell(e.onset ? "onset" : "separation"), CsvCell(e.speed),
             CsvCell(e.impact ? 1 : 0), CsvCell(e.grazing ? 1 : 0), CsvCell(e.lash ? 1 : 0),
             CsvCell(std::string(enum_name(e.cause)))});
  csv.commit();
}

void write_simulation_outputs(const std::filesystem::path& dir, const SceneConfig& scene, const Model& model,
                              const SimulationResult& result) {
  std::filesystem::create_directories(dir);
  // timeseries.csv (number formatting, then the disk's fsync) is written on a
  // thread of its own while the report waits for its gnuplot processes; the
  // report is renamed into place last, once everything else is there.
  std::string html;
  parallel_for(2, 2, [&](std::size_t job) {
    if (job == 0) {
      write_timeseries_csv(dir / "timeseries.csv", result.series);
    } else {
      write_events_csv(dir / "events.csv", result.events);
      write_json_atomic(dir / "summary.json", summary_json(scene, model, result));
      html = render_html(simulation_report(scene, model, result));
    }
  });
  write_file_atomic(dir / "report.html", html);
}

}  // namespace camdyn
