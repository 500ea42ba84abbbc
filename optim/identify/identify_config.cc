#include "optim/identify/identify_config.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "common/errors.h"
#include "dynamics/simulation.h"
#include "io/json_archive.h"
#include "io/suggest.h"

namespace camdyn::optim {

namespace {

const std::vector<std::string> kLosses = {"none", "huber", "cauchy", "soft_l1"};
const std::vector<std::string> kDifferences = {"forward", "central"};

}  // namespace

// ---------------------------------------------------------------- visit (one place per struct)

// The keyed maps (signals, weights, set, parameters) have user-chosen keys, which
// the archive cannot list: `visit` only admits them and read_maps() below checks them.

/// The most starts of a fit (solver.starts).
constexpr double kMaxFitStarts = 1000;

template <class A>
void visit(A& a, ReferenceSpec& r) {
  a.path_field("file", r.file, non_empty());
  a.field("time_column", r.time_column, non_empty());
  a.allow("signals", Json::value_t::object);
  a.allow("weights", Json::value_t::object);
  a.require(a.given("signals", true), "signals",
            "missing (expected an object: timeseries column → column of the file, e.g. "
            "{ \"contact_force\": \"force_N\" })");
}

template <class A>
void visit(A& a, ExperimentSpec& e) {
  a.field("name", e.name);  // empty: "experiment_<n>"
  a.field("reference", e.reference);
  a.allow("set", Json::value_t::object);
}

template <class A>
void visit(A& a, ParameterSpec& p) {
  a.field("initial", p.initial);
  a.field("lower", p.lower);
  a.field("upper", p.upper);
  a.field("log_scale", p.log_scale);
  a.require(!(p.lower && p.upper) || *p.lower < *p.upper, "upper",
            "must be greater than 'lower' (" + format_shortest(p.lower.value_or(0.0)) + "), got " +
                format_shortest(p.upper.value_or(0.0)));
  if (p.log_scale) {
    a.require(!p.lower || *p.lower > 0.0, "lower",
              "must be > 0 with log_scale (the fit works on ln(value)), got " + format_shortest(p.lower.value_or(0.0)));
    a.require(!p.initial || *p.initial > 0.0, "initial",
              "must be > 0 with log_scale, got " + format_shortest(p.initial.value_or(0.0)));
  }
  if (p.initial) {
    a.require(!p.lower || *p.initial >= *p.lower, "initial",
              "must be >= lower (" + format_shortest(p.lower.value_or(0.0)) + "), got " + format_shortest(*p.initial));
    a.require(!p.upper || *p.initial <= *p.upper, "initial",
              "must be <= upper (" + format_shortest(p.upper.value_or(0.0)) + "), got " + format_shortest(*p.initial));
  }
}

template <class A>
void visit(A& a, SolverSpec& s) {
  a.field("max_iterations", s.max_iterations, at_least(1));
  a.field("loss", s.loss, one_of(kLosses));
  a.field("loss_scale", s.loss_scale, positive());
  a.require(!s.loss_scale || (*s.loss_scale >= kMinLossScale && *s.loss_scale <= kMaxLossScale), "loss_scale",
            "must be in [" + format_shortest(kMinLossScale) + ", " + format_shortest(kMaxLossScale) +
                "] (its square must be a finite, normal number), got " + format_shortest(s.loss_scale.value_or(0.0)));
  a.field("function_tolerance", s.function_tolerance, positive());
  a.field("gradient_tolerance", s.gradient_tolerance, positive());
  a.field("parameter_tolerance", s.parameter_tolerance, positive());
  a.field("fd_relative_step", s.fd_relative_step, open_closed(0.0, 0.1));
  a.field("differences", s.differences, one_of(kDifferences));
  a.field("initial_trust_region_radius", s.initial_trust_region_radius, positive());
  a.require(
      s.initial_trust_region_radius >= kMinTrustRegionRadius && s.initial_trust_region_radius <= kMaxTrustRegionRadius,
      "initial_trust_region_radius",
      "must be in [" + format_shortest(kMinTrustRegionRadius) + ", " + format_shortest(kMaxTrustRegionRadius) +
          "] (Ceres' own trust-region limits), got " + format_shortest(s.initial_trust_region_radius));
  a.field("smoothing", s.smoothing, positive());
  a.field("max_relative_std_error", s.max_relative_std_error, positive());
  a.field("max_measured_values", s.max_measured_values, at_least(1));
  // Each start is a whole fit: 2e9 of them would run for ever.
  a.field("starts", s.starts, at_least(1), open_closed(0, kMaxFitStarts));
}

template <class A>
void visit(A& a, IdentifySpec& s) {
  const bool reference = a.given("reference", s.single_reference);
  const bool experiments = a.given("experiments", !s.single_reference);
  a.require(reference != experiments, "",
            "needs exactly one of 'reference' (one record of the scene as it is) or 'experiments' "
            "(several records fitted together, each with its own 'reference' and scene overrides 'set')");
  if (reference) {
    s.single_reference = true;
    s.experiments.resize(1);
    s.experiments[0].name = "reference";
    a.field("reference", s.experiments[0].reference);
  }
  if (experiments) a.field("experiments", s.experiments, non_empty());
  a.allow("parameters", Json::value_t::object);
  a.require(a.given("parameters", true), "parameters",
            "missing (expected an object: dotted config path → { \"initial\", \"lower\", \"upper\", \"log_scale\" })");
  a.field("solver", s.solver);
}

// ---------------------------------------------------------------- keyed maps

namespace {

[[noreturn]] void fail(const ConfigSource& source, const std::string& path, const std::string& reason) {
  throw InputError(source.file, path, reason);
}

void read_reference_maps(const Json& raw, const std::string& path, const ConfigSource& source, ReferenceSpec& r) {
  const std::vector<std::string> names = identify_signal_names();
  const Json& signals = raw.at("signals");
  if (signals.empty())
    fail(source, path + ".signals", "must name at least one signal (e.g. { \"contact_force\": \"force_N\" })");
  for (const auto& [key, value] : signals.items()) {
    const std::string at = path + ".signals." + key;
    // A train's columns (docs/model.md §12) are checked against the scene's train when it is built.
    if (std::find(names.begin(), names.end(), key) == names.end() && !is_train_column_name(key)) {
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      const std::string hint = did_you_mean(key, names);
      fail(source, at, "'" + key + "' is not a timeseries column" + (hint.empty() ? " (one of " + list + ")" : hint));
    }
    if (!value.is_string() || value.get<std::string>().empty())
      fail(source, at, "expected the name of a column of " + r.file + ", got " + describe_json(value));
    r.signals.emplace_back(key, value.get<std::string>());
  }
  if (const auto it = raw.find("weights"); it != raw.end() && it->is_object()) {
    for (const auto& [key, value] : it->items()) {
      const std::string at = path + ".weights." + key;
      const bool known =
          std::any_of(r.signals.begin(), r.signals.end(), [&name = key](const auto& s) { return s.first == name; });
      if (!known) {
        std::vector<std::string> given;
        for (const auto& s : r.signals) given.push_back(s.first);
        fail(source, at, "'" + key + "' is not one of this reference's signals" + did_you_mean(key, given));
      }
      if (value.is_null()) continue;  // default weight
      if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() <= 0.0)
        fail(source, at, "expected a weight > 0 [1/unit of the signal] or null, got " + describe_json(value));
      r.weights.emplace_back(key, value.get<double>());
    }
  }
}

/// `set` values are scalars, so nested objects (as `--set experiments[0].set.cam.rpm=900`
/// makes them) are dotted paths.
void read_set_entries(const Json& object, const std::string& prefix, const std::string& path,
                      const ConfigSource& source, ExperimentSpec& e) {
  for (const auto& [key, value] : object.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    if (value.is_object()) {
      read_set_entries(value, name, path, source, e);
      continue;
    }
    if (value.is_array())
      fail(source, path + ".set." + name, "expected a number, string, boolean or null, got " + describe_json(value));
    e.set.emplace_back(name, value);
  }
}

void read_set_map(const Json& raw, const std::string& path, const ConfigSource& source, ExperimentSpec& e) {
  const auto it = raw.find("set");
  if (it != raw.end() && it->is_object()) read_set_entries(*it, "", path, source, e);
}

/// `--set parameters.contact.stiffness.initial=1e10` arrives as nested objects
/// {"contact": {"stiffness": {"initial": 1e10}}}: flattens them back to the
/// dotted keys and merges them into the entries they refine (later keys win).
void flatten_parameters(const Json& raw, const std::string& prefix, Json& flat) {
  static const std::vector<std::string> leaf_keys = {"initial", "lower", "upper", "log_scale"};
  for (const auto& [key, value] : raw.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    const bool nested = value.is_object() && !value.empty() &&
                        std::none_of(leaf_keys.begin(), leaf_keys.end(),
                                     [&entry = value](const std::string& k) { return entry.contains(k); }) &&
                        std::all_of(value.begin(), value.end(), [](const Json& v) { return v.is_object(); });
    if (nested) {
      flatten_parameters(value, name, flat);
    } else if (flat.contains(name) && flat[name].is_object() && value.is_object()) {
      for (const auto& [k, v] : value.items()) flat[name][k] = v;
    } else {
      flat[name] = value;
    }
  }
}

void read_parameters(const Json& nested, const ConfigSource& source, IdentifySpec& spec) {
  Json raw = Json::object();
  flatten_parameters(nested, "", raw);
  if (raw.empty()) fail(source, "parameters", "must name at least one parameter (e.g. \"contact.stiffness\")");
  for (const auto& [key, value] : raw.items()) {
    const std::string at = "parameters." + key;
    if (!value.is_object())
      fail(source, at,
           "expected an object { \"initial\", \"lower\", \"upper\", \"log_scale\" }, got " + describe_json(value));
    ParameterSpec p;
    p.path = key;
    JsonReader reader(value, at, source);
    visit(reader, p);
    reader.finish();
    spec.parameters.push_back(std::move(p));
  }
}

Json reference_json(const ReferenceSpec& r) {
  Json j = JsonWriter::write(r);
  Json signals = Json::object();
  for (const auto& [name, column] : r.signals) signals[name] = column;
  j["signals"] = signals;
  Json weights = Json::object();
  for (const auto& [name, weight] : r.weights) weights[name] = weight;
  j["weights"] = weights;
  return j;
}

}  // namespace

