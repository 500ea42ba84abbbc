#include "study/compare_study.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "common/errors.h"
#include "dynamics/simulation.h"
#include "io/csv_writer.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "io/report.h"
#include "study/journal.h"
#include "study/mpi_runner.h"
#include "common/parallel.h"
#include "study/progress.h"

namespace camdyn {

namespace {

const std::vector<std::string> kStudyKeys = {"cases", "grid", "zip", "metrics", "overlays"};
const std::vector<std::string> kMetricNames = metric_names();
/// Metrics where a larger value is better (the margin against jump, the
/// curvature radius, the jump speed); for every other metric smaller is better.
const std::set<std::string> kHigherIsBetter = {"min_contact_force", "min_radius_of_curvature", "jump_speed_rpm"};

struct CaseConfig {
  std::string name;
  std::string config;            ///< a scene file (relative to the study); empty: inline or the study's own scene
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

/// One run: a case at one grid point.
struct Point {
  std::size_t case_index = 0;
  std::vector<Json> values;  // one per axis (grid axes, then zip axes)
  bool overlay = false;      // its contact force and follower motion are plotted
};

/// A run's outcome, read back from its journal record.
struct Outcome {
  bool ok = false;
  std::string error;
  std::vector<double> metrics;  // NaN where not available
  double run_time_s = 0.0;
  const Json* overlay = nullptr;
};

std::vector<double> metric_values(const Metrics& m) {
  std::vector<double> values;
  for_each_metric(m, [&](const char*, const auto& value, const MetricInfo&) {
    values.push_back(static_cast<double>(value));
  });
  return values;
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

std::string cell_text(const Json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

/// Deep merge as `extends` does: objects merge key by key, anything else (and
/// the motion law, which is one thing) is replaced by the patch.
void merge_into(Json& base, const Json& patch, const std::string& path = "") {
  for (const auto& item : patch.items()) {
    const std::string key_path = path.empty() ? item.key() : path + "." + item.key();
    auto it = base.find(item.key());
    if (key_path != "mechanism.cam.motion_law" && it != base.end() && it->is_object() && item.value().is_object())
      merge_into(*it, item.value(), key_path);
    else
      base[item.key()] = item.value();
  }
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

double number_or_nan(const Json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

Outcome outcome_of(const Json& record) {
  Outcome o;
  o.ok = record.value("status", std::string()) == "ok";
  o.error = record.value("error", std::string());
  o.run_time_s = number_or_nan(record.value("run_time_s", Json()));
  if (!std::isfinite(o.run_time_s)) o.run_time_s = 0.0;
  const Json metrics = record.value("metrics", Json::object());
  for (const std::string& m : kMetricNames) o.metrics.push_back(number_or_nan(metrics.value(m, Json())));
  if (auto it = record.find("overlay"); it != record.end() && it->is_object()) o.overlay = &*it;
  return o;
}

/// Whether `a` is at least as good as `b` for `metric` (ties within 1e-12 relative).
bool better_or_equal(const std::string& metric, double a, double b) {
  const double tie = 1e-12 * std::max(std::abs(a), std::abs(b));
  if (metric == "energy_residual") return std::abs(a) <= std::abs(b) + tie;
  return kHigherIsBetter.count(metric) ? a >= b - tie : a <= b + tie;
}

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

  // A case's `config` is a file name or an inline config (merged over the
  // study's own scene); the reader below sees only file names.
  std::vector<Json> inline_configs;
  std::vector<CaseConfig> cases;
  std::vector<std::string> metrics = kMetricNames;
  {
    Json known = Json::object();
    if (part.contains("cases")) {
      known["cases"] = part["cases"];
      if (known["cases"].is_array())
        for (Json& c : known["cases"]) {
          inline_configs.push_back(Json());
          if (c.is_object() && c.contains("config") && c["config"].is_object()) {
            inline_configs.back() = c["config"];
            c.erase("config");
          }
        }
    }
    if (part.contains("metrics")) known["metrics"] = part["metrics"];
    JsonReader reader(known, "", ctx.source);
    reader.field("cases", cases);
    reader.field("metrics", metrics, one_of(kMetricNames));
    reader.finish();
  }
  inline_configs.resize(cases.size());
  if (cases.empty()) cases.push_back({doc.value("name", std::string("scene")), "", {}});
  inline_configs.resize(cases.size());
  std::set<std::string> names;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    if (!names.insert(cases[c].name).second)
      throw InputError(ctx.config_file, std::string("cases[") + std::to_string(c) + "].name",
                       "case '" + cases[c].name + "' is named twice");
    if (!cases[c].config.empty()) cases[c].config = absolute_path(cases[c].config, ctx.source.dir);
  }
  const std::vector<Axis> grid = read_axes(part, "grid", ctx);
  const std::vector<Axis> zip = read_axes(part, "zip", ctx);
  for (const Axis& a : zip)
    if (a.values.size() != zip.front().values.size())
      throw InputError(ctx.config_file, "zip." + a.key, "every zip list must have the same length");
  std::vector<std::string> keys;
  for (const Axis& a : grid) keys.push_back(a.key);
  for (const Axis& a : zip) keys.push_back(a.key);

  // `overlays`: grid points (some axes fixed) whose runs get contact force and
  // follower motion against cam angle plotted, one line per run.
  std::vector<std::vector<std::pair<std::size_t, Json>>> overlays;
  if (part.contains("overlays")) {
    const Json& list = part["overlays"];
    if (!list.is_array()) throw InputError(ctx.config_file, "overlays", "expected an array of {dotted path: value}");
    for (std::size_t o = 0; o < list.size(); ++o) {
      const std::string where = std::string("overlays[") + std::to_string(o) + "]";
      if (!list[o].is_object() || list[o].empty())
        throw InputError(ctx.config_file, where, "expected a non-empty object {grid or zip key: value}");
      std::vector<std::pair<std::size_t, Json>> selection;
      for (const auto& [key, value] : list[o].items()) {
        const auto k = std::find(keys.begin(), keys.end(), key);
        if (k == keys.end())
          throw InputError(ctx.config_file, where + "." + key, "not a key of `grid` or `zip`");
        const std::size_t axis = static_cast<std::size_t>(k - keys.begin());
        const std::vector<Json>& values = axis < grid.size() ? grid[axis].values : zip[axis - grid.size()].values;
        if (std::find(values.begin(), values.end(), value) == values.end())
          throw InputError(ctx.config_file, where + "." + key, value.dump() + " is not one of its values");
        selection.emplace_back(axis, value);
      }
      overlays.push_back(std::move(selection));
    }
  }

  // The base document of each case, validated once.
  std::vector<Json> bases;
  std::vector<ConfigSource> sources;
  for (std::size_t c = 0; c < cases.size(); ++c) {
    const std::string where = std::string("cases[") + std::to_string(c) + "]";
    Json base = cases[c].config.empty() ? scene_doc : load_config_json(cases[c].config);
    if (!inline_configs[c].is_null()) {
      if (!cases[c].config.empty()) throw InputError(ctx.config_file, where + ".config", "give a file or an object");
      merge_into(base, inline_configs[c]);
    }
    for (const std::string& assignment : cases[c].set) apply_assignment(base, assignment);
    sources.push_back(cases[c].config.empty() ? ctx.source : config_source(cases[c].config));
    try {
      scene_from_json(base, sources.back());
    } catch (const InputError& e) {
      throw InputError(ctx.config_file, where, std::string("case '") + cases[c].name + "': " + e.what());
    }
    bases.push_back(std::move(base));
  }

  // Every case × cartesian product of the grid × each zip row.
  std::vector<Point> points;
  const std::size_t zip_rows = zip.empty() ? 1 : zip.front().values.size();
  for (std::size_t c = 0; c < cases.size(); ++c) {
    std::vector<std::size_t> index(grid.size(), 0);
    for (bool more = true; more;) {
      for (std::size_t z = 0; z < zip_rows; ++z) {
        Point p;
        p.case_index = c;
        for (std::size_t g = 0; g < grid.size(); ++g) p.values.push_back(grid[g].values[index[g]]);
        for (const Axis& a : zip) p.values.push_back(a.values[z]);
        for (const auto& selection : overlays)
          p.overlay = p.overlay || std::all_of(selection.begin(), selection.end(), [&](const auto& s) {
                        return p.values[s.first] == s.second;
                      });
        points.push_back(std::move(p));
      }
      more = false;
      for (std::size_t g = grid.size(); g-- > 0;) {
        if (++index[g] < grid[g].values.size()) {
          more = true;
          break;
        }
        index[g] = 0;
      }
    }
  }

  if (ctx.validate_only) {
    std::cout << dump_json(doc);
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << points.size() << " runs)\n";
    return 0;
  }

  // The study's fingerprint: everything that decides what each run computes.
  Json identity = Json::object();
  identity["keys"] = keys;
  Json case_list = Json::array(), point_list = Json::array();
  for (std::size_t c = 0; c < cases.size(); ++c)
    case_list.push_back(Json{{"name", cases[c].name}, {"dir", sources[c].dir}, {"config", bases[c]}});
  for (const Point& p : points)
    point_list.push_back(Json{{"case", p.case_index}, {"values", p.values}, {"overlay", p.overlay}});
  identity["cases"] = case_list;
  identity["points"] = point_list;
  const std::string hash = fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));

  const std::string name = doc.value("name", std::string("compare"));
  const bool root = mpi::rank() == 0;
  const bool distributed = mpi::size() > 1;

  // Rank 0 reads the journal; the runs still to do go to every rank.
  std::unique_ptr<Journal> journal;
  std::map<std::size_t, Json> records;
  std::vector<std::size_t> pending;
  std::string failure;  // rank 0's reason to stop, shared with the other ranks
  if (root) {
    try {
      std::filesystem::create_directories(ctx.out_dir);
      journal = std::make_unique<Journal>(ctx.out_dir / "journal.jsonl", "compare", hash, points.size());
      records = journal->done();
    } catch (const InputError& e) {
      if (!distributed) throw;
      failure = std::string("2") + e.what();
    } catch (const std::exception& e) {
      if (!distributed) throw;
      failure = std::string("1") + e.what();
    }
    for (std::size_t i = 0; i < points.size(); ++i)
      if (!records.count(i)) pending.push_back(i);
  }
  if (distributed) {
    Json shared{{"failure", failure}, {"pending", pending}};
    shared = Json::parse(mpi::broadcast(shared.dump()));
    failure = shared["failure"].get<std::string>();
    pending = shared["pending"].get<std::vector<std::size_t>>();
    if (!failure.empty()) {
      if (!root) return failure[0] - '0';  // rank 0 says why
      std::cerr << "camdyn: error: " << failure.substr(1) << "\n";
      return failure[0] - '0';
    }
  }
  std::size_t resumed_failed = 0;
  for (const auto& [i, record] : records)
    if (record.value("status", std::string()) != "ok") ++resumed_failed;
  const std::size_t resumed = points.size() - pending.size();
  if (root && resumed > 0)
    std::cerr << "camdyn: resuming: " << resumed << " of " << points.size() << " runs already done ("
              << (ctx.out_dir / "journal.jsonl").string() << "), skipped\n";

  // One run, as its journal record.
  auto run_one = [&](std::size_t i) -> Json {
    const Point& p = points[i];
    Json record = Json::object();
    record["index"] = i;
    record["case"] = cases[p.case_index].name;
    Json at = Json::object();
    for (std::size_t k = 0; k < keys.size(); ++k) at[keys[k]] = p.values[k];
    record["point"] = at;
    std::vector<double> values;
    std::string error;
    double run_time = 0.0;
    Json overlay;
    try {
      Json run = bases[p.case_index];
      for (std::size_t k = 0; k < keys.size(); ++k) set_config_value(run, keys[k], p.values[k]);
      const SceneConfig scene = scene_from_json(run, sources[p.case_index]);
      SimulationOptions options;
      options.record_series = p.overlay && scene.mechanism.cam.rpm > 0;
      const SimulationResult r = simulate_scene(scene, ctx.config_file, options);
      throw_if_failed(r);
      values = metric_values(r.metrics);
      run_time = r.solver.run_time_s;
      for (std::size_t m = 0; m + 1 < values.size() && error.empty(); ++m)  // jump_speed_rpm may be +inf: empty
        if (!std::isfinite(values[m])) error = "non-finite metric " + kMetricNames[m];
      if (options.record_series) overlay = last_revolution(scene, r);
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "unknown error";
    }
    const bool ok = error.empty() && !values.empty();
    Json metrics_json = Json::object();
    for (std::size_t m = 0; m < kMetricNames.size(); ++m)
      metrics_json[kMetricNames[m]] = ok && std::isfinite(values[m]) ? Json(values[m]) : Json(nullptr);
    record["status"] = ok ? "ok" : "failed";
    record["error"] = error;
    record["metrics"] = metrics_json;
    record["run_time_s"] = run_time;
    if (ok && !overlay.is_null()) record["overlay"] = overlay;
    return record;
  };

  const auto wall_start = std::chrono::steady_clock::now();
  ProgressMeter progress("compare", points.size(), resumed, resumed_failed, ctx.progress && root);
  std::mutex mutex;
  auto finished = [&](Json record) {  // rank 0, serialised by the caller
    const std::size_t i = record["index"].get<std::size_t>();
    const bool failed = record["status"] != "ok";
    journal->append(record);
    records[i] = std::move(record);
    progress.finished(failed);
  };
  try {
    if (distributed) {
      mpi::distribute_runs(
          pending, [&](std::size_t i) { return run_one(i).dump(-1, ' ', false, Json::error_handler_t::replace); },
          [&](const std::string& text) { finished(Json::parse(text)); });
    } else {
      parallel_for(pending.size(), ctx.threads(), [&](std::size_t k) {
        Json record = run_one(pending[k]);
        const std::lock_guard<std::mutex> lock(mutex);
        finished(std::move(record));
      });
    }
  } catch (const std::exception& e) {
    if (!distributed) throw;
    // The other ranks may wait for rank 0 (or it for them): end them all.
    std::cerr << "camdyn: error: rank " << mpi::rank() << ": " << e.what() << "\n";
    mpi::abort_all(1);
  }
  if (!root) return 0;  // rank 0 writes the outputs
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  // Outputs, from the records in (case, grid point) order: a resumed study
  // writes exactly what an uninterrupted one does.
  std::vector<Outcome> outcomes;
  std::size_t failed = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    outcomes.push_back(outcome_of(records.at(i)));
    if (!outcomes.back().ok) ++failed;
  }

