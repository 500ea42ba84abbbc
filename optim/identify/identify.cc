#include "optim/identify/identify.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <utility>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/csv_reader.h"
#include "io/dotted_path.h"
#include "io/json_archive.h"
#include "io/suggest.h"
#include "optim/identify/fit_residuals.h"
#include "optim/identify/fit_scene.h"
#include "optim/identify/identify_journal.h"
#include "optim/identify/identify_statistics.h"
#include "study/study.h"

namespace camdyn::optim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// Relative cost and step tolerance of the smoothed continuation stages.
constexpr double kStageTolerance = 1e-4;

/// Simulated run length of a scene [s] (as simulate() plans it).
double run_end(const SceneConfig& scene) {
  if (scene.simulation.duration) return *scene.simulation.duration;
  const double rpm = scene.mechanism.cam.rpm;
  const double cycles = scene.simulation.cycles.value_or(SimulationConfig::kDefaultCycles);
  return rpm > 0.0 ? cycles * 60.0 / rpm : 0.0;
}

std::string fmt(double x) { return format_shortest(x); }

// ---------------------------------------------------------------- parallel simulations

/// Simulates the experiments at parameter vectors, in parallel (parallel_for).
/// Each run takes an idle FitScene of its experiment (built on first use, one
/// per worker at most), sets the values in place and simulates: nothing is
/// rebuilt from JSON, and threads share nothing but the read-only problem.
/// The runs of the last points evaluated are kept (kept_points()): a continuation stage starts
/// where the last one stopped, and the covariance and the final check are at
/// the optimum, so their points (centre and difference steps) were simulated
/// already. A point is the same when its values are the same to the bit; the
/// simulation is deterministic, so a kept run is the run.
class Simulator {
 public:
  Simulator(const IdentifyProblem& problem, int threads, IdentifyJournal* journal)
      : problem_(problem),
        threads_(std::max(1, threads)),
        journal_(journal),
        kept_(kept_points(problem)),
        idle_(problem.experiments.size()) {}

  /// runs[j][k]: experiment k at parameter vector points[j]. A point the
  /// journal of a killed run holds is taken from there and counted as
  /// simulated, so the counters of a resumed run are those of an uninterrupted one.
  std::vector<std::vector<FitRun>> run(const std::vector<std::vector<double>>& points) {
    const std::lock_guard<std::mutex> calls(run_mutex_);
    const std::size_t experiments = problem_.experiments.size();
    std::vector<std::vector<FitRun>> runs(points.size());
    std::vector<std::size_t> missing, simulate;  // indices into points: not kept; of those, not journaled
    for (std::size_t j = 0; j < points.size(); ++j) {
      const auto hit = std::find_if(kept_runs_.begin(), kept_runs_.end(),
                                    [&](const KeptRun& k) { return same_bits(k.point, points[j]); });
      if (hit != kept_runs_.end()) {
        runs[j] = hit->runs;
        ++reused_;
        continue;
      }
      missing.push_back(j);
      if (const std::vector<FitRun>* journaled = journal_ != nullptr ? journal_->find(points[j]) : nullptr) {
        runs[j] = *journaled;
        resumed_ += static_cast<long>(experiments);
      } else {
        runs[j].resize(experiments);
        simulate.push_back(j);
      }
    }
    const std::size_t tasks = simulate.size() * experiments;
    parallel_for(tasks, threads_, [&](std::size_t task) {
      const std::size_t j = simulate[task / experiments], k = task % experiments;
      std::unique_ptr<FitScene> scene = acquire(k);
      runs[j][k] = scene->run(points[j]);
      release(k, std::move(scene));
    });
    simulations_ += static_cast<long>(missing.size() * experiments);
    if (journal_ != nullptr)
      for (const std::size_t j : simulate) journal_->add_point(points[j], runs[j]);
    for (const std::size_t j : missing) keep(points[j], runs[j]);
    return runs;
  }

  IdentifyJournal* journal() const { return journal_; }
  long simulations() const { return simulations_; }
  /// Simulations taken from the journal of a killed run.
  long resumed_simulations() const { return resumed_; }
  /// Points whose runs were kept from an earlier call.
  long reused_points() const { return reused_; }

 private:
  std::unique_ptr<FitScene> acquire(std::size_t experiment) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      std::vector<std::unique_ptr<FitScene>>& idle = idle_[experiment];
      if (!idle.empty()) {
        std::unique_ptr<FitScene> scene = std::move(idle.back());
        idle.pop_back();
        return scene;
      }
    }
    return std::make_unique<FitScene>(problem_.experiments[experiment], problem_.parameters, problem_.source);
  }

  void release(std::size_t experiment, std::unique_ptr<FitScene> scene) {
    const std::lock_guard<std::mutex> lock(mutex_);
    idle_[experiment].push_back(std::move(scene));
  }

  /// Points kept: two Jacobians' worth (centre and 2p difference points),
  /// within 256 MB of simulated signals.
  static std::size_t kept_points(const IdentifyProblem& problem) {
    std::size_t bytes = 0;  // one point's runs
    for (const FitExperiment& e : problem.experiments)
      bytes += e.record.signals.size() * e.record.time.size() * sizeof(double);
    const std::size_t budget = std::size_t{256} << 20;
    return std::min(4 * (2 * problem.parameters.size() + 1), budget / std::max<std::size_t>(bytes, 1));
  }

  struct KeptRun {
    std::vector<double> point;
    std::vector<FitRun> runs;  ///< per experiment
  };

  static bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
    return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](double x, double y) {
      return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
    });
  }

  // Keeps a point's runs if they all succeeded, the oldest dropped beyond kept_.
  void keep(const std::vector<double>& point, const std::vector<FitRun>& runs) {
    if (kept_ == 0 || !std::all_of(runs.begin(), runs.end(), [](const FitRun& r) { return r.ok; })) return;
    if (kept_runs_.size() == kept_) kept_runs_.erase(kept_runs_.begin());
    kept_runs_.push_back({point, runs});
  }

  const IdentifyProblem& problem_;
  int threads_;
  IdentifyJournal* journal_;                                  ///< null: none
  std::size_t kept_;                                          ///< points whose runs are kept
  std::mutex run_mutex_;                                      ///< one run() at a time: it owns kept_runs_
  std::mutex mutex_;                                          ///< guards idle_
  std::vector<std::vector<std::unique_ptr<FitScene>>> idle_;  ///< per experiment
  std::vector<KeptRun> kept_runs_;                            ///< oldest first
  long simulations_ = 0;
  long reused_ = 0;
  long resumed_ = 0;
};

// ---------------------------------------------------------------- residuals and their derivatives

/// Parameter transforms: the solver works on z = ln p (log scale) or z = p.
double to_value(const FitParameter& p, double z) { return p.log_scale ? std::exp(z) : z; }
double to_scaled(const FitParameter& p, double value) { return p.log_scale ? std::log(value) : value; }
double scaled_lower(const FitParameter& p) {
  if (p.log_scale) return p.lower > 0.0 && std::isfinite(p.lower) ? std::log(p.lower) : -kInf;
  return p.lower;
}
double scaled_upper(const FitParameter& p) { return p.log_scale ? std::log(p.upper) : p.upper; }

/// The weighted residual vector and its Jacobian in the scaled parameters,
/// by finite differences whose simulations all run in parallel: forward
/// (E·(p+1) simulations) in the solver's iterations when solver.differences
/// is "forward", central (E·(2p+1)) otherwise and always at the optimum,
/// whose Jacobian gives the covariance. Steps near a bound turn one-sided so
/// that no simulation runs outside the bounds (where the scene may be invalid). The last point is cached: Ceres
/// asks for every residual block at the same point, evaluates the cost at a
/// trial point and then, once it is accepted, the Jacobian there.
class FitEvaluator {
 public:
  FitEvaluator(const IdentifyProblem& problem, Simulator& simulator, double smoothing)
      : problem_(problem),
        simulator_(simulator),
        smoothing_(smoothing),
        assembler_(problem),
        n_(problem.residual_count()),
        p_(problem.parameters.size()) {}

  /// Residuals (and the Jacobian) at z; false if a simulation failed there.
  /// Exceptions are kept, not thrown: they must not cross Ceres.
  /// `central` asks for central differences whatever solver.differences says.
  bool evaluate(const double* z, bool jacobian, bool central = false) {
    std::lock_guard<std::mutex> lock(mutex_);
    central = central || !problem_.solver.forward_differences();
    const bool same = !z_.empty() && std::equal(z_.begin(), z_.end(), z);
    if (same && (!ok_ || !jacobian || (!j_.empty() && (j_central_ || !central)))) return ok_;
    try {
      ok_ = compute(z, jacobian, same && ok_, central);
      j_central_ = central;
    } catch (...) {
      if (!exception_) exception_ = std::current_exception();
      ok_ = false;
    }
    z_.assign(z, z + p_);
    if (!ok_) j_.clear();
    return ok_;
  }

  const std::vector<double>& residuals() const { return r_; }
  /// Row-major n × p.
  const std::vector<double>& jacobian() const { return j_; }

  /// The first InputError met (a parameter value the scene rejects), or null.
  std::exception_ptr input_error() const { return input_error_; }
  std::exception_ptr exception() const { return exception_; }
  const std::string& last_failure() const { return last_failure_; }
  std::size_t failures() const { return failures_; }

 private:
  bool compute(const double* z, bool jacobian, bool have_residuals, bool central) {
    std::vector<double> centre(p_);
    for (std::size_t i = 0; i < p_; ++i) centre[i] = to_value(problem_.parameters[i], z[i]);

    std::vector<std::vector<double>> points;
    if (!have_residuals) points.push_back(centre);
    std::vector<double> z_plus(p_), z_minus(p_);
    std::vector<int> plus_index(p_, -1), minus_index(p_, -1);
    if (jacobian) {
      const double h = problem_.solver.fd_relative_step;
      for (std::size_t i = 0; i < p_; ++i) {
        const FitParameter& par = problem_.parameters[i];
        const double step = par.log_scale ? h : h * std::max(std::abs(centre[i]), par.scale);
        const double lo = scaled_lower(par), hi = scaled_upper(par);
        z_plus[i] = z[i] + step;
        z_minus[i] = central ? z[i] - step : z[i];
        if (z_plus[i] > hi) {  // backward difference at the upper bound
          z_plus[i] = z[i];
          z_minus[i] = z[i] - step;
        }
        if (z_minus[i] < lo) z_minus[i] = z[i];  // forward difference at the lower bound
        if (z_plus[i] == z[i] && z_minus[i] == z[i]) {
          // Bounds closer than one step: use the whole interval.
          z_plus[i] = hi;
          z_minus[i] = lo;
        }
        auto add_point = [&](double zi, std::vector<int>& index) {
          if (zi == z[i]) return;  // the centre itself
          std::vector<double> point = centre;
          point[i] = to_value(par, zi);
          index[i] = static_cast<int>(points.size());
          points.push_back(std::move(point));
        };
        add_point(z_plus[i], plus_index);
        add_point(z_minus[i], minus_index);
      }
    }

    const std::vector<std::vector<FitRun>> runs = simulator_.run(points);
    for (const auto& point_runs : runs) {
      for (const FitRun& run : point_runs) {
        if (run.ok) continue;
        ++failures_;
        last_failure_ = run.error;
        if (run.input_error && !input_error_) input_error_ = run.input_error;
        return false;
      }
    }
    if (!have_residuals) {
      r_.assign(n_, 0.0);
      assembler_.assemble(runs[0], smoothing_, r_.data());
    }
    j_.clear();
    if (!jacobian) return true;

    j_.assign(n_ * p_, 0.0);
    std::vector<double> r_plus(n_), r_minus(n_);
    for (std::size_t i = 0; i < p_; ++i) {
      if (plus_index[i] >= 0)
        assembler_.assemble(runs[static_cast<std::size_t>(plus_index[i])], smoothing_, r_plus.data());
      else
        r_plus = r_;
      if (minus_index[i] >= 0)
        assembler_.assemble(runs[static_cast<std::size_t>(minus_index[i])], smoothing_, r_minus.data());
      else
        r_minus = r_;
      const double dz = z_plus[i] - z_minus[i];
      for (std::size_t row = 0; row < n_; ++row) j_[row * p_ + i] = (r_plus[row] - r_minus[row]) / dz;
    }
    return true;
  }

  const IdentifyProblem& problem_;
  Simulator& simulator_;
  double smoothing_;  ///< [s], 0 for the raw signals
  ResidualAssembler assembler_;
  std::size_t n_, p_;
  std::mutex mutex_;
  std::vector<double> z_, r_, j_;
  bool ok_ = false;
  bool j_central_ = false;  // j_ is by central differences
  std::exception_ptr exception_, input_error_;
  std::string last_failure_;
  std::size_t failures_ = 0;
};

/// One measured sample as a Ceres residual block, so that a robust loss acts
/// on each sample (Ceres applies it to the squared norm of a whole block).
/// All blocks share the evaluator, which simulates once per point.
class SampleCost final : public ceres::CostFunction {
 public:
  SampleCost(FitEvaluator& evaluator, std::size_t row, int parameters) : evaluator_(evaluator), row_(row) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(parameters);
  }

  bool Evaluate(double const* const* parameters, double* r, double** jacobians) const override {
    const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    if (!evaluator_.evaluate(parameters[0], jacobian)) return false;
    r[0] = evaluator_.residuals()[row_];
    if (jacobian) {
      const auto p = static_cast<std::size_t>(parameter_block_sizes()[0]);
      const double* row = evaluator_.jacobian().data() + row_ * p;
      std::copy(row, row + p, jacobians[0]);
    }
    return true;
  }

 private:
  FitEvaluator& evaluator_;
  std::size_t row_;
};

/// After each solver iteration: the progress callback, and the accepted
/// iterates into the journal (Ceres has written them into z by then:
/// update_state_every_iteration).
class IterationCallback final : public ceres::IterationCallback {
 public:
  IterationCallback(const IdentifyProblem& problem, const IdentifyOptions& options, std::size_t stage, double smoothing,
                    const std::vector<double>& z, IdentifyProgress where)
      : problem_(problem), options_(options), stage_(stage), smoothing_(smoothing), z_(z), where_(where) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (study_budget_exhausted()) return ceres::SOLVER_ABORT;  // solve_stage says why
    if (options_.progress) {
      where_.iteration = summary.iteration;
      where_.cost = summary.cost;
      options_.progress(where_);
    }
    if (options_.journal != nullptr && summary.step_is_successful) {
      std::vector<double> values(z_.size());
      for (std::size_t i = 0; i < z_.size(); ++i) values[i] = to_value(problem_.parameters[i], z_[i]);
      options_.journal->add_iterate(stage_, smoothing_, summary.iteration, summary.cost, values);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const IdentifyProblem& problem_;
  const IdentifyOptions& options_;
  std::size_t stage_;
  double smoothing_;
  const std::vector<double>& z_;
  IdentifyProgress where_;
};

ceres::LossFunction* make_loss(const std::string& loss, double scale) {
  if (loss == "huber") return new ceres::HuberLoss(scale);
  if (loss == "cauchy") return new ceres::CauchyLoss(scale);
  if (loss == "soft_l1") return new ceres::SoftLOneLoss(scale);
  return nullptr;  // "none": plain least squares
}

std::string percent(double x) {
  std::ostringstream s;
  s.precision(3);
  s << 100.0 * x << " %";
  return s.str();
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return out;
}

/// One least-squares solve (a continuation stage): the problem stays alive for the covariance.
struct Stage {
  std::unique_ptr<FitEvaluator> evaluator;
  std::unique_ptr<ceres::LossFunction> loss;
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
};

std::unique_ptr<Stage> solve_stage(const IdentifyProblem& problem, Simulator& simulator, const SolverSpec& spec,
                                   std::size_t stage_index, double smoothing, double loss_scale,
                                   const IdentifyOptions& options, const IdentifyProgress& where,
                                   std::vector<double>& z) {
  auto stage = std::make_unique<Stage>();
  stage->evaluator = std::make_unique<FitEvaluator>(problem, simulator, smoothing);
  // One loss object for all blocks; the problem must then not delete it per block.
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  stage->loss.reset(make_loss(spec.loss, loss_scale));
  stage->problem = std::make_unique<ceres::Problem>(problem_options);
  const int p = static_cast<int>(problem.parameters.size());
  for (std::size_t row = 0; row < problem.residual_count(); ++row)
    stage->problem->AddResidualBlock(new SampleCost(*stage->evaluator, row, p), stage->loss.get(), z.data());
  for (std::size_t i = 0; i < problem.parameters.size(); ++i) {
    const double lo = scaled_lower(problem.parameters[i]), hi = scaled_upper(problem.parameters[i]);
    if (std::isfinite(lo)) stage->problem->SetParameterLowerBound(z.data(), static_cast<int>(i), lo);
    if (std::isfinite(hi)) stage->problem->SetParameterUpperBound(z.data(), static_cast<int>(i), hi);
  }

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = spec.max_iterations;
  solver_options.initial_trust_region_radius = spec.initial_trust_region_radius;
  // A smoothed stage only has to bring the next one into its basin.
  solver_options.function_tolerance =
      smoothing > 0.0 ? std::max(spec.function_tolerance, kStageTolerance) : spec.function_tolerance;
  solver_options.gradient_tolerance = spec.gradient_tolerance;
  solver_options.parameter_tolerance =
      smoothing > 0.0 ? std::max(spec.parameter_tolerance, kStageTolerance) : spec.parameter_tolerance;
  // With bounds, Ceres runs a projected Armijo line search on each step; its
  // cubic interpolation wants the gradient at every trial, which here is a
  // whole finite-difference Jacobian. Bisection needs only the cost.
  solver_options.line_search_interpolation_type = ceres::BISECTION;
  solver_options.num_threads = 1;  // one residual block; the simulations run in parallel inside it
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  IterationCallback callback(problem, options, stage_index, smoothing, z, where);
  solver_options.callbacks.push_back(&callback);
  solver_options.update_state_every_iteration = true;  // z is the accepted iterate in the callback
  std::string options_error;
  if (!solver_options.IsValid(&options_error)) throw std::logic_error("Ceres options: " + options_error);

  ceres::Solve(solver_options, stage->problem.get(), &stage->summary);
  const FitEvaluator& cost = *stage->evaluator;
  if (cost.input_error()) std::rethrow_exception(cost.input_error());
  if (study_budget_exhausted())
    throw NumericalError(study_budget_text() + " in continuation stage " + std::to_string(stage_index + 1) +
                         (options.journal == nullptr
                              ? std::string()
                              : "; the simulations so far are kept in " + options.journal->path().string() + ": " +
                                    study_rerun_advice()));
  if (!stage->summary.IsSolutionUsable()) {
    std::string why = stage->summary.message;
    if (!cost.last_failure().empty()) why += "; last failed simulation: " + cost.last_failure();
    if (cost.exception() && cost.last_failure().empty()) {
      try {
        std::rethrow_exception(cost.exception());
      } catch (const std::exception& e) {
        why += std::string("; ") + e.what();
      }
    }
    throw NumericalError(
        "identification failed (" + std::string(ceres::TerminationTypeToString(stage->summary.termination_type)) +
        (smoothing > 0.0 ? ", stage smoothed over " + fmt(smoothing) + " s" : std::string()) + "): " + why);
  }
  return stage;
}

}  // namespace