const std::vector<std::string>& identify_study_keys() {
  static const std::vector<std::string> keys = {"reference", "experiments", "parameters", "solver"};
  return keys;
}

std::vector<std::string> identify_signal_names() {
  std::vector<std::string> names = TimeSeries::column_names();
  names.erase(names.begin());  // "time" is the time base, not a signal
  return names;
}

IdentifySpec identify_spec_from_json(const Json& part, const ConfigSource& source) {
  IdentifySpec spec;
  JsonReader reader(part, "", source);
  visit(reader, spec);
  reader.finish();

  if (spec.single_reference) {
    read_reference_maps(part.at("reference"), "reference", source, spec.experiments[0].reference);
  } else {
    const Json& list = part.at("experiments");
    for (std::size_t i = 0; i < spec.experiments.size(); ++i) {
      const std::string at = "experiments[" + std::to_string(i) + "]";
      ExperimentSpec& e = spec.experiments[i];
      if (e.name.empty()) e.name = "experiment_" + std::to_string(i + 1);
      read_reference_maps(list[i].at("reference"), at + ".reference", source, e.reference);
      read_set_map(list[i], at, source, e);
      for (std::size_t j = 0; j < i; ++j) {
        if (spec.experiments[j].name == e.name)
          fail(source, at + ".name", "'" + e.name + "' is also the name of experiments[" + std::to_string(j) + "]");
      }
    }
  }
  read_parameters(part.at("parameters"), source, spec);
  return spec;
}

Json to_json(const IdentifySpec& spec) {
  Json j = Json::object();
  if (spec.single_reference) {
    j["reference"] = reference_json(spec.experiments.front().reference);
  } else {
    Json list = Json::array();
    for (const ExperimentSpec& e : spec.experiments) {
      Json set = Json::object();
      for (const auto& [path, value] : e.set) set[path] = value;
      list.push_back(Json{{"name", e.name}, {"reference", reference_json(e.reference)}, {"set", set}});
    }
    j["experiments"] = list;
  }
  Json parameters = Json::object();
  for (const ParameterSpec& p : spec.parameters) parameters[p.path] = JsonWriter::write(p);
  j["parameters"] = parameters;
  j["solver"] = JsonWriter::write(spec.solver);
  return j;
}

}  // namespace camdyn::optim