  // comparison.csv / .json
  std::vector<std::string> columns = {"case"};
  columns.insert(columns.end(), keys.begin(), keys.end());
  for (const std::string& m : kMetricNames) columns.push_back(m);
  columns.insert(columns.end(), {"status", "error", "run_time_s"});
  CsvWriter csv(ctx.out_dir / "comparison.csv", columns);
  Json rows = Json::array();
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    const Outcome& o = outcomes[i];
    std::vector<CsvCell> cells = {CsvCell(cases[p.case_index].name)};
    Json row{{"case", cases[p.case_index].name}};
    for (std::size_t k = 0; k < keys.size(); ++k) {
      cells.push_back(CsvCell(cell_text(p.values[k])));
      row[keys[k]] = p.values[k];
    }
    Json metrics_json = Json::object();
    for (std::size_t m = 0; m < kMetricNames.size(); ++m) {
      const bool have = o.ok && std::isfinite(o.metrics[m]);
      cells.push_back(have ? CsvCell(o.metrics[m]) : CsvCell(""));
      metrics_json[kMetricNames[m]] = have ? Json(o.metrics[m]) : Json(nullptr);
    }
    cells.emplace_back(o.ok ? "ok" : "failed");
    cells.emplace_back(o.error);
    cells.emplace_back(o.run_time_s);
    csv.row(cells);
    row["metrics"] = metrics_json;
    row["status"] = o.ok ? "ok" : "failed";
    row["error"] = o.error;
    row["run_time_s"] = o.run_time_s;
    rows.push_back(row);
  }
  csv.commit();
  write_json_atomic(ctx.out_dir / "comparison.json", Json{{"name", name},
                                                          {"study", "compare"},
                                                          {"camdyn_version", CAMDYN_VERSION},
                                                          {"runs", points.size()},
                                                          {"failed", failed},
                                                          {"resumed_runs", resumed},
                                                          {"run_time_s", wall},
                                                          {"results", rows}});

