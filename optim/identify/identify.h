// Contact identification (docs/config.md `identify`): fits numeric scene
// parameters (contact stiffness, exponent, restitution, damping, friction,
// follower damping, ... any numeric config field by dotted path) to measured
// records by nonlinear least squares (Ceres, kept out of this header).
//
// Residuals are weighted differences between simulated and measured signals,
// the simulation sampled at the data's own times from the integrator's dense
// output; derivatives are finite differences of whole simulations in the
// scaled parameter space (ln p for log-scale parameters): forward in the
// iterations (solver.differences), central at the optimum; the standard
// errors come from the covariance at the optimum, scaled by the residual
// variance, and an identifiability check (rank of the Jacobian, relative
// standard errors) names the parameters the data cannot determine.
//
// The pieces, each in its own file of optim/identify/: the records
// (measured_record.h), the parallel simulations and their run cache
// (fit_simulator.h), the residuals and their finite differences
// (finite_differences.h), one Ceres solve (ceres_stage.h) and the statistics
// at the optimum (optimum_statistics.h, identify_statistics.h).
#pragma once

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/config.h"
#include "optim/identify/identify_config.h"
#include "optim/identify/measured_record.h"

namespace camdyn::optim {

/// One fitted parameter, resolved against the scene.
struct FitParameter {
  std::string name;  ///< as written in the config (the key of `parameters`)
  std::string path;  ///< full dotted path (mechanism.contact.stiffness)
  double initial = 0.0;
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  bool log_scale = false;
  double scale = 1.0;  ///< magnitude for the finite-difference step of a linear parameter
};

struct FitExperiment {
  std::string name;
  ReferenceSpec reference;
  Json scene_json;    ///< the study's resolved scene with this experiment's `set` applied
  SceneConfig scene;  ///< the same at the initial parameter values
  MeasuredRecord record;
};

/// Everything identify() needs, checked: parameter paths are numeric fields of
/// the scene, bounds and initial values make valid scenes, records are read.
struct IdentifyProblem {
  std::string config_file;  ///< for messages
  ConfigSource source;
  SceneConfig scene;  ///< the study's scene (without experiment overrides)
  std::vector<FitParameter> parameters;
  std::vector<FitExperiment> experiments;
  SolverSpec solver;
  std::string fingerprint;  ///< identify_fingerprint (optim/identify/identify_journal.h): what a journal must match
  std::size_t residual_count() const;
};

/// Memory a fit holds per measured value (sample × signal) [bytes]: the
/// Ceres residual block of the sample, the Jacobian rows, the simulated
/// signals kept for reuse, fit.csv and the report (measured on
/// identify_single_drop with 1e5 and 1e6 samples: 745 and 766 bytes).
inline constexpr double kBytesPerMeasuredValue = 800.0;

/// The memory the fit of `problem` is estimated to need [bytes].
std::size_t estimated_memory_bytes(const IdentifyProblem& problem);

/// Resolves a spec against the study's scene. Throws InputError (file, dotted path or CSV line).
IdentifyProblem prepare_identify(const SceneConfig& scene, const IdentifySpec& spec, const ConfigSource& source);

/// Splits an identify study config into scene and study part, checks both and
/// prepares the problem (what `camdyn validate` runs). `resolved` (may be null)
/// receives the resolved config.
IdentifyProblem load_identify_problem(const Json& doc, const ConfigSource& source, Json* resolved = nullptr);

/// `scene_json` with `values` (one per parameter) set, as a scene.
SceneConfig scene_with(const Json& scene_json, const std::vector<FitParameter>& parameters,
                       const std::vector<double>& values, const ConfigSource& source);

struct ParameterEstimate {
  std::string name, path;
  double value = 0.0;  ///< identified [unit of the field]
  double initial = 0.0;
  std::optional<double> std_error;     ///< null where the data do not determine it
  std::optional<double> lower, upper;  ///< null: unbounded
  bool log_scale = false;
  bool at_bound = false;  ///< ended on a bound: the standard error is not meaningful
  bool identifiable = true;
};

/// Measured against fitted signals of one experiment, at the record's times.
struct ExperimentFit {
  std::string name;
  std::vector<double> time;
  std::vector<std::string> signals;
  std::vector<std::vector<double>> measured, fitted;  ///< [k][i]
  std::vector<double> weights;
  std::vector<double> rms_error;  ///< RMS of fitted − measured per signal [unit]
  std::vector<double> noise;      ///< estimated measurement noise per signal [unit]
};

/// One solve of the continuation (smoothed signals first, raw last).
struct StageSummary {
  double smoothing_s = 0.0;  ///< [s], 0 for the raw signals
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  std::string termination;
  std::vector<double> values;  ///< parameter values at the end of the stage
};

/// One start of a multi-start fit (solver.starts).
struct FitStart {
  std::vector<double> initial;  ///< where it started [units of the fields]
  std::vector<double> values;   ///< where it ended (empty when it failed)
  double final_cost = 0.0;
  bool poor_fit = false;
  std::string error;  ///< why it failed, if it did
};

struct IdentifyResult {
  std::vector<ParameterEstimate> parameters;
  /// Correlation of the estimates; null where a standard error is undefined.
  std::vector<std::vector<std::optional<double>>> correlation;
  /// Ceres cost ½ Σ ρ(r²) of the weighted residuals of the raw records, when
  /// the last stage started (after any smoothed stages) and at the optimum.
  double initial_cost = 0.0, final_cost = 0.0;
  double rms_residual = 0.0;    ///< √(Σ r² / N) of the weighted residuals [-]
  double residual_sigma = 0.0;  ///< √(2 cost / (N − p)): the residual scale the standard errors use [-]
  std::size_t residuals = 0;
  int iterations = 0;       ///< over all stages
  std::string termination;  ///< Ceres termination type of the last stage (CONVERGENCE, NO_CONVERGENCE, ...)
  std::string message;      ///< Ceres' message
  double run_time_s = 0.0;
  long simulations = 0;          ///< simulations the fit needed (run, or taken from the journal of a killed run)
  long reused_points = 0;        ///< parameter points whose simulations were kept from an earlier evaluation
  long resumed_simulations = 0;  ///< of `simulations`, those taken from the journal (optim/identify/identify_journal.h)
  std::string loss;
  double loss_scale = 0.0;  ///< robust loss scale used (0 without one)
  bool identifiable = true;
  /// The misfit is significantly above the noise estimated from the records
  /// (optim/identify/fit_quality.h): a local minimum is likely, and no
  /// standard error is reported.
  bool poor_fit = false;
  double misfit_ratio = 0.0;     ///< worst signal's (RMS misfit / noise)² [-]
  std::vector<FitStart> starts;  ///< every start, the first from the config's initial values
  /// Singular values of the column-equilibrated Jacobian at the optimum,
  /// largest first, and its condition number (largest / smallest).
  std::vector<double> singular_values;
  double condition_number = 0.0;
  std::vector<std::string> warnings;
  std::vector<StageSummary> stages;
  std::vector<ExperimentFit> fits;
  SceneConfig identified_scene;  ///< the study's scene with the identified values