// ---------------------------------------------------------------- data

double estimate_noise(const std::vector<double>& y) {
  if (y.size() < 3) return 0.0;
  std::vector<double> d(y.size() - 1);
  for (std::size_t i = 0; i + 1 < y.size(); ++i) d[i] = y[i + 1] - y[i];
  auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  const double m = median(d);
  for (double& x : d) x = std::abs(x - m);
  // Differences of white noise have variance 2σ²; 1.4826 MAD estimates a Gaussian σ.
  return 1.4826 * median(d) / std::sqrt(2.0);
}

MeasuredRecord read_reference(const ReferenceSpec& reference, double t_end) {
  std::vector<std::string> columns{reference.time_column};
  for (const auto& [signal, file_column] : reference.signals) {
    if (file_column == reference.time_column)
      throw InputError(reference.file, "column " + file_column,
                       "is the time column and cannot also be signal " + signal);
    columns.push_back(file_column);
  }
  const CsvColumns csv = read_csv(reference.file, columns, 1);
  MeasuredRecord rec;
  rec.time = csv.values[0];
  rec.lines = csv.lines;
  if (rec.time.size() < kMinSamples)
    throw InputError(reference.file, "line " + std::to_string(rec.lines.back()),
                     "the record ends after " + std::to_string(rec.time.size()) + " samples; at least " +
                         std::to_string(kMinSamples) + " are needed");
  for (std::size_t i = 0; i < rec.time.size(); ++i) {
    const std::string line = "line " + std::to_string(rec.lines[i]);
    if (i > 0 && !(rec.time[i] > rec.time[i - 1]))
      throw InputError(reference.file, line,
                       "time (column " + reference.time_column + ") must increase: " + fmt(rec.time[i]) +
                           " s follows " + fmt(rec.time[i - 1]) + " s on line " + std::to_string(rec.lines[i - 1]));
    if (rec.time[i] < 0.0)
      throw InputError(reference.file, line,
                       "time " + fmt(rec.time[i]) + " s is before the start of the simulation (0 s)");
    if (rec.time[i] > t_end * (1.0 + 1e-12))
      throw InputError(reference.file, line,
                       "time " + fmt(rec.time[i]) + " s is after the end of the simulated run (" + fmt(t_end) +
                           " s): lengthen simulation.duration or simulation.cycles");
  }
  for (std::size_t k = 0; k < reference.signals.size(); ++k) {
    const auto& [signal, file_column] = reference.signals[k];
    const std::vector<double>& y = csv.values[k + 1];
    double sum2 = 0.0;
    for (double v : y) sum2 += v * v;
    const double rms = std::sqrt(sum2 / static_cast<double>(y.size()));
    double weight = 0.0;
    for (const auto& [name, w] : reference.weights)
      if (name == signal) weight = w;
    if (weight == 0.0) {
      if (!(rms > 0.0))
        throw InputError(reference.file, "column " + file_column,
                         "is zero everywhere, so it has no scale to weight it by: give reference.weights." + signal);
      weight = 1.0 / rms;
    }
    rec.signals.push_back(signal);
    rec.values.push_back(y);
    rec.weights.push_back(weight);
    rec.scale.push_back(rms);
    rec.noise.push_back(estimate_noise(y));
  }
  return rec;
}

