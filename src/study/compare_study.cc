#include "study/compare_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <map>
#include <mutex>

#include "common/errors.h"
#include "dynamics/simulation.h"
#include "io/csv_writer.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "io/report.h"
#include "study/parallel.h"

namespace camdyn {

namespace {

const std::vector<std::string> kStudyKeys = {"cases", "grid", "zip", "metrics"};
const std::vector<std::string> kMetricNames = {
    "separation_fraction", "max_separation_gap", "impact_count",    "max_impact_velocity",
    "peak_contact_force",  "min_contact_force",  "max_penetration", "max_kinematic_error",
    "separation_integral", "energy_residual",    "max_pressure_angle_deg", "min_radius_of_curvature",
    "jump_speed_rpm"};

struct CaseConfig {
  std::string name;
  std::string config;            ///< a scene file (relative to the study); empty: the study's own scene
  std::vector<std::string> set;  ///< "dotted.path=VALUE" overrides
};

template <class A>
void visit(A& a, CaseConfig& c) {
  a.field("name", c.name, non_empty());
  a.field("config", c.config);
  a.field("set", c.set);
}

struct Axis {
  std::string key;
  std::vector<Json> values;
};

std::vector<double> metric_values(const Metrics& m) {
  return {m.separation_fraction,   m.max_separation_gap,   static_cast<double>(m.impact_count),
          m.max_impact_velocity,   m.peak_contact_force,   m.min_contact_force,
          m.max_penetration,       m.max_kinematic_error,  m.separation_integral,
          m.energy_residual,       m.max_pressure_angle_deg, m.min_radius_of_curvature,
          m.jump_speed_rpm};
}

std::vector<Axis> read_axes(const Json& part, const std::string& key, const StudyContext& ctx) {
  std::vector<Axis> axes;
  if (!part.contains(key)) return axes;
  const Json& object = part[key];
  if (!object.is_object()) throw InputError(ctx.config_file, key, "expected an object of dotted path: [values]");
  for (const auto& [path, values] : object.items()) {
    if (!values.is_array() || values.empty())
      throw InputError(ctx.config_file, key + "." + path, "expected a non-empty array of values");
    axes.push_back({path, std::vector<Json>(values.begin(), values.end())});
  }
  return axes;
}

struct Point {
  size_t case_index = 0;
  std::vector<Json> values;  // one per axis (grid axes, then zip axes)
  bool ok = false;
  std::string error;
  std::vector<double> metrics;
  double run_time_s = 0.0;
};

std::string cell_text(const Json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

}  // namespace

int run_compare_study(const Json& doc, const StudyContext& ctx) {
  Json part;
  Json scene_doc = doc;
  for (const std::string& key : kStudyKeys)
    if (auto it = scene_doc.find(key); it != scene_doc.end()) {
      part[key] = *it;
      scene_doc.erase(it);
    }
  scene_doc["study"] = "simulate";

  std::vector<CaseConfig> cases;
  std::vector<std::string> metrics = kMetricNames;
  {
    Json known = Json::object();
    if (part.contains("cases")) known["cases"] = part["cases"];
    if (part.contains("metrics")) known["metrics"] = part["metrics"];
    JsonReader reader(known, "", ctx.source);
    reader.field("cases", cases);
    reader.field("metrics", metrics, one_of(kMetricNames));
    reader.finish();
  }
  if (cases.empty()) cases.push_back({doc.value("name", std::string("scene")), "", {}});
  for (CaseConfig& c : cases)
    if (!c.config.empty()) c.config = absolute_path(c.config, ctx.source.dir);
  const std::vector<Axis> grid = read_axes(part, "grid", ctx);
  const std::vector<Axis> zip = read_axes(part, "zip", ctx);
  for (const Axis& a : zip)
    if (a.values.size() != zip.front().values.size())
      throw InputError(ctx.config_file, "zip." + a.key, "every zip list must have the same length");

  // The base document of each case, validated once.
  std::vector<Json> bases;
  for (size_t c = 0; c < cases.size(); ++c) {
    Json base = cases[c].config.empty() ? scene_doc : load_config_json(cases[c].config);
    for (const std::string& assignment : cases[c].set) apply_assignment(base, assignment);
    const std::string where = "cases[" + std::to_string(c) + "]";
    try {
      scene_from_json(base, cases[c].config.empty() ? ctx.source : config_source(cases[c].config));
    } catch (const InputError& e) {
      throw InputError(ctx.config_file, where, std::string("case '") + cases[c].name + "': " + e.what());
    }
    bases.push_back(std::move(base));
  }

  // Every case × cartesian product of the grid × each zip row.
  std::vector<Point> points;
  const size_t zip_rows = zip.empty() ? 1 : zip.front().values.size();
  for (size_t c = 0; c < cases.size(); ++c) {
    std::vector<size_t> index(grid.size(), 0);
    for (bool more = true; more;) {
      for (size_t z = 0; z < zip_rows; ++z) {
        Point p;
        p.case_index = c;
        for (size_t g = 0; g < grid.size(); ++g) p.values.push_back(grid[g].values[index[g]]);
        for (const Axis& a : zip) p.values.push_back(a.values[z]);
        points.push_back(std::move(p));
      }
      more = false;
      for (size_t g = grid.size(); g-- > 0;) {
        if (++index[g] < grid[g].values.size()) {
          more = true;
          break;
        }
        index[g] = 0;
      }
    }
  }
  std::vector<std::string> keys;
  for (const Axis& a : grid) keys.push_back(a.key);
  for (const Axis& a : zip) keys.push_back(a.key);

  if (ctx.validate_only) {
    Json resolved = doc;
    std::cout << dump_json(resolved);
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << points.size() << " runs)\n";
    return 0;
  }

  const auto wall_start = std::chrono::steady_clock::now();
  std::mutex progress_mutex;
  size_t done = 0, failed = 0;
  parallel_for(points.size(), ctx.threads(), [&](size_t i) {
    Point& p = points[i];
    const CaseConfig& c = cases[p.case_index];
    try {
      Json run = bases[p.case_index];
      for (size_t k = 0; k < keys.size(); ++k) set_config_value(run, keys[k], p.values[k]);
      const SceneConfig scene =
          scene_from_json(run, c.config.empty() ? ctx.source : config_source(c.config));
      SimulationOptions options;
      options.record_series = false;
      const SimulationResult r = simulate_scene(scene, ctx.config_file, options);
      p.metrics = metric_values(r.metrics);
      p.run_time_s = r.solver.run_time_s;
      p.ok = true;
      for (size_t m = 0; m + 1 < p.metrics.size(); ++m)  // jump_speed_rpm may be +inf: written empty
        if (!std::isfinite(p.metrics[m])) p.ok = false, p.error = "non-finite metric " + kMetricNames[m];
    } catch (const std::exception& e) {
      p.error = e.what();
    }
    const std::lock_guard<std::mutex> lock(progress_mutex);
    ++done;
    if (!p.ok) ++failed;
    if (ctx.progress) {
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      std::fprintf(stderr, "\r  compare: %zu / %zu runs, %zu failed, %.0f s elapsed, ~%.0f s left   ", done,
                   points.size(), failed, elapsed,
                   elapsed / static_cast<double>(done) * static_cast<double>(points.size() - done));
      if (done == points.size()) std::fprintf(stderr, "\n");
    }
  });
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // comparison.csv / .json
  std::filesystem::create_directories(ctx.out_dir);
  std::vector<std::string> columns = {"case"};
  columns.insert(columns.end(), keys.begin(), keys.end());
  for (const std::string& m : kMetricNames) columns.push_back(m);
  columns.insert(columns.end(), {"status", "error", "run_time_s"});
  CsvWriter csv(ctx.out_dir / "comparison.csv", columns);
  Json rows = Json::array();
  for (const Point& p : points) {
    std::vector<CsvCell> cells = {CsvCell(cases[p.case_index].name)};
    Json row{{"case", cases[p.case_index].name}};
    for (size_t k = 0; k < keys.size(); ++k) {
      cells.push_back(CsvCell(cell_text(p.values[k])));
      row[keys[k]] = p.values[k];
    }
    Json metrics_json = Json::object();
    for (size_t m = 0; m < kMetricNames.size(); ++m) {
      const bool have = p.ok && std::isfinite(p.metrics[m]);
      cells.push_back(have ? CsvCell(p.metrics[m]) : CsvCell(""));
      metrics_json[kMetricNames[m]] = have ? Json(p.metrics[m]) : Json(nullptr);
    }
    cells.emplace_back(p.ok ? "ok" : "failed");
    cells.emplace_back(p.error);
    cells.emplace_back(p.run_time_s);
    csv.row(cells);
    row["metrics"] = metrics_json;
    row["status"] = p.ok ? "ok" : "failed";
    row["error"] = p.error;
    row["run_time_s"] = p.run_time_s;
    rows.push_back(row);
  }
  csv.commit();
  write_json_atomic(ctx.out_dir / "comparison.json",
                    Json{{"name", doc.value("name", std::string("compare"))},
                         {"study", "compare"},
                         {"camdyn_version", CAMDYN_VERSION},
                         {"runs", points.size()},
                         {"failed", failed},
                         {"run_time_s", wall},
                         {"results", rows}});

  // report.html: sortable table, metrics against the first grid key, failures.
  Report report;
  report.title = "camdyn: " + doc.value("name", std::string("compare"));
  report.subtitle = "compare study: " + std::to_string(cases.size()) + " case(s) × " +
                    std::to_string(points.size() / cases.size()) + " grid point(s)";
  report.facts = {{"runs", std::to_string(points.size())},
                  {"failed", std::to_string(failed)},
                  {"wall time", format_number(wall, 3) + " s"}};
  Table table{"Results (click a header to sort)", {"case"}, {}, true};
  table.columns.insert(table.columns.end(), keys.begin(), keys.end());
  table.columns.insert(table.columns.end(), metrics.begin(), metrics.end());
  table.columns.push_back("status");
  std::map<std::string, size_t> metric_index;
  for (size_t m = 0; m < kMetricNames.size(); ++m) metric_index[kMetricNames[m]] = m;
  for (const Point& p : points) {
    std::vector<std::string> row = {cases[p.case_index].name};
    for (const Json& v : p.values) row.push_back(cell_text(v));
    for (const std::string& m : metrics)
      row.push_back(p.ok ? format_number(p.metrics[metric_index[m]], 4) : "–");
    row.push_back(p.ok ? "ok" : "failed");
    table.rows.push_back(std::move(row));
  }
  report.tables.push_back(std::move(table));
  if (!grid.empty() && grid.front().values.front().is_number()) {
    for (const std::string& m : metrics) {
      Plot plot;
      plot.title = m + " against " + grid.front().key;
      plot.xlabel = grid.front().key;
      plot.ylabel = m;
      std::map<std::string, Series> lines;  // one line per case and value of the other axes
      for (const Point& p : points) {
        if (!p.ok || !std::isfinite(p.metrics[metric_index[m]])) continue;
        std::string label = cases[p.case_index].name;
        for (size_t k = 1; k < p.values.size(); ++k) label += ", " + keys[k] + "=" + cell_text(p.values[k]);
        Series& s = lines[label];
        s.label = label;
        s.style = "linespoints";
        s.x.push_back(p.values[0].get<double>());
        s.y.push_back(p.metrics[metric_index[m]]);
      }
      if (lines.size() > 12) continue;  // too many lines to read: the table has them
      for (auto& [label, s] : lines) plot.series.push_back(std::move(s));
      report.plots.push_back(std::move(plot));
    }
  }
  // Pass/fail map over the first two numeric grid axes (every case and
  // value of the other axes overlaid: a point fails if any run there failed).
  if (grid.size() >= 2 && grid[0].values.front().is_number() && grid[1].values.front().is_number()) {
    Plot map;
    map.title = "Pass/fail map: " + grid[0].key + " against " + grid[1].key;
    map.xlabel = grid[0].key;
    map.ylabel = grid[1].key;
    map.logx = std::all_of(grid[0].values.begin(), grid[0].values.end(), [](const Json& v) { return v.get<double>() > 0; });
    map.logy = std::all_of(grid[1].values.begin(), grid[1].values.end(), [](const Json& v) { return v.get<double>() > 0; });
    std::map<std::pair<double, double>, bool> any_failed;
    for (const Point& p : points) {
      auto& f = any_failed[{p.values[0].get<double>(), p.values[1].get<double>()}];
      f = f || !p.ok;
    }
    Series ok_points{"all runs ok", {}, {}, "points"}, failed_points{"some runs failed (see the table)", {}, {}, "points"};
    for (const auto& [xy, failed_here] : any_failed) {
      Series& s = failed_here ? failed_points : ok_points;
      s.x.push_back(xy.first);
      s.y.push_back(xy.second);
    }
    map.series = {ok_points, failed_points};
    report.plots.insert(report.plots.begin(), std::move(map));
  }
  Table failures{"Failed runs", {"case", "grid point", "reason"}, {}, false};
  for (const Point& p : points)
    if (!p.ok) {
      std::string at;
      for (size_t k = 0; k < keys.size(); ++k) at += (k ? ", " : "") + keys[k] + "=" + cell_text(p.values[k]);
      failures.rows.push_back({cases[p.case_index].name, at, p.error});
    }
  if (!failures.rows.empty()) report.tables.push_back(std::move(failures));
  write_report(ctx.out_dir / "report.html", report);

  std::printf("%s: %zu runs, %zu failed, %.3g s\n  comparison.csv and report: %s\n",
              doc.value("name", std::string("compare")).c_str(), points.size(), failed, wall,
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn
