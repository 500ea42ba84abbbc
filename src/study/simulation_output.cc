#include "study/simulation_output.h"

#include <camdyn/version.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <type_traits>

#include "io/csv_writer.h"
#include "io/json_writer.h"

namespace camdyn {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

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

Json metrics_json(const Metrics& m) {
  Json j = Json::object();
  for_each_metric(m, [&](const char* name, const auto& value, const MetricInfo& info) {
    if constexpr (std::is_floating_point_v<std::remove_cvref_t<decltype(value)>>)
      j[name] = info.infinite_is_null ? finite_or_null(value) : Json(value);
    else
      j[name] = value;
  });
  return j;
}

double rigid_contact_force(const Model& model, double theta) { return rigid_normal_force(model, theta); }

std::string follower_name(const Model& model) {
  const FollowerGeometry& f = model.follower;
  return std::string(f.oscillating() ? "oscillating_" : "translating_") + to_string(f.shape);
}

std::string drive_name(const Model& model) {
  if (model.drive == Drive::shaft)
    return model.motor == Motor::torque_speed ? "shaft:torque_speed_motor" : "shaft:constant_speed_motor";
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
                           {"tracking", model.tracking == Tracking::newton ? "newton" : "differential"},
                           {"simulated_time_s", result.end_time},
                           {"evaluated_from_s", result.evaluated_from},
                           {"termination", to_string(s.termination)},
                           {"message", s.message}};
  summary["model"] = Json{{"state_size", model.layout.size},
                          {"states", model.layout.names},
                          {"elements", model.elements},
                          {"quadratures", {"drive_work", "damper_work", "hysteresis_work", "friction_work"}},
                          {"cam", drive_name(model)},
                          {"follower", follower_name(model)},
                          {"contact_pair", contact_pair_name(model)}};
  if (model.contour) summary["contour_fit"] = contour_fit_json(model);
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
  Series curve{"fitted spline", {}, {}, "lines"}, points{"given points", {}, {}, "points"};
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
    residual.y.push_back(distances[i] * 1e6);
  }
  report.plots.push_back(Plot{"Cam contour: given points and fitted spline (cam frame at angle 0)",
                              "x [mm]",
                              "y [mm]",
                              {std::move(curve), std::move(points)}});
  report.plots.push_back(Plot{"Contour fit residual per point", "point index", "residual [µm]", {std::move(residual)}});
}

}  // namespace

Report simulation_report(const SceneConfig& scene, const Model& model, const SimulationResult& result) {
  const Metrics& m = result.metrics;
  const TimeSeries& ts = result.series;
  Report report;
  report.title = "camdyn: " + scene.name;
  std::string follower = follower_name(model);
  for (char& c : follower)
    if (c == '_') c = ' ';
  report.subtitle = "simulate — " + follower + " follower, contact model " + to_string(scene.mechanism.contact.model);
  report.facts = {{"cam speed", format(scene.mechanism.cam.rpm, "rpm")},
                  {"rigid-model jump speed", format(m.jump_speed_rpm, "rpm")},
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
  for_each_metric(m, [&](const char* name, const auto& value, const MetricInfo& info) {
    metrics.rows.push_back({name, format(static_cast<double>(value)), info.unit});
  });
  report.tables.push_back(std::move(metrics));

  const SolverSummary& s = result.solver;
  Table solver{"Solver", {"counter", "value"}, {}, false};
  auto count = [&](const char* name, long v) { solver.rows.push_back({name, std::to_string(v)}); };
  count("steps", s.counters.steps);
  count("rhs_evaluations", s.counters.rhs_evaluations);
  count("events", s.events);
  count("restarts", s.counters.reinitialisations);
  count("tracking_resets", s.tracking_resets);
  count("tracking_projections", s.projections);
  count("error_test_failures", s.counters.error_test_failures);
  report.tables.push_back(std::move(solver));

  // Time-series plots against cam angle (or time when the cam stands still).
  const bool by_angle = model.omega > 0.0;
  const std::vector<double>& x = by_angle ? ts.cam_angle_deg : ts.time;
  const std::string xlabel = by_angle ? "cam angle [deg]" : "time [s]";
  auto scaled = [](const std::vector<double>& v, double k) {
    std::vector<double> out(v.size());
    for (size_t i = 0; i < v.size(); ++i) out[i] = v[i] * k;
    return out;
  };
  const bool arm = model.follower.oscillating();  // follower columns in rad: plotted in degrees
  const double motion_scale = arm ? kRadToDeg : 1e3;
  report.plots.push_back(Plot{"Follower motion against the motion law",
                              xlabel,
                              arm ? "arm angle [deg]" : "displacement [mm]",
                              {{"follower", x, scaled(ts.follower_position, motion_scale)},
                               {"motion law", x, scaled(ts.kinematic_position, motion_scale)}}});
  report.plots.push_back(Plot{"Gap between roller and cam (> 0 separated, < 0 penetration)",
                              xlabel,
                              "gap [µm]",
                              {{"gap", x, scaled(ts.gap, 1e6)}}});
  Plot force{"Contact force", xlabel, "force [N]", {{"contact force", x, ts.contact_force}}};
  if (by_angle) {
    std::vector<double> rigid(x.size());
    for (size_t i = 0; i < x.size(); ++i) rigid[i] = rigid_contact_force(model, x[i] / kRadToDeg);
    force.series.push_back({"rigid model", x, rigid});
  }
  if (model.contact_friction) force.series.push_back({"friction force", x, ts.friction_force});
  report.plots.push_back(std::move(force));
  report.plots.push_back(Plot{"Energy balance residual (physics.md §5)",
                              "time [s]",
                              "(E − E₀) / scale [–]",
                              {{"energy residual", ts.time, ts.energy_residual}}});
  if (model.contour) add_contour_fit(model, report);
  report.notes.push_back("Model: " + std::to_string(model.layout.size) + " states; elements assembled: " + [&] {
    std::string list;
    for (const auto& e : model.elements) list += (list.empty() ? "" : ", ") + e;
    return list;
  }());
  return report;
}

void write_simulation_outputs(const std::filesystem::path& dir, const SceneConfig& scene, const Model& model,
                              const SimulationResult& result) {
  std::filesystem::create_directories(dir);
  {
    CsvWriter csv(dir / "timeseries.csv", TimeSeries::column_names());
    const auto columns = result.series.columns();
    std::vector<double> row(columns.size());
    for (size_t i = 0; i < result.series.time.size(); ++i) {
      for (size_t c = 0; c < columns.size(); ++c) row[c] = (*columns[c])[i];
      csv.row(std::span<const double>(row));
    }
    csv.commit();
  }
  {
    CsvWriter csv(dir / "events.csv", {"time", "cam_angle_deg", "kind", "speed", "impact"});
    for (const ContactEvent& e : result.events)
      csv.row({CsvCell(e.time), CsvCell(e.cam_angle_deg), CsvCell(e.onset ? "onset" : "separation"), CsvCell(e.speed),
               CsvCell(e.impact ? 1 : 0)});
    csv.commit();
  }
  write_json_atomic(dir / "summary.json", summary_json(scene, model, result));
  write_report(dir / "report.html", simulation_report(scene, model, result));
}

}  // namespace camdyn