// ---------------------------------------------------------------- problem set-up

namespace {

/// Data rows of a CSV file (lines neither empty nor comments, less the
/// header), counted without reading the values; 0 if it cannot be opened
/// (read_csv says why).
long count_data_rows(const std::string& file) {
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
                       "must be > 0 with log_scale, the scene has " + fmt(p.initial) + ": give 'initial'");
    if (p.initial < p.lower || p.initial > p.upper)
      throw InputError(source.file, at + ".initial",
                       "the scene's value " + fmt(p.initial) + " is outside [lower, upper] = [" + fmt(p.lower) + ", " +
                           fmt(p.upper) + "]: give 'initial'");
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
std::unique_ptr<Stage> run_continuation(const IdentifyProblem& problem, Simulator& simulator,
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

/// The fit at the optimum: values, weighted residuals and their Jacobian in
/// the scaled parameters (without the loss).
struct Optimum {
  std::vector<double> values;  ///< [unit of each field]
  std::vector<double> r;
  Eigen::MatrixXd jacobian;  ///< n × p
  double dof = 0.0;          ///< n − p
};

Optimum evaluate_optimum(const IdentifyProblem& problem, FitEvaluator& cost, const std::vector<double>& z,
                         IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const std::size_t n = problem.residual_count();
  if (!cost.evaluate(z.data(), true, true))
    throw NumericalError("identification: the Jacobian at the optimum could not be evaluated: " + cost.last_failure());
  Optimum o;
  o.r = cost.residuals();
  o.jacobian.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(p));
  for (std::size_t row = 0; row < n; ++row)
    for (std::size_t i = 0; i < p; ++i)
      o.jacobian(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(i)) = cost.jacobian()[row * p + i];
  double sum2 = 0.0;
  for (double x : o.r) sum2 += x * x;
  result.residuals = n;
  result.rms_residual = std::sqrt(sum2 / static_cast<double>(n));
  o.dof = static_cast<double>(n) - static_cast<double>(p);
  result.residual_sigma = std::sqrt(2.0 * result.final_cost / o.dof);
  o.values.resize(p);
  for (std::size_t i = 0; i < p; ++i) o.values[i] = to_value(problem.parameters[i], z[i]);
  return o;
}

std::vector<std::string> names_of(const IdentifyProblem& problem, const std::vector<std::size_t>& indices) {
  std::vector<std::string> names;
  for (std::size_t i : indices) names.push_back(problem.parameters[i].name);
  return names;
}

/// Structural identifiability: a direction whose effect is below the
/// finite-difference noise (integration error / step) is one the data cannot
/// see at all. Fills the singular values and warnings; returns, per
/// parameter, whether it is not identifiable (its standard error undefined).
std::vector<bool> check_rank(const IdentifyProblem& problem, const Identifiability& id, double rank_tolerance,
                             IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const Eigen::VectorXd& sv = id.singular_values;
  for (Eigen::Index i = 0; i < sv.size(); ++i) result.singular_values.push_back(sv(i));
  result.condition_number = id.condition_number;
  const double sv_max = sv.size() > 0 ? sv(0) : 0.0;
  std::vector<bool> unidentifiable(p, false);
  for (std::size_t i = 0; i < p; ++i) {
    if (!id.no_effect[i]) continue;
    unidentifiable[i] = true;
    result.warnings.push_back(
        "not identifiable: " + problem.parameters[i].name +
        " has no effect on the fitted signals (a change of it changes them by less than the integration error)");
  }
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    if (sv(k) >= rank_tolerance * sv_max) continue;
    const Eigen::VectorXd v = id.directions.col(k);
    std::vector<std::size_t> involved;
    for (std::size_t i = 0; i < p; ++i)
      if (!id.no_effect[i] && std::abs(v(static_cast<Eigen::Index>(i))) >= 0.1) involved.push_back(i);
    if (involved.empty()) continue;
    std::ostringstream dir;
    dir.precision(3);
    for (std::size_t j = 0; j < involved.size(); ++j) {
      const FitParameter& par = problem.parameters[involved[j]];
      const double c = v(static_cast<Eigen::Index>(involved[j]));
      dir << (j == 0 ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ")) << std::abs(c) << " "
          << (par.log_scale ? "ln " : "") << par.name;
    }
    for (std::size_t i : involved) unidentifiable[i] = true;
    std::ostringstream msg;
    msg.precision(3);
    msg << "not identifiable: the data cannot separate " << join_names(names_of(problem, involved))
        << " (rank-deficient Jacobian, singular value ratio " << sv(k) / sv_max << " below the finite-difference noise "
        << rank_tolerance << "); changing them along (" << dir.str()
        << ") [unit-normalised] leaves the fit unchanged. Fix one of them or add data that separates them.";
    result.warnings.push_back(msg.str());
  }
  return unidentifiable;
}

/// Covariance of the scaled parameters. The weights normalise units, not
/// noise, so each record's signal gets its own residual variance σ_g² (records
/// of different drops or sensors are not equally noisy): the sandwich of
/// sandwich_covariance() with A = (Σ ψ'(r) JᵀJ)⁻¹ from Ceres (pseudo-inverse
/// where rank-deficient; ψ = ρ'(r²) r is the influence of a residual under the
/// robust loss ρ, ψ' = 1 without one): with one record and no loss σ² (JᵀJ)⁻¹,
/// with a loss the M-estimator covariance (Huber 1981, ch. 7). Null (and a
/// warning) when it cannot be computed.
std::optional<Eigen::MatrixXd> covariance_at_optimum(const IdentifyProblem& problem, Stage& stage,
                                                     std::vector<double>& z, const Optimum& o, IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  if (o.dof <= 0.0) {
    result.warnings.push_back("no standard errors: as many parameters as measured values");
    return std::nullopt;
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.null_space_rank = -1;
  cov_options.min_reciprocal_condition_number = 1e-14;
  cov_options.apply_loss_function = true;
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> blocks = {{z.data(), z.data()}};
  if (!covariance.Compute(blocks, stage.problem.get())) {
    result.warnings.push_back("no standard errors: Ceres could not compute the covariance at the optimum");
    return std::nullopt;
  }
  std::vector<double> c(p * p);
  if (!covariance.GetCovarianceBlock(z.data(), z.data(), c.data())) {
    result.warnings.push_back("no standard errors: Ceres could not return the covariance block");
    return std::nullopt;
  }
  const auto pp = static_cast<Eigen::Index>(p);
  const Eigen::MatrixXd a =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(c.data(), pp, pp);
  std::vector<double> loss_weights(o.r.size());
  for (std::size_t i = 0; i < o.r.size(); ++i) {
    const double ri = o.r[i];
    double rho[3] = {ri * ri, 1.0, 0.0};
    if (stage.loss != nullptr) stage.loss->Evaluate(ri * ri, rho);
    loss_weights[i] = rho[1];
  }
  std::vector<std::size_t> group_rows;
  for (const FitExperiment& e : problem.experiments)
    for (std::size_t s = 0; s < e.record.signals.size(); ++s) group_rows.push_back(e.record.time.size());
  return sandwich_covariance(a, o.jacobian, o.r, loss_weights, group_rows, o.dof);
}

/// Estimates, their standard errors (the delta method scales log-parameter
/// errors back: σ_p = p σ_ln p) and correlations; warns of estimates on a bound.
void record_estimates(const IdentifyProblem& problem, const std::vector<double>& z, const Optimum& o,
                      const std::optional<Eigen::MatrixXd>& cov_z, const std::vector<bool>& undetermined,
                      IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  std::vector<double> std_z(p, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < p; ++i) {
    const FitParameter& par = problem.parameters[i];
    ParameterEstimate est;
    est.name = par.name;
    est.path = par.path;
    est.value = o.values[i];
    est.initial = par.initial;
    est.log_scale = par.log_scale;
    if (std::isfinite(par.lower)) est.lower = par.lower;
    if (std::isfinite(par.upper)) est.upper = par.upper;
    const double lo = scaled_lower(par), hi = scaled_upper(par);
    const double tol = 1e-9 * std::max(1.0, std::abs(z[i]));
    est.at_bound = (std::isfinite(lo) && z[i] - lo <= tol) || (std::isfinite(hi) && hi - z[i] <= tol);
    const double var = cov_z ? (*cov_z)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i))
                             : std::numeric_limits<double>::quiet_NaN();
    if (cov_z && !undetermined[i] && std::isfinite(var) && var >= 0.0) {
      std_z[i] = std::sqrt(var);
      est.std_error = par.log_scale ? o.values[i] * std_z[i] : std_z[i];
    }
    if (est.at_bound)
      result.warnings.push_back(par.name + " ended on its " +
                                (std::isfinite(lo) && z[i] - lo <= tol ? std::string("lower") : std::string("upper")) +
                                " bound (" + fmt(o.values[i]) +
                                "): the optimum may lie beyond it and its standard error is not meaningful");
    result.parameters.push_back(est);
  }
  result.correlation.assign(p, std::vector<std::optional<double>>(p));
  for (std::size_t i = 0; i < p; ++i) {
    for (std::size_t j = 0; j < p; ++j) {
      if (!(std_z[i] > 0.0) || !(std_z[j] > 0.0)) continue;
      const double rho = (*cov_z)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) / (std_z[i] * std_z[j]);
      if (std::isfinite(rho)) result.correlation[i][j] = i == j ? 1.0 : std::clamp(rho, -1.0, 1.0);
    }
  }
}

