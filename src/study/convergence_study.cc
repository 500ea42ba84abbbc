#include "study/convergence_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <mutex>
#include <numbers>
#include <optional>

#include "common/errors.h"
#include "dynamics/simulation.h"
#include "integrate/integrator.h"
#include "io/csv_writer.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "io/report.h"
#include "common/parallel.h"

namespace camdyn {

namespace {

/// A variant of the study's scene: `set` holds "dotted.path=VALUE" assignments.
struct SceneVariant {
  std::string name = "base";
  std::vector<std::string> set;
  std::optional<std::vector<double>> tolerances;  ///< overrides the study's for this scene
  std::optional<double> reference_rtol;           ///< overrides reference.rtol for this scene
  std::optional<std::vector<double>> rk4_steps_deg;  ///< overrides the study's for this scene
};

struct ReferenceConfig {
  IntegrationMethod method = IntegrationMethod::cvode_bdf;
  double rtol = 1e-12;
};

struct ConvergenceConfig {
  std::vector<IntegrationMethod> methods = {IntegrationMethod::cvode_bdf, IntegrationMethod::cvode_adams,
                                            IntegrationMethod::arkode_erk, IntegrationMethod::arkode_dirk,
                                            IntegrationMethod::rk4};
  std::vector<double> tolerances = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  ReferenceConfig reference;
  std::vector<Tracking> tracking = {Tracking::differential, Tracking::newton};
  double atol_factor = 1e-4;  ///< atol = rtol × atol_factor (state scale [m])
  /// rk4 has no tolerance: its fixed steps, in degrees of cam angle.
  std::vector<double> rk4_steps_deg = {0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625};
  std::vector<SceneVariant> scenes = {SceneVariant{}};
};

template <class A>
void visit(A& a, SceneVariant& v) {
  a.field("name", v.name, non_empty());
  a.field("set", v.set);
  a.field("tolerances", v.tolerances, non_empty(), open_closed(0, 0.1));
  a.field("reference_rtol", v.reference_rtol, open_closed(0, 0.1));
  a.field("rk4_steps_deg", v.rk4_steps_deg, non_empty(), positive());
}

template <class A>
void visit(A& a, ReferenceConfig& r) {
  a.field("method", r.method);
  a.field("rtol", r.rtol, open_closed(0, 0.1));
}

template <class A>
void visit(A& a, ConvergenceConfig& c) {
  a.field("methods", c.methods, non_empty());
  a.field("tolerances", c.tolerances, non_empty(), open_closed(0, 0.1));
  a.field("reference", c.reference);
  a.field("tracking", c.tracking, non_empty());
  a.field("atol_factor", c.atol_factor, positive());
  a.field("rk4_steps_deg", c.rk4_steps_deg, non_empty(), positive());
  a.field("scenes", c.scenes, non_empty());
}

const std::vector<std::string> kStudyKeys = {"methods", "tolerances", "reference", "tracking",
                                             "atol_factor", "rk4_steps_deg", "scenes"};

struct Run {
  size_t scene = 0;
  IntegrationMethod method = IntegrationMethod::cvode_bdf;
  Tracking tracking = Tracking::differential;
  double rtol = 0.0;  ///< 0 for rk4
  double step = 0.0;  ///< rk4 fixed step [s]
  // results
  bool ok = false;
  std::string error;
  double error_position = 0.0, error_peak_force = 0.0, energy_residual = 0.0, run_time_s = 0.0;
  long steps = 0, rhs_evaluations = 0;
};

SceneConfig configure(SceneConfig scene, IntegrationMethod method, Tracking tracking, double rtol,
                      double atol_factor, double step) {
  scene.integrator.method = method;
  scene.mechanism.contact.tracking = tracking;
  if (method == IntegrationMethod::rk4) {
    scene.integrator.step = step;
  } else {
    scene.integrator.rtol = rtol;
    scene.integrator.atol = rtol * atol_factor;
  }
  return scene;
}

double max_position_error(const SimulationResult& run, const SimulationResult& reference) {
  double worst = 0.0;
  const size_t n = std::min(run.series.time.size(), reference.series.time.size());
  for (size_t i = 0; i < n; ++i) {
    if (reference.series.time[i] < reference.evaluated_from) continue;
    worst = std::max(worst, std::abs(run.series.follower_position[i] - reference.series.follower_position[i]));
  }
  return worst;
}

std::string format_number4(double v) { return format_number(v, 4); }

Run make_run(size_t scene, IntegrationMethod method, Tracking tracking, double rtol, double step) {
  Run r;
  r.scene = scene;
  r.method = method;
  r.tracking = tracking;
  r.rtol = rtol;
  r.step = step;
  return r;
}

}  // namespace

int run_convergence_study(const Json& doc, const StudyContext& ctx) {
  Json study_json;
  const SceneConfig base = scene_from_study_json(doc, ctx.source, kStudyKeys, study_json);
  ConvergenceConfig config;
  JsonReader reader(study_json, "", ctx.source);
  visit(reader, config);
  reader.finish();

  // The scene variants, each validated like a scene of its own.
  std::vector<SceneConfig> scenes;
  for (size_t k = 0; k < config.scenes.size(); ++k) {
    Json variant = to_json(base);
    for (const std::string& assignment : config.scenes[k].set) apply_assignment(variant, assignment);
    try {
      scenes.push_back(scene_from_json(variant, ctx.source));
      build_model(scenes.back(), ctx.config_file);
    } catch (const InputError& e) {
      throw InputError(ctx.config_file, "scenes[" + std::to_string(k) + "].set",
                       std::string("scene '") + config.scenes[k].name + "': " + e.what());
    }
  }
  JsonWriter writer;
  visit(writer, config);
  if (ctx.validate_only) {
    std::cout << dump_json(resolved_study_json(base, "convergence", writer.json()));
    return 0;
  }

  const auto wall_start = std::chrono::steady_clock::now();
  const int threads = ctx.threads();
  // Reference runs.
  std::vector<SimulationResult> references(scenes.size());
  parallel_for(scenes.size(), threads, [&](size_t k) {
    SceneConfig s = configure(scenes[k], config.reference.method, config.tracking.front(),
                              config.scenes[k].reference_rtol.value_or(config.reference.rtol), config.atol_factor, 0.0);
    try {
      references[k] = simulate_scene(s, ctx.config_file);
      throw_if_failed(references[k]);
    } catch (const NumericalError& e) {
      throw NumericalError("reference run of scene '" + config.scenes[k].name + "' failed: " + e.what());
    }
  });

  std::vector<Run> runs;
  for (size_t k = 0; k < scenes.size(); ++k) {
    const double omega = scenes[k].mechanism.cam.rpm * 2 * std::numbers::pi / 60;
    for (const IntegrationMethod method : config.methods)
      for (const Tracking tracking : config.tracking) {
        if (method == IntegrationMethod::rk4) {
          for (double deg : config.scenes[k].rk4_steps_deg.value_or(config.rk4_steps_deg)) {
            runs.push_back(make_run(k, method, tracking, 0.0,
                                    omega > 0 ? deg * std::numbers::pi / 180 / omega : deg * 1e-6));
          }
        } else {
          for (double tol : config.scenes[k].tolerances.value_or(config.tolerances))
            runs.push_back(make_run(k, method, tracking, tol, 0.0));
        }
      }
  }

  std::mutex progress_mutex;
  size_t done = 0;
  parallel_for(runs.size(), threads, [&](size_t i) {
    Run& r = runs[i];
    const SceneConfig s = configure(scenes[r.scene], r.method, r.tracking, r.rtol, config.atol_factor, r.step);
    try {
      const SimulationResult result = simulate_scene(s, ctx.config_file);
      throw_if_failed(result);
      const SimulationResult& ref = references[r.scene];
      r.error_position = max_position_error(result, ref);
      r.error_peak_force = std::abs(result.metrics.peak_contact_force / ref.metrics.peak_contact_force - 1.0);
      r.energy_residual = result.metrics.energy_residual;
      r.run_time_s = result.solver.run_time_s;
      r.steps = result.solver.counters.steps;
      r.rhs_evaluations = result.solver.counters.rhs_evaluations;
      r.ok = std::isfinite(r.error_position) && std::isfinite(r.error_peak_force);
      if (!r.ok) r.error = "non-finite error";
    } catch (const std::exception& e) {
      r.error = e.what();
    }
    if (ctx.progress) {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      std::fprintf(stderr, "\r  convergence: %zu / %zu runs", ++done, runs.size());
      if (done == runs.size()) std::fprintf(stderr, "\n");
    }
  });

  // Outputs.
  std::filesystem::create_directories(ctx.out_dir);
  CsvWriter csv(ctx.out_dir / "work_precision.csv",
                {"scene", "method", "tracking", "rtol", "step", "error_position", "error_peak_force",
                 "energy_residual", "run_time_s", "steps", "rhs_evaluations", "status", "error"});
  for (const Run& r : runs) {
    const bool fixed = r.method == IntegrationMethod::rk4;
    csv.row({CsvCell(config.scenes[r.scene].name), CsvCell(to_string(r.method)), CsvCell(to_string(r.tracking)),
             fixed ? CsvCell("") : CsvCell(r.rtol), fixed ? CsvCell(r.step) : CsvCell(""),
             r.ok ? CsvCell(r.error_position) : CsvCell(""), r.ok ? CsvCell(r.error_peak_force) : CsvCell(""),
             r.ok ? CsvCell(r.energy_residual) : CsvCell(""), CsvCell(r.run_time_s), CsvCell(r.steps),
             CsvCell(r.rhs_evaluations), CsvCell(r.ok ? "ok" : "failed"), CsvCell(r.error)});
  }
  csv.commit();

  Report report;
  report.title = "camdyn: " + base.name + " — error against run time";
  report.subtitle = "convergence study: every method × tracking mode × tolerance against a reference run (" +
                    to_string(config.reference.method) + ", rtol " + format_number4(config.reference.rtol) + ")";
  const long failed = std::count_if(runs.begin(), runs.end(), [](const Run& r) { return !r.ok; });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  report.facts.emplace_back("runs", std::to_string(runs.size()));
  report.facts.emplace_back("failed", std::to_string(failed));
  report.facts.emplace_back("wall time", format_number4(wall) + " s");
  for (size_t k = 0; k < scenes.size(); ++k) {
    Plot time_plot, rhs_plot;
    time_plot.title = "Work-precision, scene '" + config.scenes[k].name + "': position error against run time";
    time_plot.xlabel = "run time [s]";
    time_plot.ylabel = "max |y − y_ref| [m]";
    time_plot.logx = time_plot.logy = true;
    rhs_plot = time_plot;
    rhs_plot.title = "Scene '" + config.scenes[k].name + "': position error against RHS evaluations";
    rhs_plot.xlabel = "right-hand-side evaluations";
    for (const IntegrationMethod method : config.methods)
      for (const Tracking tracking : config.tracking) {
        Series by_time{to_string(method) + " / " + to_string(tracking), {}, {}, "linespoints"};
        Series by_rhs = by_time;
        for (const Run& r : runs)
          if (r.scene == k && r.method == method && r.tracking == tracking && r.ok && r.error_position > 0) {
            by_time.x.push_back(r.run_time_s);
            by_time.y.push_back(r.error_position);
            by_rhs.x.push_back(static_cast<double>(r.rhs_evaluations));
            by_rhs.y.push_back(r.error_position);
          }
        time_plot.series.push_back(std::move(by_time));
        rhs_plot.series.push_back(std::move(by_rhs));
      }
    report.plots.push_back(std::move(time_plot));
    report.plots.push_back(std::move(rhs_plot));
  }
  Table table{"Runs", {"scene", "method", "tracking", "rtol / step", "error_position [m]", "error_peak_force",
                       "energy_residual", "run_time_s", "steps", "rhs_evaluations", "status"},
              {}, true};
  for (const Run& r : runs)
    table.rows.push_back({config.scenes[r.scene].name, to_string(r.method), to_string(r.tracking),
                          r.method == IntegrationMethod::rk4 ? format_number4(r.step) + " s" : format_number4(r.rtol),
                          r.ok ? format_number4(r.error_position) : "–", r.ok ? format_number4(r.error_peak_force) : "–",
                          r.ok ? format_number4(r.energy_residual) : "–", format_number4(r.run_time_s),
                          std::to_string(r.steps), std::to_string(r.rhs_evaluations), r.ok ? "ok" : r.error});
  report.tables.push_back(std::move(table));
  write_report(ctx.out_dir / "report.html", report);
  write_json_atomic(ctx.out_dir / "config.json", resolved_study_json(base, "convergence", writer.json()));

  std::printf("%s: %zu runs (%ld failed) in %.3g s\n  work_precision.csv and report: %s\n", base.name.c_str(),
              runs.size(), failed, wall,
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn
