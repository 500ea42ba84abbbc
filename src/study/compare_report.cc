// report.html of a compare study: the verdict (the best case, ranked with
// separation first), the cases at a glance, the best case per metric, a
// pass/fail map over the first two numeric grid axes, each metric against the
// first grid axis, the overlays (contact force and follower motion against cam
// angle), the cam of the first case to scale with its SVAJ, then the results
// table with the best case per grid point marked and the failed runs.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string_view>

#include "common/errors.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/metrics.h"
#include "io/dotted_path.h"
#include "output/cam_plots.h"
#include "output/report.h"
#include "study/compare_output.h"

namespace camdyn {

namespace {

std::size_t metric_index(const std::string& metric) {
  const std::vector<std::string>& names = compare_metric_names();
  return static_cast<std::size_t>(std::find(names.begin(), names.end(), metric) - names.begin());
}

/// Whether `a` is at least as good as `b` for `metric` (ties within 1e-12 relative).
bool better_or_equal(const std::string& metric, double a, double b) {
  const double tie = 1e-12 * std::max(std::abs(a), std::abs(b));
  if (metric == "energy_residual") return std::abs(a) <= std::abs(b) + tie;
  return higher_is_better(metric) ? a >= b - tie : a <= b + tie;
}

bool has_metric(const CompareResult& r, std::size_t i, std::size_t mi) {
  return r.outcomes[i].ok && std::isfinite(r.outcomes[i].metrics[mi]);
}

/// Separation fractions closer than this count as equal when ranking [–]
/// (0.1 % of the evaluated time: a graze, not a jump).
constexpr double kSeparationTie = 1e-3;

/// A run's separation fraction [–]; +inf for a failed run or one without it.
double separation(const CompareResult& r, std::size_t i) {
  const std::size_t mi = metric_index("separation_fraction");
  return has_metric(r, i, mi) ? r.outcomes[i].metrics[mi] : std::numeric_limits<double>::infinity();
}

/// Separation first: of `runs`, those that separate least (within
/// kSeparationTie). A run airborne for much of the time is never best on a
/// force or speed metric, however low its numbers are.
std::vector<std::size_t> least_separated(const CompareResult& r, const std::vector<std::size_t>& runs) {
  double least = std::numeric_limits<double>::infinity();
  for (const std::size_t i : runs) least = std::min(least, separation(r, i));
  std::vector<std::size_t> out;
  for (const std::size_t i : runs)
    if (!std::isfinite(least) || separation(r, i) <= least + kSeparationTie) out.push_back(i);
  return out;
}

/// The unit of the follower coordinate the successful runs `points` share,
/// or "m or rad" when they mix translating and oscillating followers.
std::string coordinate_unit(const CompareResult& r, const std::vector<std::size_t>& points) {
  std::string unit;
  for (const std::size_t i : points) {
    if (!r.outcomes[i].ok) continue;
    if (!unit.empty() && unit != r.outcomes[i].coordinate_unit) return "m or rad";
    unit = r.outcomes[i].coordinate_unit;
  }
  return unit.empty() ? "m" : unit;
}

std::vector<std::size_t> all_points(const CompareResult& r) {
  std::vector<std::size_t> points(r.points.size());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = i;
  return points;
}

/// The unit of a metric as the metrics table prints it ("–": dimensionless);
/// one measured in the follower coordinate takes the runs' unit.
std::string metric_unit(const CompareResult& r, const std::string& metric) {
  std::string unit = "–";
  const Metrics none;
  for_each_metric(none, [&](const char* name, const auto&, const MetricInfo& info) {
    if (metric == name) unit = info.in_coordinate ? coordinate_unit(r, all_points(r)) : info.unit;
  });
  TrainMetrics train;
  train.links = train.seats = train.springs = train.clash = train.lash = true;
  for_each_train_metric(train, [&](const char* name, double, bool, const char* u) {
    if (metric == name) unit = u;
  });
  return unit;
}

/// An axis label for a grid key (a dotted config path) with its unit in
/// brackets: SI as the config takes it, from the field's name; a follower
/// field measured along q (the spring, the damper) in an arm's units when
/// every run is an arm's.
std::string key_label(const CompareResult& r, const std::string& key) {
  if (coordinate_unit(r, all_points(r)) == "rad") {
    const std::string unit =
        coordinate_field_unit(full_dotted_path(key), coordinate_units(FollowerMotion::oscillating));
    if (!unit.empty()) return key + " [" + unit + "]";
  }
  const std::string leaf = key.substr(key.rfind('.') + 1);
  const auto ends_with = [&](std::string_view tail) { return leaf.size() >= tail.size() && leaf.ends_with(tail); };
  static const std::map<std::string, std::string> units = {{"rpm", "rpm"},
                                                           {"mass", "kg"},
                                                           {"preload", "N"},
                                                           {"damping", "N s/m"},
                                                           {"base_radius", "m"},
                                                           {"radius", "m"},
                                                           {"offset", "m"},
                                                           {"lift", "m"},
                                                           {"face_width", "m"},
                                                           {"arm_length", "m"},
                                                           {"width", "m"},
                                                           {"inertia", "kg m²"},
                                                           {"gravity", "m/s²"},
                                                           {"reference_velocity", "m/s"},
                                                           {"duration", "s"},
                                                           {"output_step", "s"},
                                                           {"restitution", "–"},
                                                           {"exponent", "–"},
                                                           {"mu", "–"},
                                                           {"rtol", "–"},
                                                           {"atol", "–"},
                                                           {"cycles", "–"},
                                                           {"discard_cycles", "–"},
                                                           {"control_points", "–"}};
  std::string unit;
  if (ends_with("_deg"))
    unit = "deg";
  else if (ends_with("_rpm"))
    unit = "rpm";
  else if (leaf == "stiffness")
    unit = key.find("contact") != std::string::npos ? "N/mⁿ" : "N/m (N m/rad for an arm)";
  else if (const auto it = units.find(leaf); it != units.end())
    unit = it->second;
  else
    unit = "SI, as in the config";
  return key + " [" + unit + "]";
}

/// The chosen metrics that some run has: a metric that applies to none of
/// the scenes (a train's on single followers, a seat's without one) is no
/// column of empty cells.
std::vector<std::string> shown_metrics(const CompareResult& r) {
  if (std::none_of(r.outcomes.begin(), r.outcomes.end(), [](const CompareOutcome& o) { return o.ok; }))
    return r.spec->metrics;  // nothing ran: every column, each "–"
  std::vector<std::string> shown;
  for (const std::string& m : r.spec->metrics)
    for (std::size_t i = 0; i < r.points.size(); ++i)
      if (has_metric(r, i, metric_index(m))) {
        shown.push_back(m);
        break;
      }
  return shown;
}

/// Every run with the shown metrics, one row each.
Table results_table(const CompareResult& r) {
  const std::vector<std::string> metrics = shown_metrics(r);
  Table table{"Results (click a header to sort; ★ best case at that grid point)", {"case"}, {}, true};
  table.columns.insert(table.columns.end(), r.keys.begin(), r.keys.end());
  table.columns.insert(table.columns.end(), metrics.begin(), metrics.end());
  table.columns.push_back("status");
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const CompareOutcome& o = r.outcomes[i];
    std::vector<std::string> row = {r.case_name(i)};
    for (const Json& v : r.points[i].values) row.push_back(cell_text(v));
    for (const std::string& m : metrics) row.push_back(o.ok ? format_number(o.metrics[metric_index(m)], 4) : "–");
    row.push_back(o.ok ? "ok" : "failed");
    table.rows.push_back(std::move(row));
  }
  return table;
}

/// Marks in `table` (column `column`) the best runs of `metric` at each grid
/// point, ties included, unless all tie; returns the wins per case and the
/// number of grid points where there was a winner.
std::pair<std::map<std::string, std::size_t>, std::size_t> mark_winners(
    const CompareResult& r, const std::map<std::vector<Json>, std::vector<std::size_t>>& groups,
    const std::string& metric, Table& table, std::size_t column) {
  const std::size_t mi = metric_index(metric);
  std::map<std::string, std::size_t> wins;
  std::size_t contested = 0;
  for (const auto& [at, runs] : groups) {
    std::vector<std::size_t> valid;
    for (const std::size_t i : runs)
      if (has_metric(r, i, mi)) valid.push_back(i);
    if (valid.size() < 2) continue;
    const std::vector<std::size_t> contenders = least_separated(r, valid);
    double top = r.outcomes[contenders.front()].metrics[mi];
    for (const std::size_t i : contenders)
      if (better_or_equal(metric, r.outcomes[i].metrics[mi], top)) top = r.outcomes[i].metrics[mi];
    std::vector<std::size_t> winners;
    for (const std::size_t i : contenders)
      if (better_or_equal(metric, r.outcomes[i].metrics[mi], top)) winners.push_back(i);
    if (winners.size() == valid.size()) continue;  // all tie: nothing to mark
    ++contested;
    for (const std::size_t i : winners) {
      table.marked.emplace_back(i, column);
      ++wins[r.case_name(i)];
    }
  }
  return {wins, contested};
}

/// One row of the "best case per metric" table.
std::vector<std::string> best_row(const CompareResult& r, const std::string& metric,
                                  const std::map<std::string, std::size_t>& wins, std::size_t contested) {
  const std::size_t mi = metric_index(metric);
  std::vector<std::size_t> all;
  for (std::size_t i = 0; i < r.points.size(); ++i)
    if (has_metric(r, i, mi)) all.push_back(i);
  std::size_t overall = r.points.size();  // the overall best run for this metric, separation first
  for (const std::size_t i : least_separated(r, all))
    if ((overall == r.points.size() ||
         !better_or_equal(metric, r.outcomes[overall].metrics[mi], r.outcomes[i].metrics[mi])))
      overall = i;
  std::string most = "–";
  if (!wins.empty() && r.spec->cases.size() > 1) {
    std::size_t top_wins = 0;
    for (const auto& [c, n] : wins) top_wins = std::max(top_wins, n);
    most.clear();
    for (const auto& [c, n] : wins)
      if (n == top_wins) most += (most.empty() ? "" : ", ") + c;
    most += std::string(" (") + std::to_string(top_wins) + " of " + std::to_string(contested) + ")";
  }
  std::string where = "–", value = "–";
  if (overall < r.points.size()) {
    value = format_number(r.outcomes[overall].metrics[mi], 4);
    where = r.case_name(overall);
    for (std::size_t k = 0; k < r.keys.size(); ++k)
      where += ", " + r.keys[k] + "=" + cell_text(r.points[overall].values[k]);
  }
  return {metric, higher_is_better(metric) ? "higher" : "lower", most, value, where};
}

/// Best value of each metric among the cases at the same grid point (over all
/// runs when there is one case), marked in `table`; the summary per metric.
Table best_table(const CompareResult& r, Table& table) {
  const std::size_t first_metric_column = 1 + r.keys.size();
  std::map<std::vector<Json>, std::vector<std::size_t>> groups;  // grid point -> runs
  for (std::size_t i = 0; i < r.points.size(); ++i)
    groups[r.spec->cases.size() > 1 ? r.points[i].values : std::vector<Json>{}].push_back(i);
  Table best{"Best case per metric",
             {"metric", "better", "most often best (grid points won)", "best value", "where"},
             {},
             true};
  const std::vector<std::string> metrics = shown_metrics(r);  // results_table's columns
  for (std::size_t mm = 0; mm < metrics.size(); ++mm) {
    const std::string& m = metrics[mm];
    const auto [wins, contested] = mark_winners(r, groups, m, table, first_metric_column + mm);
    best.rows.push_back(best_row(r, m, wins, contested));
  }
  return best;
}

/// Each metric against the first grid axis, one line per case and value of the other axes.
std::vector<Plot> metric_plots(const CompareResult& r) {
  std::vector<Plot> plots;
  const std::vector<CompareAxis>& grid = r.spec->grid;
  if (grid.empty() || !grid.front().values.front().is_number()) return plots;
  for (const std::string& m : r.spec->metrics) {
    Plot plot;
    plot.title = m + " against " + grid.front().key;
    plot.xlabel = key_label(r, grid.front().key);
    plot.ylabel = m + " [" + metric_unit(r, m) + "]";
    std::map<std::string, Series> lines;
    std::vector<std::string> order;
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      const ComparePoint& p = r.points[i];
      if (!has_metric(r, i, metric_index(m))) continue;
      std::string label = r.case_name(i);
      for (std::size_t k = 1; k < p.values.size(); ++k) label += ", " + r.keys[k] + "=" + cell_text(p.values[k]);
      if (!lines.count(label)) order.push_back(label);
      Series& s = lines[label];
      s.label = label;
      s.style = "linespoints";
      s.x.push_back(p.values[0].get<double>());
      s.y.push_back(r.outcomes[i].metrics[metric_index(m)]);
    }
    // No run has it (a metric that does not apply to the scene, e.g. a flat
    // face's excursion on a roller), or too many lines to read: the table has them.
    if (lines.empty() || lines.size() > 12) continue;
    for (const std::string& label : order) plot.series.push_back(std::move(lines[label]));
    plots.push_back(std::move(plot));
  }
  return plots;
}

