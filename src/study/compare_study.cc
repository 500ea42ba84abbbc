// The compare study: the config (compare_config.cc) → the base scene of each
// case and every run (case × grid point) → the runs not yet in the journal,
// on threads or MPI ranks → the outcomes, read back from the journal records
// → comparison.csv / .json and report.html (compare_output.cc, compare_report.cc).
#include "study/compare_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <optional>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/simulation.h"
#include "io/json_archive.h"
#include "io/json_merge.h"
#include "io/json_writer.h"
#include "study/compare_config.h"
#include "study/compare_output.h"
#include "study/journal.h"
#include "study/journaled_runs.h"
#include "study/mpi_runner.h"
#include "study/steady_state.h"

namespace camdyn {

namespace {

/// The base document of a case, validated once, and where its relative paths resolve.
struct CaseBase {
  Json config;
  ConfigSource source;
};

/// What the study computes: every case's base scene and every run.
struct ComparePlan {
  CompareSpec spec;
  std::vector<std::string> keys;  ///< spec.keys()
  std::vector<CaseBase> bases;    ///< one per case
  std::vector<ComparePoint> points;
};

std::vector<CaseBase> resolve_cases(const CompareSpec& spec, const Json& scene_doc, const StudyContext& ctx) {
  std::vector<CaseBase> bases;
  for (std::size_t c = 0; c < spec.cases.size(); ++c) {
    const CompareCase& one = spec.cases[c];
    const std::string where = std::string("cases[") + std::to_string(c) + "]";
    Json base = one.config.empty() ? scene_doc : load_config_json(one.config);
    if (!one.inline_config.is_null()) {
      if (!one.config.empty()) throw InputError(ctx.config_file, where + ".config", "give a file or an object");
      merge_config(base, one.inline_config);
    }
    for (const std::string& assignment : one.set) apply_assignment(base, assignment);
    ConfigSource source = one.config.empty() ? ctx.source : config_source(one.config);
    try {
      scene_from_json(base, source);
    } catch (const InputError& e) {
      throw InputError(ctx.config_file, where, std::string("case '") + one.name + "': " + e.what());
    }
    bases.push_back({std::move(base), std::move(source)});
  }
  return bases;
}

/// Every case × cartesian product of the grid × each zip row.
std::vector<ComparePoint> expand_points(const CompareSpec& spec) {
  std::vector<ComparePoint> points;
  const std::size_t zip_rows = spec.zip.empty() ? 1 : spec.zip.front().values.size();
  for (std::size_t c = 0; c < spec.cases.size(); ++c) {
    std::vector<std::size_t> index(spec.grid.size(), 0);
    for (bool more = true; more;) {
      for (std::size_t z = 0; z < zip_rows; ++z) {
        ComparePoint p;
        p.case_index = c;
        for (std::size_t g = 0; g < spec.grid.size(); ++g) p.values.push_back(spec.grid[g].values[index[g]]);
        for (const CompareAxis& a : spec.zip) p.values.push_back(a.values[z]);
        for (const OverlaySelection& selection : spec.overlays)
          p.overlay = p.overlay || std::all_of(selection.begin(), selection.end(),
                                               [&](const auto& s) { return p.values[s.first] == s.second; });
        points.push_back(std::move(p));
      }
      more = false;
      for (std::size_t g = spec.grid.size(); g-- > 0;) {
        if (++index[g] < spec.grid[g].values.size()) {
          more = true;
          break;
        }
        index[g] = 0;
      }
    }
  }
  return points;
}

/// The study's `name`, or `fallback` when it has none or it is not a string
/// (each case's scene reports the wrong type, naming the field).
std::string study_name(const Json& doc, const std::string& fallback) {
  const auto it = doc.find("name");
  return it != doc.end() && it->is_string() ? it->get<std::string>() : fallback;
}

/// Reads the study: its own fields, the scene of each case, every run.
ComparePlan plan_study(const Json& doc, const StudyContext& ctx) {
  Json part;
  Json scene_doc = doc;
  for (const std::string& key : compare_study_keys())
    if (auto it = scene_doc.find(key); it != scene_doc.end()) {
      part[key] = *it;
      scene_doc.erase(it);
    }
  scene_doc["study"] = "simulate";
  ComparePlan plan;
  plan.spec = compare_spec_from_json(part, study_name(doc, "scene"), ctx);
  plan.keys = plan.spec.keys();
  plan.bases = resolve_cases(plan.spec, scene_doc, ctx);
  plan.points = expand_points(plan.spec);
  return plan;
}

/// Builds every run's scene and model before any run (validate as well as
/// run): a study none of whose runs can be built is bad input, exit 2 naming
/// the first case and its first run's reason; where only some cannot be
/// built they are kept as failed runs (a comparison may show that a case
/// cannot be built, and a sweep may cross the edge of what can be).
void check_some_run_builds(const ComparePlan& plan, const StudyContext& ctx, CamGeometryCache& geometries) {
  std::string first;
  for (const ComparePoint& p : plan.points) {
    try {
      Json run = plan.bases[p.case_index].config;
      for (std::size_t k = 0; k < plan.keys.size(); ++k) set_config_value(run, plan.keys[k], p.values[k]);
      const SceneConfig scene = scene_from_json(run, plan.bases[p.case_index].source);
      build_model(*geometries.get(scene, ctx.config_file), scene, ctx.config_file);
      return;
    } catch (const InputError& e) {
      if (first.empty()) first = "case '" + plan.spec.cases[p.case_index].name + "': " + std::string(e.what());
    }
  }
  if (!plan.points.empty())
    throw InputError(ctx.config_file, "cases[" + std::to_string(plan.points.front().case_index) + "]",
                     "none of the study's " + std::to_string(plan.points.size()) + " runs can be built: " + first);
}

/// The study's fingerprint: everything that decides what each run computes.
std::string study_fingerprint(const ComparePlan& plan) {
  Json identity = Json::object();
  identity["keys"] = plan.keys;
  Json case_list = Json::array(), point_list = Json::array();
  for (std::size_t c = 0; c < plan.spec.cases.size(); ++c)
    case_list.push_back(
        Json{{"name", plan.spec.cases[c].name}, {"dir", plan.bases[c].source.dir}, {"config", plan.bases[c].config}});
  for (const ComparePoint& p : plan.points)
    point_list.push_back(Json{{"case", p.case_index}, {"values", p.values}, {"overlay", p.overlay}});
  identity["cases"] = case_list;
  identity["points"] = point_list;
  return fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));
}