/// Practical identifiability: a parameter known only to worse than
/// max_relative_std_error of its value is not determined by these data. The
/// weakest direction of the Jacobian says which parameters trade off with it.
void check_standard_errors(const IdentifyProblem& problem, const Identifiability& id, std::vector<bool>& unidentifiable,
                           IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const SolverSpec& spec = problem.solver;
  std::vector<std::size_t> weak;
  for (std::size_t i = 0; i < p; ++i) {
    const ParameterEstimate& est = result.parameters[i];
    if (unidentifiable[i] || !est.std_error) continue;
    const double rel = *est.std_error / (est.value != 0.0 ? std::abs(est.value) : problem.parameters[i].scale);
    if (rel > spec.max_relative_std_error) weak.push_back(i);
  }
  if (weak.empty()) return;
  std::vector<std::size_t> involved = weak;
  const Eigen::VectorXd v = id.directions.col(id.directions.cols() - 1);
  bool weak_in_direction = false;
  for (std::size_t i : weak) weak_in_direction = weak_in_direction || std::abs(v(static_cast<Eigen::Index>(i))) >= 0.2;
  if (weak_in_direction) {
    for (std::size_t i = 0; i < p; ++i)
      if (std::abs(v(static_cast<Eigen::Index>(i))) >= 0.2 &&
          std::find(involved.begin(), involved.end(), i) == involved.end())
        involved.push_back(i);
    std::sort(involved.begin(), involved.end());
  }
  std::ostringstream msg;
  msg.precision(3);
  msg << "not identifiable: the data do not determine " << join_names(names_of(problem, involved))
      << " (relative standard error";
  for (std::size_t j = 0; j < involved.size(); ++j) {
    const ParameterEstimate& est = result.parameters[involved[j]];
    msg << (j == 0 ? " " : ", ")
        << (est.std_error ? percent(*est.std_error / std::max(std::abs(est.value), 1e-300)) : std::string("undefined"));
  }
  msg << "; limit solver.max_relative_std_error = " << percent(spec.max_relative_std_error) << ")";
  if (involved.size() == 2 && result.correlation[involved[0]][involved[1]])
    msg << ", correlation " << *result.correlation[involved[0]][involved[1]];
  if (involved.size() > 1)
    msg << ": they trade off against each other. Fix one of them or add data that separates them"
           " (other drop heights, other speeds).";
  else
    msg << ": the signals hardly depend on it. Fix it or add data that excites it.";
  result.warnings.push_back(msg.str());
  for (std::size_t i : involved) unidentifiable[i] = true;
}

/// Measured against fitted, at the optimum; warns of a misfit well above the noise.
void record_fits(const IdentifyProblem& problem, Simulator& simulator, const std::vector<double>& values,
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
        result.warnings.push_back("experiment '" + e.name + "', " + fit.signals[s] + ": RMS misfit " +
                                  fmt(fit.rms_error.back()) +
                                  " is more than three times the noise estimated from the record (" +
                                  fmt(fit.noise[s]) + "): the model or its fixed parameters may not match the data");
    }
    result.fits.push_back(std::move(fit));
  }
}

}  // namespace

IdentifyResult identify(const IdentifyProblem& problem, const IdentifyOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  const std::size_t p = problem.parameters.size();
  const SolverSpec& spec = problem.solver;
  Simulator simulator(problem, options.threads, options.journal);
  IdentifyResult result;
  result.loss = spec.loss;
  result.loss_scale = loss_scale_of(problem);

  std::vector<double> z(p);
  for (std::size_t i = 0; i < p; ++i) z[i] = to_scaled(problem.parameters[i], problem.parameters[i].initial);
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

}  // namespace camdyn::optim
