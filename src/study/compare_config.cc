// The compare study's own config fields: `cases` and `metrics` through their
// `visit` (io/json_archive.h); `grid`, `zip` and `overlays`, whose keys are
// dotted paths rather than field names, by hand with the same kind of messages.
#include "study/compare_config.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/metrics.h"
#include "io/input_file.h"
#include "io/json_archive.h"

namespace camdyn {

const std::vector<std::string>& compare_study_keys() {
  static const std::vector<std::string> keys = {"cases", "grid", "zip", "metrics", "overlays"};
  return keys;
}

const std::vector<std::string>& compare_metric_names() {
  // Metrics' visit lists them once, then the train's (for_each_train_metric).
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all = metric_names();
    for (std::string& t : train_metric_names()) all.push_back(std::move(t));
    return all;
  }();
  return names;
}

bool higher_is_better(const std::string& metric) {
  static const std::set<std::string> higher = {"min_contact_force", "min_radius_of_curvature", "jump_speed_rpm",
                                               "min_link_force"};
  return higher.count(metric) > 0;
}

std::vector<std::string> CompareSpec::keys() const {
  std::vector<std::string> keys;
  for (const CompareAxis& a : grid) keys.push_back(a.key);
  for (const CompareAxis& a : zip) keys.push_back(a.key);
  return keys;
}

const std::vector<Json>& CompareSpec::axis_values(std::size_t axis) const {
  return axis < grid.size() ? grid[axis].values : zip[axis - grid.size()].values;
}

template <class A>
void visit(A& a, CompareCase& c) {
  a.field("name", c.name, non_empty());
  a.field("config", c.config);
  a.field("set", c.set);
}

template <class A>
void visit(A& a, CompareSpec& s) {
  a.field("cases", s.cases);
  a.field("metrics", s.metrics, one_of(compare_metric_names()));
}

namespace {

/// `cases` and `metrics`. A case's `config` is a file name or an inline config;
/// the reader sees only file names, the objects are put back afterwards.
void read_fields(const Json& part, const StudyContext& ctx, CompareSpec& spec) {
  std::vector<Json> inline_configs;
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
  visit(reader, spec);
  reader.finish();
  for (std::size_t c = 0; c < spec.cases.size(); ++c) spec.cases[c].inline_config = inline_configs[c];
}

std::vector<CompareAxis> read_axes(const Json& part, const std::string& key, const StudyContext& ctx) {
  std::vector<CompareAxis> axes;
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

/// `overlays`: grid points (some axes fixed) whose runs get contact force and
/// follower motion against cam angle plotted, one line per run.
std::vector<OverlaySelection> read_overlays(const Json& part, const CompareSpec& spec, const StudyContext& ctx) {
  std::vector<OverlaySelection> overlays;
  if (!part.contains("overlays")) return overlays;
  const std::vector<std::string> keys = spec.keys();
  const Json& list = part["overlays"];
  if (!list.is_array()) throw InputError(ctx.config_file, "overlays", "expected an array of {dotted path: value}");
  for (std::size_t o = 0; o < list.size(); ++o) {
    const std::string where = std::string("overlays[") + std::to_string(o) + "]";
    if (!list[o].is_object() || list[o].empty())
      throw InputError(ctx.config_file, where, "expected a non-empty object {grid or zip key: value}");
    OverlaySelection selection;
    for (const auto& [key, value] : list[o].items()) {
      const auto k = std::find(keys.begin(), keys.end(), key);
      if (k == keys.end()) throw InputError(ctx.config_file, where + "." + key, "not a key of `grid` or `zip`");
      const std::size_t axis = static_cast<std::size_t>(k - keys.begin());
      const std::vector<Json>& values = spec.axis_values(axis);
      if (std::find(values.begin(), values.end(), value) == values.end())
        throw InputError(ctx.config_file, where + "." + key,
                         value.dump(-1, ' ', false, Json::error_handler_t::replace) + " is not one of its values");
      selection.emplace_back(axis, value);
    }
    overlays.push_back(std::move(selection));
  }
  return overlays;
}

/// What one run of a compare study holds until the study ends: its grid
/// point, its outcome (metrics, message) and its row of the table [bytes].
constexpr double kBytesPerCompareRun = 1024.0;

/// Refuses a study whose runs (cases × grid points × zip rows) would not fit
/// the memory budget, before any is listed: two axes of 1e5 values each ask
/// for 1e10 runs, which would exhaust the machine's memory, not end.
void require_runs_in_memory_budget(const CompareSpec& spec, const StudyContext& ctx) {
  double runs = static_cast<double>(spec.cases.size());  // as a double: the product may overflow an integer
  for (const CompareAxis& a : spec.grid) runs *= static_cast<double>(a.values.size());
  if (!spec.zip.empty()) runs *= static_cast<double>(spec.zip.front().values.size());
  const double bytes = runs * kBytesPerCompareRun;
  if (bytes > memory_budget_bytes())
    throw InputError(ctx.config_file, spec.grid.empty() ? "zip" : "grid",
                     "the study asks for " + format_shortest(runs) + " runs (cases x grid points x zip rows), about " +
                         format_shortest(std::ceil(bytes / kBytesPerMb)) + " MB to hold them: " + memory_budget_text() +
                         ": use fewer values, or split the study");
}

}  // namespace

CompareSpec compare_spec_from_json(const Json& study_part, const std::string& default_case, const StudyContext& ctx) {
  CompareSpec spec;
  read_fields(study_part, ctx, spec);
  if (spec.cases.empty()) spec.cases.push_back({default_case, "", {}, Json()});
  std::set<std::string> names;
  for (std::size_t c = 0; c < spec.cases.size(); ++c) {
    CompareCase& one = spec.cases[c];
    if (!names.insert(one.name).second)
      throw InputError(ctx.config_file, std::string("cases[") + std::to_string(c) + "].name",
                       "case '" + one.name + "' is named twice");
    if (!one.config.empty()) {
      one.config = absolute_path(one.config, ctx.source.dir);
      const std::string field = std::string("cases[") + std::to_string(c) + "].config";
      try {
        check_input_file(one.config, field);  // a regular file within the memory budget (io/input_file.h)
      } catch (const InputError& e) {
        throw InputError(ctx.config_file, field, "'" + one.config + "': " + e.reason());
      }
    }
  }
  spec.grid = read_axes(study_part, "grid", ctx);
  spec.zip = read_axes(study_part, "zip", ctx);
  for (const CompareAxis& a : spec.zip)
    if (a.values.size() != spec.zip.front().values.size())
      throw InputError(ctx.config_file, "zip." + a.key, "every zip list must have the same length");
  require_runs_in_memory_budget(spec, ctx);
  spec.overlays = read_overlays(study_part, spec, ctx);
  return spec;
}

}  // namespace camdyn