/// Contact force and follower motion against cam angle at the chosen grid points.
std::vector<Plot> overlay_plots(const CompareResult& r) {
  std::vector<Plot> plots;
  for (const OverlaySelection& selection : r.spec->overlays) {
    std::string at;
    for (const auto& [axis, value] : selection) at += (at.empty() ? "" : ", ") + r.keys[axis] + "=" + cell_text(value);
    Plot force{"Contact force against cam angle (last revolution), " + at,
               "cam angle [deg]",
               "contact force [N]",
               {},
               false,
               false,
               std::make_pair(0.0, 360.0)};
    std::vector<std::size_t> shown;  // the runs this overlay draws
    for (std::size_t i = 0; i < r.points.size(); ++i)
      if (r.outcomes[i].overlay.is_object() && std::all_of(selection.begin(), selection.end(), [&](const auto& s) {
            return r.points[i].values[s.first] == s.second;
          }))
        shown.push_back(i);
    const std::string unit = coordinate_unit(r, shown);
    Plot motion{"Follower displacement against cam angle (last revolution), " + at,
                "cam angle [deg]",
                CoordinateUnits::axis("follower displacement", unit),
                {},
                false,
                false,
                std::make_pair(0.0, 360.0)};
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      const ComparePoint& p = r.points[i];
      const bool selected =
          std::all_of(selection.begin(), selection.end(), [&](const auto& s) { return p.values[s.first] == s.second; });
      if (!selected || !r.outcomes[i].overlay.is_object()) continue;
      std::string label = r.case_name(i);
      for (std::size_t k = 0; k < r.keys.size(); ++k)
        if (std::none_of(selection.begin(), selection.end(), [&](const auto& s) { return s.first == k; }))
          label += ", " + r.keys[k] + "=" + cell_text(p.values[k]);
      const Json& o = r.outcomes[i].overlay;
      const auto x = o.at("cam_angle_deg").get<std::vector<double>>();
      force.series.push_back({label, x, o.at("contact_force").get<std::vector<double>>(), "lines"});
      motion.series.push_back({label, x, o.at("follower_position").get<std::vector<double>>(), "lines"});
    }
    if (force.series.empty()) continue;  // every selected run failed: the failures table says why
    if (unit == "m") {                   // a length: in µm, mm or m as the largest displacement needs
      std::vector<const std::vector<double>*> columns;
      for (const Series& s : motion.series) columns.push_back(&s.y);
      const LengthUnit length = length_unit(columns);
      motion.ylabel = length.axis("follower displacement");
      for (Series& s : motion.series) s.y = length.of(s.y);
    }
    plots.push_back(std::move(force));
    plots.push_back(std::move(motion));
  }
  return plots;
}

