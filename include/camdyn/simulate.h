// Simulating a scene and reading the result, with plain standard types only:
// the metrics by name, a summary of the integration in the manner of Ceres'
// Solver::Summary (how it ended, why, and the counters), the time series as
// named columns and the contact events. Part of the public API.
#pragma once

#include <camdyn/scene.h>

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace camdyn {

/// The most threads SimulateOptions::jobs may ask for (each holds a workspace).
inline constexpr int kMaxJobs = 1024;

/// What simulate() is asked to do. simulate() checks it as the config
/// loader checks a field: InputError with an empty file(), the field's name
/// as path() ("sample_times", "jobs") and the reason.
struct SimulateOptions {
  /// Record the time series (Result::series) at the config's output step.
  bool record_series = true;
  /// Extra times [s] at which the state is sampled from the integrator's
  /// dense output into Result::samples: finite, ascending (each ≥ the one
  /// before), within the run [0, Result::end_time], at most kMaxPointsPerCall.
  std::vector<double> sample_times;
  /// Called now and then (at most every 0.25 s of wall time, between
  /// integrator steps) with the fraction of simulated time done, in [0, 1].
  /// It may throw to abandon the run: the exception leaves simulate() (the
  /// Python module stops a run on Ctrl-C so).
  std::function<void(double)> progress;
  /// Threads for simulation.steady_state's orbit search (its Jacobian
  /// columns), 0 … kMaxJobs; 0: one per core. The numbers do not depend on it.
  int jobs = 1;
};

/// How a run ended (summary.json's `solver.termination`).
enum class TerminationStatus {
  converged,           ///< integrated to the end time
  integrator_failure,  ///< the integrator gave up
  step_budget,         ///< more internal steps than integrator.max_steps
  wall_time_budget,    ///< longer than integrator.max_wall_time_s
  penetration_limit,   ///< penetration far beyond what the contact law describes
  left_flat_face,      ///< the contact point ran off the flat face
  tracking_lost,       ///< the contact pair could not be found again
  no_initial_contact,  ///< no contact pair at the start
};

/// The word summary.json writes for a status ("converged", "step_budget", ...).
const char* termination_name(TerminationStatus status);

/// The integration: how it ended and what it cost.
struct RunSummary {
  TerminationStatus termination = TerminationStatus::converged;
  /// Empty when converged; otherwise what stopped the run, naming the time and
  /// cam angle reached.
  std::string message;
  std::string method;  ///< integrator.method
  double rtol = 0.0, atol = 0.0;
  long steps = 0;
  long rhs_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_iterations = 0;
  long jacobian_evaluations = 0;
  long reinitialisations = 0;
  long events = 0;           ///< roots located (onsets, separations, force clamp switches)
  long tracking_resets = 0;  ///< global re-initialisations of the contact pair
  long projections = 0;      ///< drift projections of the differential tracking
  double run_time_s = 0.0;   ///< wall time of the run [s]
  /// Richardson estimate (integrator.error_estimate = "richardson"): max
  /// position difference [m; rad for an oscillating follower, whose
  /// position is its arm angle] and relative peak force difference [-] to a run
  /// at a 100x tighter tolerance; both 0 without it.
  bool error_estimated = false;
  double error_position = 0.0;
  double error_peak_contact_force = 0.0;

  bool converged() const { return termination == TerminationStatus::converged; }
};

/// Time series as named columns of equal length (timeseries.csv's columns:
/// time, cam_angle_deg, follower_position, ..., in that order).
struct Columns {
  std::vector<std::string> names;
  std::vector<std::string> units;           ///< units[i] is the unit of names[i] (column_unit)
  std::vector<std::vector<double>> values;  ///< values[i] is the column names[i]

  /// The column called `name`; throws std::out_of_range if there is none.
  const std::vector<double>& operator[](std::string_view name) const;
  std::size_t rows() const { return values.empty() ? 0 : values.front().size(); }
};

/// A contact onset or separation located by root finding.
struct Event {
  double time = 0.0;           ///< [s]
  double cam_angle_deg = 0.0;  ///< [deg]
  bool onset = true;           ///< onset (gap closes) or separation (gap opens)
  double speed = 0.0;          ///< normal approach speed at onset, separation speed at separation [m/s]
  bool impact = false;         ///< an onset after a separation, with a positive approach speed
  bool grazing = false;        ///< an onset that is not an impact (no approach, or no separation before it)
  bool lash =
      false;  ///< a separation while a body rests on its seat, or the onset taking that lash up (docs/model.md §12)
  /// A separation's cause: "take_up", "float" or "seat_bounce"; an onset
  /// carries the cause of the separation it ends; empty otherwise (docs/valvetrain.md).
  std::string cause;
};

struct Result {
  /// summary.json's metrics over the evaluated cycles, by name (SI units;
  /// impact_count as a number; jump_speed_rpm +inf when the law never
  /// decelerates; peak_contact_stress only with materials and
  /// max_face_excursion only for a flat face, absent otherwise). Partial when
  /// the run did not converge.
  std::map<std::string, double> metrics;
  RunSummary solver;
  Columns series;   ///< at the config's output step (empty without record_series)
  Columns samples;  ///< at SimulateOptions::sample_times
  std::vector<Event> events;
  /// What `metrics` are over (summary.json `metrics_over`): "window" (the
  /// evaluated cycles) or "periodic_orbit" (simulation.steady_state found a
  /// stable orbit: one period of it).
  std::string metrics_over = "window";
  /// With simulation.steady_state: the orbit found, or why the window's
  /// metrics stay (summary.json `steady_state`); empty without it.
  std::string steady_state;
  double evaluated_from = 0.0;  ///< start of the evaluated window [s]
  double end_time = 0.0;        ///< [s]
};

/// Simulates the scene, as `camdyn run` does (with simulation.steady_state,
/// the metrics over one period of the orbit the run settles on). A solver that gives up or a budget that runs out is
/// not an exception: result.solver says how the run ended (call
/// throw_if_failed to make it one). Throws InputError when the follower has
/// no static equilibrium to start from, or for options out of their range
/// (SimulateOptions).
Result simulate(const Scene& scene, const SimulateOptions& options = {});

/// The unit of a time-series column: one every run has, or a follower
/// train's by its suffix (`valve_link_force`: "N"); "" for a name that is
/// neither. `oscillating`: the follower is an arm, whose coordinate's columns
/// are in rad and its own seat, stop and spring forces in N m.
std::string column_unit(std::string_view name, bool oscillating = false);
/// The columns every run has, in order, with their units (a translating follower's).
std::vector<std::pair<std::string, std::string>> series_column_units();
/// A follower train's column suffixes (`_position`, `_link_force`, ...) with their units.
std::vector<std::pair<std::string, std::string>> train_column_units();

/// Throws NumericalError(result.solver.message) unless the run converged.
void throw_if_failed(const Result& result);

/// For its lifetime, every simulation and study run on the thread that made
/// it polls `interrupted` at most every 0.25 s of wall time (between
/// integrator steps; docs/library.md). Once it returns true, every run stops
/// as when a study's wall-time budget (--max-study-time) is used up: a
/// simulation returns early (not converged), a study keeps what its journal
/// holds and ends with exit code 3. The Python module stops on Ctrl-C this
/// way. One at a time per process.
class InterruptCheck {
 public:
  explicit InterruptCheck(std::function<bool()> interrupted);
  ~InterruptCheck();
  InterruptCheck(const InterruptCheck&) = delete;
  InterruptCheck& operator=(const InterruptCheck&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace camdyn
