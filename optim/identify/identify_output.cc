#include "optim/identify/identify_output.h"

#include <camdyn/version.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dynamics/coordinate_units.h"
#include "io/csv_writer.h"
#include "io/json_writer.h"
#include "output/cam_plots.h"

namespace camdyn::optim {

namespace {

Json finite_json(double v) { return std::isfinite(v) ? Json(v) : Json(nullptr); }
Json optional_json(const std::optional<double>& v) { return v && std::isfinite(*v) ? Json(*v) : Json(nullptr); }

std::optional<double> relative_std_error(const ParameterEstimate& p) {
  if (!p.std_error || p.value == 0.0) return std::nullopt;
  return *p.std_error / std::abs(p.value);
}

/// Signals of all experiments, in order of first appearance (the fit.csv columns).
std::vector<std::string> all_signals(const IdentifyResult& result) {
  std::vector<std::string> signals;
  for (const ExperimentFit& fit : result.fits)
    for (const std::string& s : fit.signals)
      if (std::find(signals.begin(), signals.end(), s) == signals.end()) signals.push_back(s);
  return signals;
}

std::string cell(const std::optional<double>& v, int digits = 6) { return v ? format_number(*v, digits) : "–"; }

/// Plot units: signals in SI, time in ms (impacts last fractions of a
/// millisecond). The follower columns are in the unit of q: an arm's in rad
/// (coordinate_units.h); gap and contact offset are lengths at the contact.
const char* unit_of(const std::string& signal, const CoordinateUnits& units) {
  if (signal == "contact_force" || signal == "friction_force") return "N";
  if (signal == "follower_position" || signal == "kinematic_position") return units.position;
  if (signal == "follower_velocity") return units.velocity;
  if (signal == "follower_acceleration") return units.acceleration;
  if (signal == "cam_angle_deg") return "deg";
  if (signal == "cam_speed_rpm") return "rpm";
  if (signal == "energy_residual") return "–";
  return "m";
}

/// A parameter's name, with its unit when that depends on the follower
/// (the spring, the damper, ...: N m/rad for an arm).
std::string parameter_label(const ParameterEstimate& p, const CoordinateUnits& units) {
  const std::string unit = coordinate_field_unit(p.path, units);
  return unit.empty() ? p.name : p.name + " [" + unit + "]";
}

/// The identified scene's cam to scale with its SVAJ: at the speed of the
/// records when they share one, else per radian of cam angle.
void add_cam(const IdentifyProblem& problem, const IdentifyResult& result, Report& report) {
  const SceneConfig& scene = result.identified_scene;
  const double rpm = scene.mechanism.cam.rpm;
  const bool one_speed = std::all_of(problem.experiments.begin(), problem.experiments.end(),
                                     [rpm](const FitExperiment& e) { return e.scene.mechanism.cam.rpm == rpm; });
  for (Plot& plot : scene_cam_plots(scene, problem.config_file, one_speed ? rpm : 0.0, "the identified scene"))
    report.plots.push_back(std::move(plot));
}

}  // namespace

Json identified_json(const IdentifyProblem& problem, const IdentifyResult& result, const Json& resolved_config) {
  Json j;
  j["name"] = problem.scene.name;
  j["study"] = "identify";
  j["camdyn_version"] = CAMDYN_VERSION;
  Json parameters = Json::object();
  for (const ParameterEstimate& p : result.parameters) {
    parameters[p.name] = Json{{"value", p.value},
                              {"std_error", optional_json(p.std_error)},
                              {"lower", optional_json(p.lower)},
                              {"upper", optional_json(p.upper)},
                              {"initial", p.initial},
                              {"relative_std_error", optional_json(relative_std_error(p))},
                              {"log_scale", p.log_scale},
                              {"path", p.path},
                              {"at_bound", p.at_bound},
                              {"identifiable", p.identifiable}};
  }
  j["parameters"] = parameters;
  j["final_cost"] = result.final_cost;
  j["initial_cost"] = result.initial_cost;
  j["rms_residual"] = result.rms_residual;
  j["residual_sigma"] = finite_json(result.residual_sigma);
  j["residuals"] = result.residuals;
  j["iterations"] = result.iterations;
  j["termination"] = result.termination;
  j["message"] = result.message;
  j["run_time_s"] = result.run_time_s;
  j["simulations"] = result.simulations;
  j["reused_points"] = result.reused_points;
  j["resumed_simulations"] = result.resumed_simulations;
  Json stages = Json::array();
  for (const StageSummary& st : result.stages)
    stages.push_back(Json{{"smoothing_s", st.smoothing_s},
                          {"iterations", st.iterations},
                          {"initial_cost", st.initial_cost},
                          {"final_cost", st.final_cost},
                          {"termination", st.termination},
                          {"values", st.values}});
  j["stages"] = stages;
  j["identifiable"] = result.identifiable;
  j["poor_fit"] = result.poor_fit;
  j["misfit_ratio"] = finite_json(result.misfit_ratio);
  Json starts = Json::array();
  for (const FitStart& s : result.starts)
    starts.push_back(Json{{"initial", s.initial},
                          {"values", s.values},
                          {"final_cost", s.error.empty() ? Json(s.final_cost) : Json()},
                          {"poor_fit", s.poor_fit},
                          {"error", s.error}});
  j["starts"] = starts;
  j["warnings"] = result.warnings;
  Json names = Json::array();
  Json matrix = Json::array();
  for (std::size_t i = 0; i < result.parameters.size(); ++i) {
    names.push_back(result.parameters[i].name);
    Json row = Json::array();
    for (const std::optional<double>& c : result.correlation[i]) row.push_back(optional_json(c));
    matrix.push_back(row);
  }
  j["correlation"] = Json{{"parameters", names}, {"matrix", matrix}};
  Json singular = Json::array();
  for (double s : result.singular_values) singular.push_back(s);
  j["jacobian"] = Json{{"singular_values", singular},
                       {"condition_number", finite_json(result.condition_number)},
                       {"note", "columns normalised to unit length, scaled parameters (ln p for log_scale)"}};
  j["loss"] = Json{{"type", result.loss}, {"scale", result.loss == "none" ? Json(nullptr) : Json(result.loss_scale)}};
  Json experiments = Json::array();
  for (std::size_t k = 0; k < result.fits.size(); ++k) {
    const ExperimentFit& fit = result.fits[k];
    const FitExperiment& e = problem.experiments[k];
    Json signals = Json::object();
    for (std::size_t s = 0; s < fit.signals.size(); ++s) {
      signals[fit.signals[s]] = Json{{"column", e.reference.signals[s].second},
                                     {"weight", fit.weights[s]},
                                     {"rms_error", fit.rms_error[s]},
                                     {"noise_estimate", fit.noise[s]}};
    }
    experiments.push_back(
        Json{{"name", fit.name}, {"file", e.reference.file}, {"samples", fit.time.size()}, {"signals", signals}});
  }
  j["experiments"] = experiments;
  j["config"] = resolved_config;
  return j;
}

Json identified_scene_json(const IdentifyProblem& problem, const IdentifyResult& result) {
  SceneConfig scene = result.identified_scene;
  scene.name = problem.scene.name + "_identified";
  scene.study = "simulate";
  Json j = to_json(scene);
  std::string what;
  for (const ParameterEstimate& p : result.parameters) what += (what.empty() ? "" : ", ") + p.name;
  j["description"] = "the scene of " + problem.config_file + " with " + what + " identified by camdyn identify";
  return j;
}

/// The banner: each parameter with its standard error, or which ones the data cannot pin down.
Verdict identify_verdict(const IdentifyResult& result) {
  Verdict v;
  v.tone = result.poor_fit ? Verdict::Tone::bad : result.identifiable ? Verdict::Tone::good : Verdict::Tone::warning;
  std::string values, unpinned;
  for (const ParameterEstimate& p : result.parameters) {
    values += (values.empty() ? "" : ", ") + p.name + " = " + format_number(p.value, 5) +
              (p.std_error ? " ± " + format_number(*p.std_error, 2) : "");
    if (!p.identifiable) unpinned += (unpinned.empty() ? "" : ", ") + p.name;
  }
  v.headline = result.poor_fit ? "NOT identified: poor fit, a local minimum is likely (misfit " +
                                     format_number(result.misfit_ratio, 3) + " times the noise variance): " + values
               : result.identifiable
                   ? "identified: " + values
                   : "NOT identifiable" + (unpinned.empty() ? "" : " (" + unpinned + ")") + ": " + values;
  if (result.starts.size() > 1)
    v.details.push_back("best of " + std::to_string(result.starts.size()) + " starts (solver.starts)");
  v.details.push_back("termination " + result.termination + " after " + std::to_string(result.iterations) +
                      " iterations; RMS residual (weighted) " + format_number(result.rms_residual, 4));
  return v;
}

Report identify_report(const IdentifyProblem& problem, const IdentifyResult& result) {
  Report report;
  report.verdict = identify_verdict(result);
  report.title = "camdyn: " + problem.scene.name;
  report.subtitle = "identify — " + std::to_string(result.parameters.size()) + " parameters fitted to " +
                    std::to_string(result.fits.size()) + " record" + (result.fits.size() == 1 ? "" : "s") +
                    ", contact model " + to_string(problem.scene.mechanism.contact.model);
  report.facts = {{"verdict", result.identifiable ? "identifiable" : "NOT identifiable (see the notes)"},
                  {"termination", result.termination},
                  {"iterations", std::to_string(result.iterations)},
                  {"final cost", format_number(result.final_cost)},
                  {"RMS residual (weighted)", format_number(result.rms_residual)},
                  {"measured values", std::to_string(result.residuals)},
                  {"simulations", std::to_string(result.simulations) + " (" + std::to_string(result.reused_points) +
                                      " points reused)"},
                  {"loss", result.loss == "none" ? "none (least squares)"
                                                 : result.loss + ", scale " + format_number(result.loss_scale)},
                  {"run time", format_number(result.run_time_s, 3) + " s"}};

  Table params{"Identified parameters (± one standard error)",
               {"parameter", "initial", "identified", "std error", "relative", "lower", "upper", "note"},
               {},
               true};
  for (const ParameterEstimate& p : result.parameters) {
    const std::optional<double> rel = relative_std_error(p);
    std::string note = p.identifiable ? "" : "not identifiable";
    if (p.at_bound) note += std::string(note.empty() ? "" : "; ") + "on a bound";
    if (p.log_scale) note += std::string(note.empty() ? "" : "; ") + "log scale";
    params.rows.push_back({parameter_label(p, coordinate_units(problem.scene)), format_number(p.initial),
                           format_number(p.value, 8), cell(p.std_error, 3),
                           rel ? format_number(100.0 * *rel, 3) + " %" : "–", cell(p.lower), cell(p.upper), note});
  }
  report.tables.push_back(std::move(params));

  if (result.parameters.size() > 1) {
    Table corr{"Correlation of the estimates", {"parameter"}, {}, false};
    for (const ParameterEstimate& p : result.parameters) corr.columns.push_back(p.name);
    for (std::size_t i = 0; i < result.parameters.size(); ++i) {
      std::vector<std::string> row{result.parameters[i].name};
      for (const std::optional<double>& c : result.correlation[i]) row.push_back(cell(c, 4));
      corr.rows.push_back(std::move(row));
    }
    report.tables.push_back(std::move(corr));
  }

  Table records{
      "Records", {"experiment", "file", "samples", "signal", "weight", "RMS misfit", "noise estimate"}, {}, true};
  for (std::size_t k = 0; k < result.fits.size(); ++k) {
    const ExperimentFit& fit = result.fits[k];
    const CoordinateUnits units = coordinate_units(problem.experiments[k].scene);
    for (std::size_t s = 0; s < fit.signals.size(); ++s) {
      const std::string unit = unit_of(fit.signals[s], units);
      const std::string per_unit = unit.find('/') == std::string::npos ? "1/" + unit : "1/(" + unit + ")";
      records.rows.push_back({fit.name, problem.experiments[k].reference.file, std::to_string(fit.time.size()),
                              fit.signals[s], format_number(fit.weights[s], 4) + " " + per_unit,
                              format_number(fit.rms_error[s], 4) + " " + unit,
                              format_number(fit.noise[s], 4) + " " + unit});
    }
  }
  report.tables.push_back(std::move(records));

  for (std::size_t k = 0; k < result.fits.size(); ++k) {
    const ExperimentFit& fit = result.fits[k];
    const CoordinateUnits units = coordinate_units(problem.experiments[k].scene);
    std::vector<double> t_ms(fit.time.size());
    for (std::size_t i = 0; i < t_ms.size(); ++i) t_ms[i] = 1e3 * fit.time[i];
    for (std::size_t s = 0; s < fit.signals.size(); ++s) {
      const std::string ylabel = CoordinateUnits::axis(fit.signals[s], unit_of(fit.signals[s], units));
      Plot plot;
      plot.title = fit.name + ": " + fit.signals[s] + ", measured and fitted";
      plot.xlabel = "time [ms]";
      plot.ylabel = ylabel;
      plot.series = {{"measured", t_ms, fit.measured[s], "points", PlotRole::measured},
                     {"fitted", t_ms, fit.fitted[s], "lines", PlotRole::fitted}};
      report.plots.push_back(std::move(plot));
      Plot residual;
      residual.title = fit.name + ": " + fit.signals[s] + ", residual (fitted − measured)";
      residual.xlabel = "time [ms]";
      residual.ylabel = ylabel;
      std::vector<double> r(fit.time.size());
      for (std::size_t i = 0; i < r.size(); ++i) r[i] = fit.fitted[s][i] - fit.measured[s][i];
      residual.series = {{"residual", t_ms, r, "points"}};
      report.plots.push_back(std::move(residual));
    }
  }
  add_cam(problem, result, report);

  report.notes = result.warnings;
  report.notes.push_back(
      "Standard errors: covariance (JᵀJ)⁻¹ of the Jacobian at the optimum (central finite differences of whole "
      "simulations), scaled by the residual variance 2·cost/(N − p) = " +
      format_number(result.residual_sigma * result.residual_sigma, 4) +
      " (weights normalise each signal by its RMS; they do not know the noise). Log-scale parameters are converted by "
      "the delta method. They assume independent noise and a model that can reproduce the data.");
  report.notes.push_back("Termination: " + result.message);
  return report;
}

void write_identify_outputs(const std::filesystem::path& out_dir, const IdentifyProblem& problem,
                            const IdentifyResult& result, const Json& resolved_config) {
  std::filesystem::create_directories(out_dir);
  write_json_atomic(out_dir / "identified.json", identified_json(problem, result, resolved_config));
  write_json_atomic(out_dir / "identified_scene.json", identified_scene_json(problem, result));

  const std::vector<std::string> signals = all_signals(result);
  std::vector<std::string> columns{"time", "experiment"};
  for (const std::string& s : signals) {
    columns.push_back(s + "_measured");
    columns.push_back(s + "_fitted");
  }
  CsvWriter csv(out_dir / "fit.csv", columns);
  std::vector<CsvCell> row;
  for (const ExperimentFit& fit : result.fits) {
    for (std::size_t i = 0; i < fit.time.size(); ++i) {
      row.clear();
      row.emplace_back(fit.time[i]);
      row.emplace_back(fit.name);
      for (const std::string& s : signals) {
        const auto it = std::find(fit.signals.begin(), fit.signals.end(), s);
        if (it == fit.signals.end()) {  // this experiment does not record the signal
          row.emplace_back(std::string());
          row.emplace_back(std::string());
          continue;
        }
        const auto k = static_cast<std::size_t>(it - fit.signals.begin());
        row.emplace_back(fit.measured[k][i]);
        row.emplace_back(fit.fitted[k][i]);
      }
      csv.row(row);
    }
  }
  csv.commit();
  write_report(out_dir / "report.html", identify_report(problem, result));
}

}  // namespace camdyn::optim