  /// The identified values, in the parameters' order.
  std::vector<double> identified_values() const {
    std::vector<double> v;
    for (const ParameterEstimate& e : parameters) v.push_back(e.value);
    return v;
  }
};

/// Where the fit is, for a progress line: the continuation stage (1-based,
/// of `stages`; the last one fits the raw signals) and the solver iteration in it.
struct IdentifyProgress {
  int stage = 1, stages = 1;
  double smoothing = 0.0;  ///< the stage's smoothing window [s], 0 for the raw signals
  int iteration = 0;       ///< Ceres iteration within the stage (0: the starting point)
  double cost = 0.0;       ///< the stage's cost at that iteration
};

class IdentifyJournal;

struct IdentifyOptions {
  int threads = 1;  ///< simulations run in parallel
  /// Called after each solver iteration of each continuation stage.
  std::function<void(const IdentifyProgress&)> progress;
  /// Where simulations, accepted iterates and stages are journaled, and the
  /// simulations of a killed run are taken from (null: no journal).
  IdentifyJournal* journal = nullptr;
  /// Spread the starts over the MPI ranks (docs/optimize.md "MPI ranks";
  /// collective: every rank calls identify()): start k on rank k mod N. Rank
  /// 0 returns the fit; the other ranks return an empty result.
  bool over_ranks = false;
};

/// Runs the fit. Throws NumericalError (exit 3) when the solver fails (no
/// usable solution, e.g. the simulation fails at the initial values) and
/// InputError if a parameter value makes an invalid scene.
IdentifyResult identify(const IdentifyProblem& problem, const IdentifyOptions& options = {});

}  // namespace camdyn::optim
