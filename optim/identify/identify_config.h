// The study fields of an `identify` config (docs/config.md, section `identify`):
// which scene parameters to fit (any numeric field by dotted path, with
// bounds, log scale and initial value), the measured records to fit them to
// (one `reference`, or several `experiments` with shared parameters and their
// own scene overrides), and the least-squares solver settings. Each struct is
// mapped to JSON in one `visit` (io/json_archive.h), so unknown keys are errors
// with the closest valid key suggested; the keyed maps (`parameters`,
// `signals`, `weights`, `set`) are read beside it in identify_config.cc.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io/config.h"

namespace camdyn::optim {

/// A measured record (`reference`): a CSV file with a header row.
struct ReferenceSpec {
  std::string file;                  ///< made absolute against the config's directory
  std::string time_column = "time";  ///< [s], strictly increasing, in simulation time
  /// `signals`: timeseries.csv column (contact_force, follower_acceleration, ...) → file column, in file order.
  std::vector<std::pair<std::string, std::string>> signals;
  /// `weights`: per signal [1/unit of the signal]; absent = 1/RMS of the measured signal, so
  /// that signals of different units mix.
  std::vector<std::pair<std::string, double>> weights;
};

/// One experiment (a drop height, a rig speed): its record and how its scene
/// differs from the study's scene (`set`: dotted path → value, as `--set`).
struct ExperimentSpec {
  std::string name;
  ReferenceSpec reference;
  std::vector<std::pair<std::string, Json>> set;
};

/// One fitted parameter (`parameters."contact.stiffness"`).
struct ParameterSpec {
  std::string path;               ///< dotted config path as written (the map key)
  std::optional<double> initial;  ///< absent/null: the scene's value
  std::optional<double> lower;    ///< absent/null: unbounded
  std::optional<double> upper;
  bool log_scale = false;  ///< fit ln(value): for positive parameters spanning decades
};

/// `solver`: Ceres trust-region least squares with finite-difference derivatives.
/// Ceres' own limits of the trust region (Solver::Options'
/// min_trust_region_radius and max_trust_region_radius, left at their defaults).
inline constexpr double kMinTrustRegionRadius = 1e-32;
inline constexpr double kMaxTrustRegionRadius = 1e16;
/// The range of solver.loss_scale: its square stays a finite, normal number.
inline constexpr double kMinLossScale = 1e-100;
inline constexpr double kMaxLossScale = 1e100;

struct SolverSpec {
  int max_iterations = 100;
  std::string loss = "none";  ///< none, huber, cauchy, soft_l1
  /// Robust loss scale in weighted residual units (fractions of each signal's scale).
  /// null: three times the measurement noise estimated from the records.
  std::optional<double> loss_scale;
  double function_tolerance = 1e-8;  ///< relative cost decrease that counts as converged
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;  ///< relative step that counts as converged
  /// Finite-difference step in the scaled parameter space: Δln p for log-scale
  /// parameters, Δp / max(|p|, scale) otherwise. Must stay well above the
  /// integration noise (≈ rtol) so the derivative resolves the response, not the noise.
  double fd_relative_step = 1e-4;
  /// The Jacobian in the solver's iterations: "forward" differences (p + 1
  /// simulations per experiment) or "central" (2p + 1). Gauss–Newton steps need
  /// only the Jacobian's direction to about the step's accuracy, so forward
  /// differences cost fewer simulations for the same optimum (identify_drop
  /// 192 against 292, identify_cam_rig 148 against 260). Where two parameters
  /// trade off almost exactly, the forward Jacobian's error along the
  /// trade-off gets step after step rejected and central is cheaper
  /// (identify_single_drop: 41 against 120). The covariance at the optimum
  /// always uses central differences.
  std::string differences = "forward";
  bool forward_differences() const { return differences == "forward"; }
  /// Initial Levenberg–Marquardt trust region radius (Ceres; the inverse of the
  /// damping relative to diag(JᵀJ)). Ceres' default 1e4 makes the first step
  /// pure Gauss–Newton, which from a far start runs along a poorly determined
  /// direction (stiffness against exponent) straight into the bounds.
  double initial_trust_region_radius = 100.0;
  /// Continuation for records with impacts: fit first to the signals smoothed
  /// over these time windows [s] (moving average applied twice, widest first),
  /// then to the raw signals. A simulated impact pulls towards the measured
  /// one only where the two overlap; smoothing widens them.
  std::vector<double> smoothing;
  /// A parameter whose standard error exceeds this fraction of its value is
  /// reported as not identifiable from the data.
  double max_relative_std_error = 0.1;
  /// Most measured values (samples × signals, all records together) a fit
  /// takes: the fit holds about kBytesPerMeasuredValue (optim/identify/identify.h) of
  /// memory per value, so the default is about 400 MB; a larger record is
  /// refused at validation (decimate it, or raise this).
  long max_measured_values = 500000;
  /// Starts of the fit: the config's initial values first, the others from a
  /// space-filling (Halton) design over the bounds; the best fit is kept.
  /// null: automatic, one start, and 2p + 2 more when its fit is poor
  /// (optim/identify/fit_quality.h).
  std::optional<int> starts;
};

struct IdentifySpec {
  std::vector<ParameterSpec> parameters;
  std::vector<ExperimentSpec> experiments;  ///< one entry for the single-`reference` form
  bool single_reference = false;            ///< given as `reference` (the scene itself is the experiment)
  SolverSpec solver;
};

/// The keys of a study config that belong to the identify study (the rest is the scene).
const std::vector<std::string>& identify_study_keys();

/// The timeseries.csv columns a reference signal may name.
std::vector<std::string> identify_signal_names();

/// Reads the identify part of a study config (the keys of identify_study_keys()).
/// Throws InputError(file, dotted path, reason); unknown keys are errors with a suggestion.
IdentifySpec identify_spec_from_json(const Json& study_part, const ConfigSource& source);

/// The resolved identify part (every field, defaults filled in).
Json to_json(const IdentifySpec& spec);

}  // namespace camdyn::optim