/// Pass/fail map over the first two numeric grid axes (every case and value of
/// the other axes overlaid: a point fails if any run there failed).
std::optional<Plot> pass_fail_map(const CompareResult& r) {
  const std::vector<CompareAxis>& grid = r.spec->grid;
  if (grid.size() < 2 || !grid[0].values.front().is_number() || !grid[1].values.front().is_number())
    return std::nullopt;
  const auto positive = [](const CompareAxis& a) {
    return std::all_of(a.values.begin(), a.values.end(), [](const Json& v) { return v.get<double>() > 0; });
  };
  Plot map;
  map.title = "Pass/fail map: " + grid[0].key + " against " + grid[1].key;
  map.xlabel = key_label(r, grid[0].key);
  map.ylabel = key_label(r, grid[1].key);
  map.logx = positive(grid[0]);
  map.logy = positive(grid[1]);
  std::map<std::pair<double, double>, bool> any_failed;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    auto& f = any_failed[{r.points[i].values[0].get<double>(), r.points[i].values[1].get<double>()}];
    f = f || !r.outcomes[i].ok;
  }
  Series ok_points{"all runs ok", {}, {}, "points"},
      failed_points{"some runs failed (see the table)", {}, {}, "points"};
  for (const auto& [xy, failed_here] : any_failed) {
    Series& s = failed_here ? failed_points : ok_points;
    s.x.push_back(xy.first);
    s.y.push_back(xy.second);
  }
  map.series = {ok_points, failed_points};
  return map;
}

/// The cam of the first case, as its scene gives it before the grid's values
/// (captioned so when the study has more than one run), with its SVAJ at its
/// speed, or per radian of cam angle when the speed may differ between runs.
void add_design_plots(const CompareResult& r, Report& report) {
  if (!r.design) return;
  const CompareCase& first = r.spec->cases.front();
  bool one_speed = std::none_of(r.keys.begin(), r.keys.end(), [](const std::string& k) { return k.ends_with("rpm"); });
  for (const CompareCase& c : r.spec->cases) {
    one_speed = one_speed && c.config.empty() && c.inline_config.is_null();
    for (const std::string& assignment : c.set) one_speed = one_speed && assignment.find("rpm") == std::string::npos;
  }
  const std::string caption = r.points.size() > 1 ? "base design: case '" + first.name + "'" +
                                                        (r.keys.empty() ? "" : " before the grid's values")
                                                  : "";
  try {
    for (Plot& plot : scene_cam_plots(*r.design, r.config_file, one_speed ? r.design->mechanism.cam.rpm : 0.0, caption))
      report.plots.push_back(std::move(plot));
  } catch (const InputError& e) {  // a case whose scene builds only with the grid's values
    report.notes.push_back("The cam of case '" + first.name + "' cannot be drawn: " + e.what());
  }
}

Table failures_table(const CompareResult& r) {
  Table failures{"Failed runs", {"case", "grid point", "reason"}, {}, false};
  failures.wrap = true;  // a reason is read whole
  for (std::size_t i = 0; i < r.points.size(); ++i)
    if (!r.outcomes[i].ok) {
      std::string at;
      for (std::size_t k = 0; k < r.keys.size(); ++k)
        at += (k ? ", " : "") + r.keys[k] + "=" + cell_text(r.points[i].values[k]);
      failures.rows.push_back({r.case_name(i), at, r.outcomes[i].error});
    }
  return failures;
}

/// One case over the whole grid, for the ranking at the top of the page.
struct CaseStanding {
  std::string name;
  std::size_t ok = 0, failed = 0;
  double worst_separation = 0.0;  ///< largest separation fraction over its runs [–]; +inf if none ran
  std::size_t wins = 0;           ///< cells marked best in the results table
  std::string first_error;
  /// With a cam-speed axis: the highest grid speed up to which every run of
  /// the case ran and kept contact [rpm]; −inf when its lowest speed does not.
  double holds_to_rpm = -std::numeric_limits<double>::infinity();
};

/// The grid's cam-speed axis (an index into r.keys), if it has one.
std::optional<std::size_t> speed_axis(const CompareResult& r) {
  for (std::size_t k = 0; k < r.keys.size(); ++k)
    if (r.keys[k] == "mechanism.cam.rpm") return k;
  return std::nullopt;
}

/// Each case's holds_to_rpm: runs taken by speed, the highest speed below
/// which no run failed or separated (at any value of the other axes).
void find_speeds_held(const CompareResult& r, std::size_t axis, std::vector<CaseStanding>& cases) {
  for (std::size_t c = 0; c < cases.size(); ++c) {
    std::vector<std::pair<double, bool>> runs;  // rpm, held
    for (std::size_t i = 0; i < r.points.size(); ++i) {
      if (r.points[i].case_index != c || !r.points[i].values[axis].is_number()) continue;
      runs.emplace_back(r.points[i].values[axis].get<double>(), r.outcomes[i].ok && separation(r, i) <= kSeparationTie);
    }
    std::sort(runs.begin(), runs.end());
    double held = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < runs.size(); ++k) {
      if (!runs[k].second) break;
      if (k + 1 == runs.size() || runs[k + 1].first > runs[k].first) held = runs[k].first;
    }
    cases[c].holds_to_rpm = held;
  }
}

/// The cases ranked: over a cam-speed axis, the highest speed held without
/// separation first; then fewest failed runs, least separation (within
/// kSeparationTie) and most metric comparisons won.
std::vector<CaseStanding> rank_cases(const CompareResult& r, const Table& marked_results) {
  std::vector<CaseStanding> cases(r.spec->cases.size());
  for (std::size_t c = 0; c < cases.size(); ++c) cases[c].name = r.spec->cases[c].name;
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    CaseStanding& s = cases[r.points[i].case_index];
    if (!r.outcomes[i].ok) {
      ++s.failed;
      if (s.first_error.empty()) s.first_error = r.outcomes[i].error;
      continue;
    }
    ++s.ok;
    const double sep = separation(r, i);
    if (std::isfinite(sep)) s.worst_separation = std::max(s.worst_separation, sep);
  }
  for (CaseStanding& s : cases)
    if (s.ok == 0) s.worst_separation = std::numeric_limits<double>::infinity();
  for (const auto& [row, column] : marked_results.marked) ++cases[r.points[row].case_index].wins;
  if (const std::optional<std::size_t> axis = speed_axis(r)) find_speeds_held(r, *axis, cases);
  std::stable_sort(cases.begin(), cases.end(), [](const CaseStanding& a, const CaseStanding& b) {
    if (a.holds_to_rpm != b.holds_to_rpm) return a.holds_to_rpm > b.holds_to_rpm;
    if (a.failed != b.failed) return a.failed < b.failed;
    if (std::abs(a.worst_separation - b.worst_separation) > kSeparationTie || !std::isfinite(a.worst_separation) ||
        !std::isfinite(b.worst_separation))
      return a.worst_separation < b.worst_separation;
    return a.wins > b.wins;
  });
  return cases;
}

/// "up to 1205 rpm", or "below the lowest speed" when the lowest does not hold.
std::string held_text(double holds_to_rpm) {
  return std::isfinite(holds_to_rpm) ? "up to " + format_number(holds_to_rpm) + " rpm" : "below the lowest speed";
}

Table standings_table(const std::vector<CaseStanding>& cases, bool by_speed) {
  Table t{by_speed ? "Cases at a glance (ranked: highest speed held without separation, then failed runs, then "
                     "separation, then metrics won)"
                   : "Cases at a glance (ranked: failed runs, then separation, then metrics won)",
          {"rank", "case", "runs ok", "failed", "worst separation fraction [–]", "best values (★)", "first failure"},
          {},
          false};
  if (by_speed) t.columns.insert(t.columns.begin() + 2, "holds without separation");
  t.wrap = true;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const CaseStanding& c = cases[k];
    t.rows.push_back({std::to_string(k + 1), c.name, std::to_string(c.ok), std::to_string(c.failed),
                      std::isfinite(c.worst_separation) ? format_number(c.worst_separation, 3) : "–",
                      std::to_string(c.wins), c.first_error.empty() ? "–" : c.first_error});
    if (by_speed) t.rows.back().insert(t.rows.back().begin() + 2, held_text(c.holds_to_rpm));
  }
  return t;
}

/// The banner: the best case (separation first) and how many runs failed.
Verdict compare_verdict(const CompareResult& r, const std::vector<CaseStanding>& cases) {
  Verdict v;
  const CaseStanding& best = cases.front();
  const std::string runs = std::to_string(r.points.size() - r.failed) + " of " + std::to_string(r.points.size()) +
                           " runs ok" + (r.failed ? ", " + std::to_string(r.failed) + " failed" : "");
  if (best.ok == 0) {
    v.tone = Verdict::Tone::bad;
    v.headline = "every run failed: " + best.first_error;
    return v;
  }
  const bool stays = best.worst_separation <= kSeparationTie;
  const std::string who = cases.size() > 1 ? "best: " + best.name : best.name;
  v.headline = stays ? who + " — stays in contact at every grid point"
                     : (cases.size() > 1 ? "every case separates somewhere; least: " + best.name : best.name) +
                           " — airborne up to " + format_number(100.0 * best.worst_separation, 3) + " % of the time";
  if (speed_axis(r) && cases.size() > 1 && !stays)
    v.headline = "best: " + best.name + " — holds without separation " + held_text(best.holds_to_rpm);
  if (cases.size() > 1) v.headline += ", " + std::to_string(best.wins) + " best values";
  v.tone = r.failed > 0 || !stays ? Verdict::Tone::warning : Verdict::Tone::good;
  v.details.push_back(runs);
  if (cases.size() > 1)
    v.details.push_back(speed_axis(r) ? "ranked on the highest speed held without separation, then the failed runs, "
                                        "the separation and the best values of the chosen metrics"
                                      : "ranked on the failed runs, then the separation, then the best values of the "
                                        "chosen metrics");
  return v;
}

}  // namespace

void write_compare_report(const CompareResult& r, const std::filesystem::path& out_dir) {
  Report report;
  report.title = "camdyn: " + r.name;
  report.subtitle = "compare study: " + std::to_string(r.spec->cases.size()) + " case(s) × " +
                    std::to_string(r.points.size() / r.spec->cases.size()) + " grid point(s)";
  report.facts = {{"runs", std::to_string(r.points.size())},
                  {"failed", std::to_string(r.failed)},
                  {"wall time", format_number(r.wall_time_s, 3) + " s"}};
  if (r.resumed > 0) report.facts.push_back({"resumed from the journal", std::to_string(r.resumed) + " runs"});
  if (r.mpi_ranks > 1) report.facts.push_back({"MPI ranks", std::to_string(r.mpi_ranks)});

  Table table = results_table(r);
  Table best = best_table(r, table);
  const std::vector<CaseStanding> cases = rank_cases(r, table);
  report.verdict = compare_verdict(r, cases);
  report.tables.push_back(standings_table(cases, speed_axis(r).has_value()));
  report.tables.push_back(std::move(best));
  if (std::optional<Plot> map = pass_fail_map(r)) report.plots.push_back(std::move(*map));
  for (Plot& plot : metric_plots(r)) report.plots.push_back(std::move(plot));
  for (Plot& plot : overlay_plots(r)) report.plots.push_back(std::move(plot));
  add_design_plots(r, report);
  report.appendix.push_back(std::move(table));
  Table failures = failures_table(r);
  if (!failures.rows.empty()) report.appendix.push_back(std::move(failures));
  report.notes.push_back(
      "★ marks the best case at each grid point for that metric (lower is better, except "
      "min_contact_force, min_radius_of_curvature and jump_speed_rpm; energy_residual by magnitude); "
      "separation comes first: only the runs that separate least there (within 0.1 % of the time) compete, so a "
      "run that is airborne is never best on a force or a speed. Nothing is marked where all cases tie.");
  if (r.resumed > 0)
    report.notes.push_back(std::to_string(r.resumed) + " of " + std::to_string(r.points.size()) +
                           " runs were done by an earlier, interrupted invocation and read from journal.jsonl.");
  write_report(out_dir / "report.html", report);
}

}  // namespace camdyn