  // report.html
  std::map<std::string, std::size_t> metric_index;
  for (std::size_t m = 0; m < kMetricNames.size(); ++m) metric_index[kMetricNames[m]] = m;
  Report report;
  report.title = "camdyn: " + name;
  report.subtitle = "compare study: " + std::to_string(cases.size()) + " case(s) × " +
                    std::to_string(points.size() / cases.size()) + " grid point(s)";
  report.facts = {{"runs", std::to_string(points.size())},
                  {"failed", std::to_string(failed)},
                  {"wall time", format_number(wall, 3) + " s"}};
  if (resumed > 0) report.facts.push_back({"resumed from the journal", std::to_string(resumed) + " runs"});
  if (distributed) report.facts.push_back({"MPI ranks", std::to_string(mpi::size())});

  // Best value of each metric among the cases at the same grid point (over
  // all runs when there is one case), ties included, unless all tie.
  Table table{"Results (click a header to sort; ★ best case at that grid point)", {"case"}, {}, true};
  table.columns.insert(table.columns.end(), keys.begin(), keys.end());
  const std::size_t first_metric_column = table.columns.size();
  table.columns.insert(table.columns.end(), metrics.begin(), metrics.end());
  table.columns.push_back("status");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Point& p = points[i];
    std::vector<std::string> row = {cases[p.case_index].name};
    for (const Json& v : p.values) row.push_back(cell_text(v));
    for (const std::string& m : metrics)
      row.push_back(outcomes[i].ok ? format_number(outcomes[i].metrics[metric_index[m]], 4) : "–");
    row.push_back(outcomes[i].ok ? "ok" : "failed");
    table.rows.push_back(std::move(row));
  }
  std::map<std::vector<Json>, std::vector<std::size_t>> groups;  // grid point -> runs
  for (std::size_t i = 0; i < points.size(); ++i)
    groups[cases.size() > 1 ? points[i].values : std::vector<Json>{}].push_back(i);
  Table best{"Best case per metric", {"metric", "better", "most often best (grid points won)", "best value", "where"},
             {}, true};
  for (std::size_t mm = 0; mm < metrics.size(); ++mm) {
    const std::string& m = metrics[mm];
    const std::size_t mi = metric_index[m];
    std::map<std::string, std::size_t> wins;
    std::size_t contested = 0;
    for (const auto& [at, runs] : groups) {
      std::vector<std::size_t> valid;
      for (const std::size_t i : runs)
        if (outcomes[i].ok && std::isfinite(outcomes[i].metrics[mi])) valid.push_back(i);
      if (valid.size() < 2) continue;
      double top = outcomes[valid.front()].metrics[mi];
      for (const std::size_t i : valid)
        if (better_or_equal(m, outcomes[i].metrics[mi], top)) top = outcomes[i].metrics[mi];
      std::vector<std::size_t> winners;
      for (const std::size_t i : valid)
        if (better_or_equal(m, outcomes[i].metrics[mi], top)) winners.push_back(i);
      if (winners.size() == valid.size()) continue;  // all tie: nothing to mark
      ++contested;
      for (const std::size_t i : winners) {
        table.marked.emplace_back(i, first_metric_column + mm);
        ++wins[cases[points[i].case_index].name];
      }
    }
    // Overall best run for this metric.
    std::size_t overall = points.size();
    for (std::size_t i = 0; i < points.size(); ++i)
      if (outcomes[i].ok && std::isfinite(outcomes[i].metrics[mi]) &&
          (overall == points.size() || !better_or_equal(m, outcomes[overall].metrics[mi], outcomes[i].metrics[mi])))
        overall = i;
    std::string most = "–";
    if (!wins.empty() && cases.size() > 1) {
      std::size_t top_wins = 0;
      for (const auto& [c, n] : wins) top_wins = std::max(top_wins, n);
      most.clear();
      for (const auto& [c, n] : wins)
        if (n == top_wins) most += (most.empty() ? "" : ", ") + c;
      most += std::string(" (") + std::to_string(top_wins) + " of " + std::to_string(contested) + ")";
    }
    std::string where = "–", value = "–";
    if (overall < points.size()) {
      value = format_number(outcomes[overall].metrics[mi], 4);
      where = cases[points[overall].case_index].name;
      for (std::size_t k = 0; k < keys.size(); ++k) where += ", " + keys[k] + "=" + cell_text(points[overall].values[k]);
    }
    best.rows.push_back({m, kHigherIsBetter.count(m) ? "higher" : "lower", most, value, where});
  }
  report.tables.push_back(std::move(table));
  report.tables.push_back(std::move(best));

