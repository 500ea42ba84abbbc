#include "study/convergence_output.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "dynamics/coordinate_units.h"
#include "io/csv_writer.h"
#include "io/json_writer.h"
#include "output/cam_plots.h"
#include "output/report.h"

namespace camdyn {

namespace {

std::string format_number4(double v) { return format_number(v, 4); }

/// The unit of a run's position error: its scene's follower coordinate (an
/// arm's in rad, coordinate_units.h).
const char* position_unit(const ConvergenceStudy& study, const ConvergenceRun& r) {
  return coordinate_units(study.scenes[r.scene]).position;
}

/// The unit the runs' position errors share, or "" when the scenes mix
/// translating and oscillating followers (each value then carries its own).
std::string shared_position_unit(const ConvergenceStudy& study) {
  std::string first = coordinate_units(study.scenes.front()).position;
  for (const SceneConfig& scene : study.scenes)
    if (coordinate_units(scene).position != first) return "";
  return first;
}

/// work_precision.csv: one row per run; errors empty for a failed run.
void write_work_precision_csv(const std::filesystem::path& path, const ConvergenceStudy& study,
                              const std::vector<ConvergenceRun>& runs) {
  CsvWriter csv(path, {"scene", "method", "tracking", "rtol", "step", "error_position", "error_peak_force",
                       "energy_residual", "run_time_s", "steps", "rhs_evaluations", "status", "error"});
  for (const ConvergenceRun& r : runs) {
    const bool fixed = r.method == IntegrationMethod::rk4;
    csv.row({CsvCell(study.config.scenes[r.scene].name), CsvCell(to_string(r.method)), CsvCell(to_string(r.tracking)),
             fixed ? CsvCell("") : CsvCell(r.rtol), fixed ? CsvCell(r.step) : CsvCell(""),
             r.ok ? CsvCell(r.error_position) : CsvCell(""), r.ok ? CsvCell(r.error_peak_force) : CsvCell(""),
             r.ok ? CsvCell(r.energy_residual) : CsvCell(""), CsvCell(r.run_time_s), CsvCell(r.steps),
             CsvCell(r.rhs_evaluations), CsvCell(r.ok ? "ok" : "failed"), CsvCell(r.error)});
  }
  csv.commit();
}

/// Position error against run time and against RHS evaluations for scene k,
/// one series per method and tracking mode (successful runs with an error > 0).
std::pair<Plot, Plot> work_precision_plots(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs,
                                           size_t k) {
  const ConvergenceConfig& config = study.config;
  Plot time_plot, rhs_plot;
  time_plot.title = "Work-precision, scene '" + config.scenes[k].name + "': position error against run time";
  time_plot.xlabel = "run time [s]";
  time_plot.ylabel = CoordinateUnits::axis("max |y − y_ref|", coordinate_units(study.scenes[k]).position);
  time_plot.logx = time_plot.logy = true;
  rhs_plot = time_plot;
  rhs_plot.title = "Scene '" + config.scenes[k].name + "': position error against RHS evaluations";
  rhs_plot.xlabel = "right-hand-side evaluations [-]";
  for (const IntegrationMethod method : config.methods)
    for (const Tracking tracking : config.tracking) {
      Series by_time{to_string(method) + " / " + to_string(tracking), {}, {}, "linespoints"};
      Series by_rhs = by_time;
      for (const ConvergenceRun& r : runs)
        if (r.scene == k && r.method == method && r.tracking == tracking && r.ok && r.error_position > 0) {
          by_time.x.push_back(r.run_time_s);
          by_time.y.push_back(r.error_position);
          by_rhs.x.push_back(static_cast<double>(r.rhs_evaluations));
          by_rhs.y.push_back(r.error_position);
        }
      time_plot.series.push_back(std::move(by_time));
      rhs_plot.series.push_back(std::move(by_rhs));
    }
  return {std::move(time_plot), std::move(rhs_plot)};
}

/// The table of every run.
Table runs_table(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs) {
  const std::string unit = shared_position_unit(study);
  Table table{"Runs",
              {"scene", "method", "tracking", "rtol / step",
               CoordinateUnits::axis("error_position", unit.empty() ? "m or rad" : unit), "error_peak_force",
               "energy_residual", "run_time_s", "steps", "rhs_evaluations", "status"},
              {},
              true};
  const auto error_text = [&](const ConvergenceRun& r) {
    if (!r.ok) return std::string("–");
    return unit.empty() ? format_number4(r.error_position) + " " + position_unit(study, r)
                        : format_number4(r.error_position);
  };
  for (const ConvergenceRun& r : runs)
    table.rows.push_back({study.config.scenes[r.scene].name, to_string(r.method), to_string(r.tracking),
                          r.method == IntegrationMethod::rk4 ? format_number4(r.step) + " s" : format_number4(r.rtol),
                          error_text(r), r.ok ? format_number4(r.error_peak_force) : "–",
                          r.ok ? format_number4(r.energy_residual) : "–", format_number4(r.run_time_s),
                          std::to_string(r.steps), std::to_string(r.rhs_evaluations), r.ok ? "ok" : r.error});
  return table;
}

/// Where the position error does not fall with the tolerance: per scene,
/// method and tracking mode with at least 3 successful runs over a decade or
/// more of rtol, the least-squares slope of log error against log rtol; below
/// 0.3 the error is flat, limited by event location or by the model, not by
/// the integrator (a well-resolved run has a slope near 1). One line each.
std::vector<std::string> flat_error_notes(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs) {
  std::vector<std::string> notes;
  for (std::size_t k = 0; k < study.scenes.size(); ++k)
    for (const IntegrationMethod method : study.config.methods)
      for (const Tracking tracking : study.config.tracking) {
        double sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0, lo = INFINITY, hi = 0.0;
        int n = 0;
        for (const ConvergenceRun& r : runs) {
          if (r.scene != k || r.method != method || r.tracking != tracking || !r.ok || !(r.rtol > 0.0) ||
              !(r.error_position > 0.0))
            continue;
          const double x = std::log10(r.rtol), y = std::log10(r.error_position);
          sx += x;
          sy += y;
          sxx += x * x;
          sxy += x * y;
          lo = std::min(lo, r.rtol);
          hi = std::max(hi, r.rtol);
          ++n;
        }
        if (n < 3 || hi < 10.0 * lo) continue;
        const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
        if (slope >= 0.3) continue;
        notes.push_back("scene '" + study.config.scenes[k].name + "', " + to_string(method) + " (" +
                        to_string(tracking) + "): the position error stays flat as rtol falls from " +
                        format_number4(hi) + " to " + format_number4(lo) + " (slope " + format_number4(slope) +
                        " per decade): it is limited by event location or by the model, not by the "
                        "integrator's tolerance, and tightening rtol will not make it smaller");
      }
  return notes;
}

/// The banner: the most accurate run and the cheapest one, and how many failed.
Verdict convergence_verdict(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs, long failed) {
  const ConvergenceRun* accurate = nullptr;
  const ConvergenceRun* fast = nullptr;
  for (const ConvergenceRun& r : runs) {
    if (!r.ok) continue;
    if (!accurate || r.error_position < accurate->error_position) accurate = &r;
    if (!fast || r.run_time_s < fast->run_time_s) fast = &r;
  }
  Verdict v;
  v.tone = failed == 0 ? Verdict::Tone::good : accurate ? Verdict::Tone::warning : Verdict::Tone::bad;
  const auto describe = [&](const ConvergenceRun& r) {
    return to_string(r.method) + " (" + to_string(r.tracking) + ", " +
           (r.method == IntegrationMethod::rk4 ? "step " + format_number4(r.step) + " s"
                                               : "rtol " + format_number4(r.rtol)) +
           "): position error " + format_number4(r.error_position) + " " + position_unit(study, r) + " in " +
           format_number4(r.run_time_s) + " s";
  };
  v.headline = accurate ? "most accurate: " + describe(*accurate) : "every run failed";
  if (fast) v.details.push_back("fastest: " + describe(*fast));
  v.details.push_back(std::to_string(runs.size() - static_cast<std::size_t>(failed)) + " of " +
                      std::to_string(runs.size()) + " runs succeeded");
  for (std::string& note : flat_error_notes(study, runs)) v.details.push_back(std::move(note));
  return v;
}

}  // namespace

Report convergence_report(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs, long failed,
                          double wall, const std::string& file, const std::vector<std::string>& reference_missing) {
  Report report;
  report.title = "camdyn: " + study.base.name + " — error against run time";
  report.subtitle = "convergence study: every method × tracking mode × tolerance against a reference run (" +
                    to_string(study.config.reference.method) + ", rtol " + format_number4(study.config.reference.rtol) +
                    ")";
  report.verdict = convergence_verdict(study, runs, failed);
  for (std::size_t k = 0; k < reference_missing.size(); ++k) {
    if (reference_missing[k].empty()) continue;
    // Without its reference a scene's runs measure nothing: say so first.
    report.verdict->tone = Verdict::Tone::bad;
    report.verdict->headline =
        "reference run of scene '" + study.config.scenes[k].name + "' missing: its runs are listed without errors";
    report.verdict->details.insert(report.verdict->details.begin(), "the reference failed: " + reference_missing[k]);
  }
  report.facts.emplace_back("runs", std::to_string(runs.size()));
  report.facts.emplace_back("failed", std::to_string(failed));
  report.facts.emplace_back("wall time", format_number4(wall) + " s");
  for (size_t k = 0; k < study.scenes.size(); ++k) {
    auto [time_plot, rhs_plot] = work_precision_plots(study, runs, k);
    report.plots.push_back(std::move(time_plot));
    report.plots.push_back(std::move(rhs_plot));
  }
  const SceneConfig& first = study.scenes.front();
  for (Plot& plot : scene_cam_plots(first, file, first.mechanism.cam.rpm,
                                    study.scenes.size() > 1 ? "scene '" + study.config.scenes.front().name + "'" : ""))
    report.plots.push_back(std::move(plot));
  Table table = runs_table(study, runs);
  table.wrap = true;  // the failure reasons in the status column
  report.appendix.push_back(std::move(table));
  return report;
}

double write_convergence_outputs(const std::filesystem::path& out_dir, const ConvergenceStudy& study,
                                 const ConvergenceResult& result, const std::string& config_file) {
  const std::vector<ConvergenceRun>& runs = result.runs;
  std::filesystem::create_directories(out_dir);
  write_work_precision_csv(out_dir / "work_precision.csv", study, runs);
  const long failed = result.failed();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - result.started).count();
  write_report(out_dir / "report.html",
               convergence_report(study, runs, failed, wall, config_file, result.reference_missing));
  write_json_atomic(out_dir / "config.json", study.resolved);
  return wall;
}

}  // namespace camdyn