/// Every metric in compare_metric_names() order (the order Metrics' visit
/// lists them, then the train's); NaN (written as null) where it does not
/// apply, such as a train metric of an element the scene lacks.
std::vector<double> metric_values(const Metrics& m) {
  std::vector<double> values;
  for_each_metric(m, [&](const char*, const auto& value, const MetricInfo&) {
    values.push_back(metric_value(value).value_or(std::numeric_limits<double>::quiet_NaN()));
  });
  const std::vector<std::string> train = train_metric_names();
  const std::size_t first = values.size();
  values.resize(first + train.size(), std::numeric_limits<double>::quiet_NaN());
  if (m.train)
    for_each_train_metric(*m.train, [&](const char* name, double value, bool, const char*) {
      const auto at = std::find(train.begin(), train.end(), name) - train.begin();
      values[first + static_cast<std::size_t>(at)] = value;
    });
  return values;
}

/// Per metric in compare_metric_names() order: whether it may be empty
/// without the run having failed (+inf written as null, such as
/// jump_speed_rpm, or a metric that does not apply to every scene).
std::vector<bool> metrics_that_may_be_null() {
  std::vector<bool> nullable;
  const Metrics none;
  for_each_metric(none, [&](const char*, const auto& value, const MetricInfo& info) {
    nullable.push_back(info.infinite_is_null || !metric_value(value));
  });
  nullable.resize(nullable.size() + train_metric_names().size(), true);  // scenes without the element
  return nullable;
}