  if (!grid.empty() && grid.front().values.front().is_number()) {
    for (const std::string& m : metrics) {
      Plot plot;
      plot.title = m + " against " + grid.front().key;
      plot.xlabel = grid.front().key;
      plot.ylabel = m;
      std::map<std::string, Series> lines;  // one line per case and value of the other axes
      std::vector<std::string> order;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Point& p = points[i];
        if (!outcomes[i].ok || !std::isfinite(outcomes[i].metrics[metric_index[m]])) continue;
        std::string label = cases[p.case_index].name;
        for (std::size_t k = 1; k < p.values.size(); ++k) label += ", " + keys[k] + "=" + cell_text(p.values[k]);
        if (!lines.count(label)) order.push_back(label);
        Series& s = lines[label];
        s.label = label;
        s.style = "linespoints";
        s.x.push_back(p.values[0].get<double>());
        s.y.push_back(outcomes[i].metrics[metric_index[m]]);
      }
      if (lines.size() > 12) continue;  // too many lines to read: the table has them
      for (const std::string& label : order) plot.series.push_back(std::move(lines[label]));
      report.plots.push_back(std::move(plot));
    }
  }
  // Contact force and follower motion against cam angle at the chosen grid points.
  for (const auto& selection : overlays) {
    std::string at;
    for (const auto& [axis, value] : selection) at += (at.empty() ? "" : ", ") + keys[axis] + "=" + cell_text(value);
    Plot force{"Contact force against cam angle (last revolution), " + at, "cam angle [deg]", "contact force [N]",
               {}, false, false, std::make_pair(0.0, 360.0)};
    Plot motion{"Follower displacement against cam angle (last revolution), " + at, "cam angle [deg]",
                "follower displacement [m]", {}, false, false, std::make_pair(0.0, 360.0)};
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Point& p = points[i];
      const bool selected = std::all_of(selection.begin(), selection.end(),
                                        [&](const auto& s) { return p.values[s.first] == s.second; });
      if (!selected || outcomes[i].overlay == nullptr) continue;
      std::string label = cases[p.case_index].name;
      for (std::size_t k = 0; k < keys.size(); ++k)
        if (std::none_of(selection.begin(), selection.end(), [&](const auto& s) { return s.first == k; }))
          label += ", " + keys[k] + "=" + cell_text(p.values[k]);
      const Json& o = *outcomes[i].overlay;
      const auto x = o.at("cam_angle_deg").get<std::vector<double>>();
      force.series.push_back({label, x, o.at("contact_force").get<std::vector<double>>(), "lines"});
      motion.series.push_back({label, x, o.at("follower_position").get<std::vector<double>>(), "lines"});
    }
    if (force.series.empty()) continue;  // every selected run failed: the failures table says why
    report.plots.push_back(std::move(force));
    report.plots.push_back(std::move(motion));
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
    for (std::size_t i = 0; i < points.size(); ++i) {
      auto& f = any_failed[{points[i].values[0].get<double>(), points[i].values[1].get<double>()}];
      f = f || !outcomes[i].ok;
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
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!outcomes[i].ok) {
      std::string at;
      for (std::size_t k = 0; k < keys.size(); ++k) at += (k ? ", " : "") + keys[k] + "=" + cell_text(points[i].values[k]);
      failures.rows.push_back({cases[points[i].case_index].name, at, outcomes[i].error});
    }
  if (!failures.rows.empty()) report.tables.push_back(std::move(failures));
  report.notes.push_back("★ marks the best case at each grid point for that metric (lower is better, except "
                         "min_contact_force, min_radius_of_curvature and jump_speed_rpm; energy_residual by magnitude); "
                         "nothing is marked where all cases tie.");
  if (resumed > 0)
    report.notes.push_back(std::to_string(resumed) + " of " + std::to_string(points.size()) +
                           " runs were done by an earlier, interrupted invocation and read from journal.jsonl.");
  write_report(ctx.out_dir / "report.html", report);

  const std::string resumed_text = resumed > 0 ? std::string(" (") + std::to_string(resumed) + " resumed)" : "";
  std::printf("%s: %zu runs, %zu failed, %.3g s%s\n  comparison.csv and report: %s\n", name.c_str(), points.size(),
              failed, wall, resumed_text.c_str(),
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn
