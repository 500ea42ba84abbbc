#include "optim/identify/identify.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/constants.h"
#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "dynamics/model.h"
#include "io/dotted_path.h"
#include "io/hex_doubles.h"
#include "io/input_file.h"
#include "io/json_archive.h"
#include "io/suggest.h"
#include "optim/halton_sequence.h"
#include "optim/identify/ceres_stage.h"
#include "optim/identify/finite_differences.h"
#include "optim/identify/fit_quality.h"
#include "optim/identify/fit_simulator.h"
#include "optim/identify/identify_journal.h"
#include "optim/identify/identify_statistics.h"
#include "optim/identify/optimum_statistics.h"
#include "study/mpi_runner.h"
#include "study/study.h"

namespace camdyn::optim {

namespace {

/// Simulated run length of a scene [s] (as simulate() plans it).
double run_end(const SceneConfig& scene) {
  if (scene.simulation.duration) return *scene.simulation.duration;
  const double rpm = scene.mechanism.cam.rpm;
  const double cycles = scene.simulation.cycles.value_or(SimulationConfig::kDefaultCycles);
  return rpm > 0.0 ? cycles * 60.0 / rpm : 0.0;
}

// ---------------------------------------------------------------- problem set-up

/// Data rows of a CSV file (lines neither empty nor comments, less the
/// header), counted without reading the values; 0 if it cannot be opened
/// (read_csv says why).
long count_data_rows(const std::string& file) {
  try {
    check_input_file(file);  // a regular file within the memory budget (io/input_file.h)
  } catch (const InputError&) {
    return 0;
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) return 0;
  std::vector<char> buffer(std::size_t{1} << 20);
  long lines = 0;
  bool line_start = true;  // the next character starts a line
  auto count = [&](char first) {
    if (first != '\n' && first != '\r' && first != '#') ++lines;
  };
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const char* p = buffer.data();
    const char* const end = p + in.gcount();
    if (p == end) break;
    if (line_start) count(*p);
    while (const void* nl = std::memchr(p, '\n', static_cast<std::size_t>(end - p))) {
      p = static_cast<const char*>(nl) + 1;
      if (p == end) break;
      count(*p);
    }
    line_start = end[-1] == '\n';
  }
  return std::max(lines - 1, 0L);
}

/// The measured values (samples × signals) of a record, refused before it is
/// read if the fit's total would exceed solver.max_measured_values.
long check_record_size(const ReferenceSpec& reference, const SolverSpec& solver, long before, const std::string& file,
                       const std::string& field) {
  const long rows = count_data_rows(reference.file);
  const long values = rows * static_cast<long>(reference.signals.size());
  if (before + values <= solver.max_measured_values) return values;
  std::ostringstream why;
  why.precision(3);
  why << reference.file << " has " << rows << " samples of " << reference.signals.size() << " signal"
      << (reference.signals.size() == 1 ? "" : "s") << ", which makes " << before + values
      << " measured values in all, more than solver.max_measured_values = " << solver.max_measured_values
      << ": the fit would need about "
      << std::llround(static_cast<double>(before + values) * kBytesPerMeasuredValue / 1e6)
      << " MB of memory. Decimate the records (keeping every k-th row with k = "
      << (before + values + solver.max_measured_values - 1) / solver.max_measured_values
      << " fits the limit; the fit needs the impacts resolved, not every sample) or raise "
         "solver.max_measured_values";
  throw InputError(file, field, why.str());
}

}  // namespace

std::size_t estimated_memory_bytes(const IdentifyProblem& problem) {
  return static_cast<std::size_t>(static_cast<double>(problem.residual_count()) * kBytesPerMeasuredValue);
}

std::size_t IdentifyProblem::residual_count() const {
  std::size_t n = 0;
  for (const FitExperiment& e : experiments) n += e.record.time.size() * e.record.signals.size();
  return n;
}

SceneConfig scene_with(const Json& scene_json, const std::vector<FitParameter>& parameters,
                       const std::vector<double>& values, const ConfigSource& source) {
  Json doc = scene_json;
  for (std::size_t i = 0; i < parameters.size(); ++i) set_config_value(doc, parameters[i].path, values[i]);
  return scene_from_json(doc, source);
}

IdentifyProblem prepare_identify(const SceneConfig& scene, const IdentifySpec& spec, const ConfigSource& source) {
  IdentifyProblem problem;
  problem.config_file = source.file;
  problem.source = source;
  problem.scene = scene;
  problem.solver = spec.solver;
  const Json base = to_json(scene);

  for (const ParameterSpec& ps : spec.parameters) {
    const std::string at = "parameters." + ps.path;
    FitParameter p;
    p.name = ps.path;
    p.path = full_dotted_path(ps.path);
    for (const FitParameter& other : problem.parameters)
      if (other.path == p.path)
        throw InputError(source.file, at, "'" + ps.path + "' is the same field as '" + other.name + "'");
    std::string why;
    const Json* field = find_dotted_field(base, p.path, why);
    if (field == nullptr) throw InputError(source.file, at, why);
    if (!field->is_number() && !field->is_null())
      throw InputError(source.file, at,
                       "'" + p.path + "' is " + describe_json(*field) + ", not a numeric field of the scene");
    if (ps.initial) {
      p.initial = *ps.initial;
    } else if (field->is_number()) {
      p.initial = field->get<double>();
    } else {
      throw InputError(source.file, at + ".initial",
                       "missing: the scene has no value for '" + p.path + "' to start from");
    }
    p.log_scale = ps.log_scale;
    p.lower = ps.lower.value_or(-kInf);
    p.upper = ps.upper.value_or(kInf);
    if (p.log_scale && !(p.initial > 0.0))
      throw InputError(source.file, at + ".initial",
                       "must be > 0 with log_scale, the scene has " + format_shortest(p.initial) + ": give 'initial'");
    if (p.initial < p.lower || p.initial > p.upper)
      throw InputError(source.file, at + ".initial",
                       "the scene's value " + format_shortest(p.initial) + " is outside [lower, upper] = [" +
                           format_shortest(p.lower) + ", " + format_shortest(p.upper) + "]: give 'initial'");
    p.scale = std::abs(p.initial) > 0.0                          ? std::abs(p.initial)
              : std::isfinite(p.lower) && std::isfinite(p.upper) ? p.upper - p.lower
                                                                 : 1.0;
    problem.parameters.push_back(p);
  }

  std::vector<double> initial;
  for (const FitParameter& p : problem.parameters) initial.push_back(p.initial);

  long measured_values = 0;  // of the records before this one
  for (std::size_t k = 0; k < spec.experiments.size(); ++k) {
    const ExperimentSpec& es = spec.experiments[k];
    const std::string at = spec.single_reference ? "reference" : "experiments[" + std::to_string(k) + "]";
    FitExperiment e;
    e.name = es.name;
    e.reference = es.reference;
    e.scene_json = base;
    for (const auto& [path, value] : es.set) {
      for (const FitParameter& p : problem.parameters)
        if (full_dotted_path(path) == p.path)
          throw InputError(source.file, at + ".set." + path,
                           "'" + path + "' is a fitted parameter (shared by all experiments), it cannot be set here");
      try {
        set_config_value(e.scene_json, path, value);
      } catch (const InputError& error) {
        throw InputError(source.file, at + ".set." + path, error.reason());
      }
    }
    try {
      scene_from_json(e.scene_json, source);
    } catch (const InputError& error) {
      throw InputError(source.file, at + ".set", "makes an invalid scene: " + error.path() + ": " + error.reason());
    }
    // The scene must be valid at the initial values and at every bound, so the
    // solver never meets a parameter value the scene rejects.
    const std::string for_experiment = spec.single_reference ? std::string() : " for experiment '" + e.name + "'";
    auto check = [&](const std::vector<double>& values, const std::string& where, bool keep) {
      try {
        SceneConfig s = scene_with(e.scene_json, problem.parameters, values, source);
        build_model(s, source.file);
        if (keep) e.scene = std::move(s);
      } catch (const InputError& error) {
        throw InputError(source.file, where,
                         "makes an invalid scene" + for_experiment + ": " +
                             (error.path().empty() ? std::string() : error.path() + ": ") + error.reason());
      }
    };
    check(initial, "parameters", true);
    for (std::size_t i = 0; i < problem.parameters.size(); ++i) {
      const FitParameter& par = problem.parameters[i];
      for (const bool upper : {false, true}) {
        std::vector<double> values = initial;
        values[i] = upper ? par.upper : par.lower;
        if (std::isfinite(values[i])) check(values, "parameters." + par.name + (upper ? ".upper" : ".lower"), false);
      }
    }
    measured_values += check_record_size(e.reference, problem.solver, measured_values, source.file,
                                         spec.single_reference ? "reference.file" : at + ".reference.file");
    e.record = read_reference(e.reference, run_end(e.scene));
    problem.experiments.push_back(std::move(e));
  }
  problem.fingerprint = identify_fingerprint(scene, spec, problem.experiments);
  if (problem.residual_count() <= problem.parameters.size())
    throw InputError(source.file, "parameters",
                     std::to_string(problem.parameters.size()) + " parameters cannot be fitted to " +
                         std::to_string(problem.residual_count()) + " measured values");
  return problem;
}

IdentifyProblem load_identify_problem(const Json& doc, const ConfigSource& source, Json* resolved) {
  if (!doc.is_object())
    throw InputError(source.file, "", "expected a JSON object at the top level, got " + describe_json(doc));
  // A near miss of a study key would otherwise be reported by the scene with scene keys only.
  const std::vector<std::string>& keys = identify_study_keys();
  for (const auto& item : doc.items()) {
    if (std::find(keys.begin(), keys.end(), item.key()) != keys.end()) continue;
    const std::string hint = did_you_mean(item.key(), keys);
    if (!hint.empty()) throw InputError(source.file, item.key(), "unknown key '" + item.key() + "'" + hint);
  }
  Json part;
  const SceneConfig scene = scene_from_study_json(doc, source, keys, part);
  const IdentifySpec spec = identify_spec_from_json(part, source);
  IdentifyProblem problem = prepare_identify(scene, spec, source);
  if (resolved != nullptr) *resolved = resolved_study_json(scene, "identify", to_json(spec));
  return problem;
}

// ---------------------------------------------------------------- the fit

namespace {

/// Robust loss scale: three noise standard deviations (weighted units),
/// pooled over the signals; 0 without a loss.
double loss_scale_of(const IdentifyProblem& problem) {
  const SolverSpec& spec = problem.solver;
  double noise2 = 0.0;
  std::size_t signals = 0;
  for (const FitExperiment& e : problem.experiments) {
    for (std::size_t s = 0; s < e.record.signals.size(); ++s, ++signals) {
      const double w = e.record.weights[s] * e.record.noise[s];
      noise2 += w * w;
    }
  }
  const double pooled_noise = std::sqrt(noise2 / static_cast<double>(std::max<std::size_t>(signals, 1)));
  return spec.loss == "none" ? 0.0 : spec.loss_scale.value_or(std::max(3.0 * pooled_noise, 1e-6));
}

/// Continuation: fit the smoothed signals first (widest window first), so
/// that simulated and measured impacts overlap and pull together, then the
/// raw signals, whose fit gives the estimates and their covariance. z goes
/// from the initial to the final scaled values; returns the last stage.
std::unique_ptr<Stage> run_continuation(const IdentifyProblem& problem, FitSimulator& simulator,
                                        const IdentifyOptions& options, std::vector<double>& z,
                                        IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  std::vector<double> widths = problem.solver.smoothing;
  std::sort(widths.begin(), widths.end(), std::greater<>());
  widths.push_back(0.0);
  std::unique_ptr<Stage> stage;
  for (std::size_t index = 0; index < widths.size(); ++index) {
    const double width = widths[index];
    const IdentifyProgress where{static_cast<int>(index) + 1, static_cast<int>(widths.size()), width, 0, 0.0};
    stage = solve_stage(problem, simulator, problem.solver, index, width, result.loss_scale, options, where, z);
    const ceres::Solver::Summary& summary = stage->summary;
    std::vector<double> stage_values(p);
    for (std::size_t i = 0; i < p; ++i) stage_values[i] = to_value(problem.parameters[i], z[i]);
    result.stages.push_back({width, static_cast<int>(summary.iterations.size()) - 1, summary.initial_cost,
                             summary.final_cost, ceres::TerminationTypeToString(summary.termination_type),
                             stage_values});
    result.iterations += result.stages.back().iterations;
    if (options.journal != nullptr) options.journal->add_stage(index, result.stages.back());
    if (stage->evaluator->failures() > 0)
      result.warnings.push_back(
          std::to_string(stage->evaluator->failures()) +
          " trial steps failed to simulate and were rejected; the last: " + stage->evaluator->last_failure());
  }
  const ceres::Solver::Summary& summary = stage->summary;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.termination = ceres::TerminationTypeToString(summary.termination_type);
  result.message = summary.message;
  if (summary.termination_type == ceres::NO_CONVERGENCE)
    result.warnings.push_back("the solver stopped after " + std::to_string(result.stages.back().iterations) +
                              " iterations without converging (solver.max_iterations): " + summary.message);
  return stage;
}

/// Measured against fitted, at the optimum; warns of a misfit well above the noise.
void record_fits(const IdentifyProblem& problem, FitSimulator& simulator, const std::vector<double>& values,
                 IdentifyResult& result) {
  const std::vector<std::vector<FitRun>> runs = simulator.run({values});
  for (std::size_t k = 0; k < problem.experiments.size(); ++k) {
    const FitExperiment& e = problem.experiments[k];
    const FitRun& run = runs[0][k];
    if (!run.ok) throw NumericalError("identification: the simulation at the optimum failed: " + run.error);
    ExperimentFit fit;
    fit.name = e.name;
    fit.time = e.record.time;
    fit.signals = e.record.signals;
    fit.measured = e.record.values;
    fit.weights = e.record.weights;
    fit.noise = e.record.noise;
    fit.fitted = run.signals;
    for (std::size_t s = 0; s < fit.signals.size(); ++s) {
      double e2 = 0.0;
      for (std::size_t i = 0; i < fit.time.size(); ++i) e2 += std::pow(fit.fitted[s][i] - fit.measured[s][i], 2);
      fit.rms_error.push_back(std::sqrt(e2 / static_cast<double>(fit.time.size())));
      // A misfit well above the measurement noise means the model cannot reproduce the record.
      if (fit.noise[s] > 0.0 && fit.rms_error.back() > 3.0 * fit.noise[s])
        result.warnings.push_back(
            "experiment '" + e.name + "', " + fit.signals[s] + ": RMS misfit " + format_shortest(fit.rms_error.back()) +
            " is more than three times the noise estimated from the record (" + format_shortest(fit.noise[s]) +
            "): the model or its fixed parameters may not match the data");
    }
    result.fits.push_back(std::move(fit));
  }
}

}  // namespace

namespace {

/// The fit from the scaled start `z` (one start of identify()).
IdentifyResult identify_from(const IdentifyProblem& problem, const IdentifyOptions& options, std::vector<double> z) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::size_t p = problem.parameters.size();
  const SolverSpec& spec = problem.solver;
  FitSimulator simulator(problem, options.threads, options.journal);
  IdentifyResult result;
  result.loss = spec.loss;
  result.loss_scale = loss_scale_of(problem);

  const std::unique_ptr<Stage> stage = run_continuation(problem, simulator, options, z, result);
  FitEvaluator& cost = *stage->evaluator;
  const Optimum optimum = evaluate_optimum(problem, cost, z, result);

  // The rank tolerance: the finite-difference noise, integration error over the step.
  double max_rtol = 0.0;
  for (const FitExperiment& e : problem.experiments) max_rtol = std::max(max_rtol, e.scene.integrator.rtol);
  const double rank_tolerance = std::clamp(10.0 * max_rtol / spec.fd_relative_step, 1e-10, 1e-2);
  std::vector<double> magnitudes(p);
  for (std::size_t i = 0; i < p; ++i) {
    const FitParameter& par = problem.parameters[i];
    magnitudes[i] = par.log_scale ? 1.0 : std::max(std::abs(optimum.values[i]), par.scale);
  }
  const Identifiability id = identifiability(optimum.jacobian, magnitudes, rank_tolerance);
  std::vector<bool> unidentifiable = check_rank(problem, id, rank_tolerance, result);
  const std::vector<bool> undetermined = unidentifiable;  // standard error undefined
  const std::optional<Eigen::MatrixXd> cov_z = covariance_at_optimum(problem, *stage, z, optimum, result);
  if (cost.input_error()) std::rethrow_exception(cost.input_error());

  record_estimates(problem, z, optimum, cov_z, undetermined, result);
  check_standard_errors(problem, id, unidentifiable, result);
  result.identifiable = std::none_of(unidentifiable.begin(), unidentifiable.end(), [](bool b) { return b; });
  for (std::size_t i = 0; i < p; ++i) result.parameters[i].identifiable = !unidentifiable[i];

  record_fits(problem, simulator, optimum.values, result);
  result.identified_scene = scene_with(to_json(problem.scene), problem.parameters, optimum.values, problem.source);
  result.simulations = simulator.simulations();
  result.reused_points = simulator.reused_points();
  result.resumed_simulations = simulator.resumed_simulations();
  result.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return result;
}

/// Start k ≥ 1 of the space-filling design: parameter i at the k-th Halton
/// point of the i-th prime over its bounds in the scaled space (an unbounded
/// side: a factor e² from the initial value on a log scale, max(|p₀|, scale)
/// on a linear one).
std::vector<double> design_start(const IdentifyProblem& problem, int k) {
  const std::size_t p = problem.parameters.size();
  std::vector<double> z(p);
  for (std::size_t i = 0; i < p; ++i) {
    const FitParameter& par = problem.parameters[i];
    const double z0 = to_scaled(par, par.initial);
    const double reach = par.log_scale ? 2.0 : std::max(std::abs(par.initial), par.scale);
    double lo = scaled_lower(par), hi = scaled_upper(par);
    if (!std::isfinite(lo)) lo = z0 - reach;
    if (!std::isfinite(hi)) hi = z0 + reach;
    z[i] = lo + halton(k, kHaltonBases[i % kHaltonBases.size()]) * (hi - lo);
  }
  return z;
}

std::vector<double> to_values(const IdentifyProblem& problem, const std::vector<double>& z) {
  std::vector<double> v(z.size());
  for (std::size_t i = 0; i < z.size(); ++i) v[i] = to_value(problem.parameters[i], z[i]);
  return v;
}

/// A poor fit (optim/identify/fit_quality.h) reports no standard error and is not identified.
void flag_poor_fit(const FitQuality& q, IdentifyResult& result) {
  result.poor_fit = q.poor;
  result.misfit_ratio = q.worst_ratio;
  if (!q.poor) return;
  result.identifiable = false;
  for (ParameterEstimate& e : result.parameters) {
    e.std_error.reset();
    e.identifiable = false;
  }
  for (auto& row : result.correlation) std::fill(row.begin(), row.end(), std::nullopt);
  result.warnings.insert(result.warnings.begin(), "poor_fit: local minimum likely: the misfit variance of " + q.where +
                                                      " is " + format_shortest(q.worst_ratio) +
                                                      " times the noise variance estimated from the record (critical " +
                                                      format_shortest(q.critical) +
                                                      " at the 0.1 % level); no standard error is reported, and the " +
                                                      std::to_string(result.starts.size()) + " start(s) are listed");
}

}  // namespace

namespace {

/// The further starts of a multi-start fit (start k ≥ 1 of the design), in
/// start order: each one's FitStart and simulations, and the fits run here.
struct FurtherStarts {
  explicit FurtherStarts(std::size_t count) : starts(count), simulations(count, 0), results(count) {}
  std::vector<FitStart> starts;
  std::vector<long> simulations;                       ///< of a start that converged (a failed one counts none)
  std::vector<std::optional<IdentifyResult>> results;  ///< the fits run in this process
};

/// Further start `k` ≥ 1 into `further` (index k − 1); a failure is that
/// start's error unless the study's time ran out.
void run_further_start(const IdentifyProblem& problem, const IdentifyOptions& extra, int k, FurtherStarts& further) {
  const std::size_t i = static_cast<std::size_t>(k) - 1;
  const std::vector<double> z = design_start(problem, k);
  FitStart& start = further.starts[i];
  start = FitStart{to_values(problem, z), {}, 0.0, false, ""};
  try {
    further.results[i] = identify_from(problem, extra, z);
  } catch (const NumericalError& e) {
    if (study_budget_exhausted()) throw;  // the study's wall time, not this start, ran out
    start.error = e.what();
  }
  if (!further.results[i]) return;
  const IdentifyResult& r = *further.results[i];
  further.simulations[i] = r.simulations;
  start.values = r.identified_values();
  start.final_cost = r.final_cost;
  start.poor_fit = assess_fit(r.fits).poor;
}

/// What rank 0 needs of a further start run on another rank, as text (doubles as hex, io/hex_doubles.h).
std::string further_start_text(int k, const FurtherStarts& further) {
  const std::size_t i = static_cast<std::size_t>(k) - 1;
  const FitStart& start = further.starts[i];
  const Json record{{"start", k},
                    {"values", doubles_to_hex(start.values)},
                    {"final_cost", doubles_to_hex({start.final_cost})},
                    {"poor_fit", start.poor_fit},
                    {"error", start.error},
                    {"simulations", further.simulations[i]}};
  return record.dump(-1, ' ', false, Json::error_handler_t::replace);
}

/// Rank 0: a further start of another rank into `further` (its fit stays there).
void take_further_start(const IdentifyProblem& problem, const std::string& text, FurtherStarts& further) {
  const Json record = Json::parse(text);
  const int k = record.at("start").get<int>();
  if (k < 1 || static_cast<std::size_t>(k) > further.starts.size())
    throw std::runtime_error("identify: a rank's start record names no start of this fit");
  const std::size_t i = static_cast<std::size_t>(k) - 1;
  const std::string& values = record.at("values").get_ref<const std::string&>();
  const auto v = doubles_from_hex(values, values.empty() ? 0 : problem.parameters.size());
  const auto cost = doubles_from_hex(record.at("final_cost").get_ref<const std::string&>(), 1);
  if (!v || !cost) throw std::runtime_error("identify: a rank's start record is malformed");
  FitStart& start = further.starts[i];
  start = FitStart{to_values(problem, design_start(problem, k)), *v, cost->front(), record.at("poor_fit").get<bool>(),
                   record.at("error").get<std::string>()};
  further.simulations[i] = record.at("simulations").get<long>();
}

/// The fit of further start `i` (index k − 1), the best one, whose cost is
/// `cost`: run in this process, or else on another rank and fitted again
/// here (the fit is deterministic: the same to the bit, checked by its cost).
IdentifyResult chosen_fit(const IdentifyProblem& problem, const IdentifyOptions& extra, std::size_t i, double cost,
                          FurtherStarts& further) {
  if (further.results[i]) return std::move(*further.results[i]);
  IdentifyResult r = identify_from(problem, extra, design_start(problem, static_cast<int>(i) + 1));
  if (std::bit_cast<std::uint64_t>(r.final_cost) != std::bit_cast<std::uint64_t>(cost))
    throw std::runtime_error("identify: start " + std::to_string(i + 1) +
                             " fitted again on rank 0 did not end where it ended on its rank");
  return r;
}

/// The starts over the MPI ranks (docs/optimize.md "MPI ranks"): start k on
/// rank k mod N, start 0 (`first`, if not run yet) on rank 0; rank 0 gets
/// every further start's record.
void run_identify_starts_over_ranks(const IdentifyProblem& problem, const IdentifyOptions& extra, int wanted,
                                    const std::function<void()>& first, FurtherStarts& further) {
  std::vector<std::size_t> indices(static_cast<std::size_t>(wanted));
  std::iota(indices.begin(), indices.end(), std::size_t{0});
  mpi::distribute_runs(
      indices,
      [&](std::size_t k) {
        if (k == 0) {
          first();
          return std::string();
        }
        run_further_start(problem, extra, static_cast<int>(k), further);
        return mpi::rank() == 0 ? std::string() : further_start_text(static_cast<int>(k), further);
      },
      [&](const std::string& text) {
        if (!text.empty()) take_further_start(problem, text, further);
      });
}

}  // namespace

IdentifyResult identify(const IdentifyProblem& problem, const IdentifyOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::size_t p = problem.parameters.size();
  std::vector<double> z0(p);
  for (std::size_t i = 0; i < p; ++i) z0[i] = to_scaled(problem.parameters[i], problem.parameters[i].initial);
  const bool ranks = options.over_ranks && mpi::size() > 1;
  const bool root = mpi::rank() == 0;
  std::optional<IdentifyResult> first_fit;
  const auto first = [&] {
    if (!first_fit) first_fit = identify_from(problem, options, z0);
  };
  // The starts wanted: the config's, or more when the first start's fit is poor.
  int wanted = problem.solver.starts.value_or(0);
  if (!problem.solver.starts) {
    if (root) {
      first();
      wanted = assess_fit(first_fit->fits).poor ? 2 * static_cast<int>(p) + 3 : 1;
    }
    if (ranks) wanted = std::stoi(mpi::broadcast(std::to_string(wanted)));
  }
  // The further starts at once on the threads (each its own simulator; the
  // progress callback one call at a time), or over the MPI ranks, then taken
  // in start order, so the result is the one of the starts run one after the other.
  const std::size_t count = static_cast<std::size_t>(std::max(0, wanted - 1));
  const int parallel = ranks ? 1 : std::clamp(options.threads, 1, std::max(1, wanted - 1));
  std::mutex progress_mutex;
  IdentifyOptions extra = options;
  extra.journal = nullptr;  // the journal resumes the first start
  extra.threads = std::max(1, options.threads / parallel);
  if (options.progress && parallel > 1)
    extra.progress = [&options, &progress_mutex](const IdentifyProgress& at) {
      const std::lock_guard<std::mutex> lock(progress_mutex);
      options.progress(at);
    };
  FurtherStarts further(count);
  if (ranks) {
    run_identify_starts_over_ranks(problem, extra, std::max(wanted, 1), first, further);
    if (!root) return IdentifyResult{};  // rank 0 has every start's record
  } else {
    first();
    parallel_for(count, parallel,
                 [&](std::size_t i) { run_further_start(problem, extra, static_cast<int>(i) + 1, further); });
  }
  IdentifyResult& best = *first_fit;
  FitQuality quality = assess_fit(best.fits);
  std::vector<FitStart> starts = {
      {to_values(problem, z0), best.identified_values(), best.final_cost, quality.poor, ""}};
  long simulations = best.simulations;
  std::optional<std::size_t> winner;  // the further start whose fit is best, if any
  double best_cost = best.final_cost;
  for (std::size_t i = 0; i < count; ++i) {
    FitStart& start = further.starts[i];
    if (!start.values.empty()) {  // converged
      simulations += further.simulations[i];
      if (start.final_cost < best_cost) {
        best_cost = start.final_cost;
        winner = i;
      }
    }
    starts.push_back(std::move(start));
  }
  if (winner) best = chosen_fit(problem, extra, *winner, best_cost, further);
  quality = assess_fit(best.fits);
  best.starts = std::move(starts);
  best.simulations = simulations;
  flag_poor_fit(quality, best);
  best.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return best;
}

}  // namespace camdyn::optim