/// The last simulated cam revolution of a run, sorted by cam angle in [0, 360):
/// what the overlays of the report plot.
Json last_revolution(const SceneConfig& scene, const SimulationResult& r) {
  const double period = 60.0 / scene.mechanism.cam.rpm;  // [s]
  std::vector<std::size_t> order;
  std::vector<double> angle(r.series.time.size());
  for (std::size_t i = 0; i < r.series.time.size(); ++i) {
    if (r.series.time[i] < r.end_time - period * (1.0 + 1e-12) || r.series.time[i] >= r.end_time) continue;
    angle[i] = std::fmod(r.series.cam_angle_deg[i], 360.0);
    if (angle[i] < 0) angle[i] += 360.0;
    order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return angle[a] < angle[b]; });
  Json cam = Json::array(), position = Json::array(), force = Json::array();
  for (const std::size_t i : order) {
    cam.push_back(angle[i]);
    position.push_back(r.series.follower_position[i]);
    force.push_back(r.series.contact_force[i]);
  }
  return Json{{"cam_angle_deg", cam}, {"follower_position", position}, {"contact_force", force}};
}

/// Run `i` of the plan, as its journal record. A failed run is a record with
/// status "failed" and the error, never an exception.
Json run_record(const ComparePlan& plan, std::size_t i, const StudyContext& ctx, CamGeometryCache& geometries) {
  const std::vector<std::string>& metric_names = compare_metric_names();
  const ComparePoint& p = plan.points[i];
  Json record = Json::object();
  record["index"] = i;
  record["case"] = plan.spec.cases[p.case_index].name;
  Json at = Json::object();
  for (std::size_t k = 0; k < plan.keys.size(); ++k) at[plan.keys[k]] = p.values[k];
  record["point"] = at;
  std::vector<double> values;
  std::string error;
  double run_time = 0.0;  // [s]
  Json overlay;
  std::string coordinate_unit;
  try {
    Json run = plan.bases[p.case_index].config;
    for (std::size_t k = 0; k < plan.keys.size(); ++k) set_config_value(run, plan.keys[k], p.values[k]);
    const SceneConfig scene = scene_from_json(run, plan.bases[p.case_index].source);
    coordinate_unit = coordinate_units(scene).position;
    SimulationOptions options;
    options.record_series = p.overlay && scene.mechanism.cam.rpm > 0;
    const Model model = build_model(*geometries.get(scene, ctx.config_file), scene, ctx.config_file);
    Workspace ws;
    SimulationResult r = simulate(scene, model, ws, options);
    estimate_error(scene, model, r);
    throw_if_failed(r);
    if (scene.simulation.steady_state) apply_steady_state(scene, model, r);
    values = metric_values(r.metrics);
    run_time = r.solver.run_time_s;
    const std::vector<bool> nullable = metrics_that_may_be_null();
    for (std::size_t m = 0; m < values.size() && error.empty(); ++m)  // jump_speed_rpm may be +inf: empty
      if (!std::isfinite(values[m]) && !nullable[m]) error = "non-finite metric " + metric_names[m];
    if (options.record_series) overlay = last_revolution(scene, r);
  } catch (const std::exception& e) {
    error = e.what();
    if (error.empty()) error = "unknown error";
  }
  const bool ok = error.empty() && !values.empty();
  Json metrics_json = Json::object();
  for (std::size_t m = 0; m < metric_names.size(); ++m)
    metrics_json[metric_names[m]] = ok && std::isfinite(values[m]) ? Json(values[m]) : Json(nullptr);
  record["status"] = ok ? "ok" : "failed";
  record["error"] = error;
  // A run a budget cut short is not a failure of the design: named, so that
  // the study withholds its ranking (and a resume with a larger budget redoes it).
  if (const std::string budget = ok ? std::string() : budget_that_cut(error); !budget.empty())
    record[kBudgetKey] = budget;
  record["metrics"] = metrics_json;
  record["run_time_s"] = run_time;
  if (ok && !overlay.is_null()) record["overlay"] = overlay;
  if (ok) record["coordinate_unit"] = coordinate_unit;
  return record;
}

double number_or_nan(const Json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

// Whether `overlay` is what last_revolution writes: the three series, numbers
// of equal count (the report reads them as such).
bool well_formed_overlay(const Json& overlay) {
  if (!overlay.is_object() || !overlay.contains("cam_angle_deg") || !overlay["cam_angle_deg"].is_array()) return false;
  const std::size_t count = overlay["cam_angle_deg"].size();
  for (const char* key : {"cam_angle_deg", "follower_position", "contact_force"}) {
    const auto it = overlay.find(key);
    if (it == overlay.end() || !it->is_array() || it->size() != count ||
        !std::all_of(it->begin(), it->end(), [](const Json& v) { return v.is_number(); }))
      return false;
  }
  return true;
}

CompareOutcome outcome_of(const Json& record) {
  CompareOutcome o;
  o.ok = string_or(record, "status", "") == "ok";
  o.error = string_or(record, "error", "");
  o.run_time_s = number_or_nan(record.value("run_time_s", Json()));
  if (!std::isfinite(o.run_time_s)) o.run_time_s = 0.0;
  Json metrics = record.value("metrics", Json::object());
  if (!metrics.is_object()) metrics = Json::object();
  for (const std::string& m : compare_metric_names()) o.metrics.push_back(number_or_nan(metrics.value(m, Json())));
  if (auto it = record.find("overlay"); it != record.end() && well_formed_overlay(*it)) o.overlay = *it;
  o.coordinate_unit = string_or(record, "coordinate_unit", "m");  // a journal from before: translating
  return o;
}

}  // namespace

int run_compare_study(const Json& doc, const StudyContext& ctx) {
  const ComparePlan plan = plan_study(doc, ctx);
  CamGeometryCache geometries;  // a grid over speeds or the mechanism's numbers builds each cam once
  check_some_run_builds(plan, ctx, geometries);
  if (ctx.validate_only) {
    std::cout << dump_json(doc);
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << plan.points.size() << " runs)\n";
    return 0;
  }
  const auto wall_start = std::chrono::steady_clock::now();
  JournaledRuns state;
  if (const std::optional<int> code = run_journaled(
          "compare", study_fingerprint(plan), plan.points.size(),
          [&](std::size_t i) { return run_record(plan, i, ctx, geometries); }, ctx, state))
    return *code;
  if (mpi::rank() != 0) return 0;  // rank 0 writes the outputs

  // Outputs, from the records in (case, grid point) order: a resumed study
  // writes exactly what an uninterrupted one does.
  CompareResult result;
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  result.name = study_name(doc, "compare");
  result.spec = &plan.spec;
  result.keys = plan.keys;
  result.points = plan.points;
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    result.outcomes.push_back(outcome_of(state.records.at(i)));
    if (!result.outcomes.back().ok) ++result.failed;
  }
  result.resumed = state.resumed;
  result.mpi_ranks = mpi::size();
  result.design = scene_from_json(plan.bases.front().config, plan.bases.front().source);
  result.config_file = ctx.config_file;
  write_comparison(result, ctx.out_dir);
  if (state.budget_cut > 0) {
    // The ranking counts failed runs against a case: not with runs that merely ran out of a budget.
    std::filesystem::remove(ctx.out_dir / "report.html");  // an earlier run's verdict must not stand
    std::cerr << "camdyn: error: "
              << withheld_text(state.budget_cut, plan.points.size(), "runs", state.budgets,
                               "the comparison's verdict (report.html, the ranking of the cases)")
              << "; comparison.csv and comparison.json hold the runs\n";
    return 3;
  }
  write_compare_report(result, ctx.out_dir);
  print_compare_summary(result, ctx.out_dir);
  return 0;
}

}  // namespace camdyn
