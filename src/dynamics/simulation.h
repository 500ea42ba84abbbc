// One simulation run of a scene: initial conditions, integration with event
// location at contact onset / separation (docs/model.md §6), the energy balance
// (§7), the metrics over the evaluated cycles (§8) and the time series.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "dynamics/metrics.h"
#include "dynamics/model.h"
#include "integrate/ode_system.h"
#include "scene/scene.h"

namespace camdyn {

/// Columns of timeseries.csv (docs/config.md, "Outputs of simulate"), one entry per output step.
struct TimeSeries {
  std::vector<double> time, cam_angle_deg, follower_position, follower_velocity, follower_acceleration,
      kinematic_position, gap, contact_force, friction_force, energy_residual,
      contact_offset,  ///< contact point across the follower face from its centre [m]
      cam_speed_rpm;   ///< cam speed [rpm] (constant unless the drive is a shaft)
  /// A follower train's columns (docs/model.md §12), after the others:
  /// `<body>_position`, `<body>_velocity` (train bodies), `<body>_link_force`,
  /// `<body>_seat_force`, `<body>_stop_force`, `<body>_spring_force` where the body has them.
  std::vector<std::string> train_names;
  std::vector<std::vector<double>> train;
  /// For the report's plots, not columns of timeseries.csv: the drive torque
  /// on the cam [N m] (dynamics/contact_stress.h cam_drive_torque), the
  /// motor's torque with a shaft drive [N m] (the shaft's with a
  /// constant-speed motor), the Hertz contact stress where the contact has
  /// materials [Pa]; empty where the run has no such thing.
  std::vector<double> cam_torque, motor_torque, contact_stress;

  /// The columns every run has, in order (dynamics/series_columns.h kSeriesColumns).
  static std::vector<std::string> column_names();
  /// Their values, in that order.
  std::vector<const std::vector<double>*> columns() const;
  /// Every column of this series: column_names() and the train's.
  std::vector<std::string> all_names() const;
  std::vector<const std::vector<double>*> all_columns() const;
};

/// Every column the model's time series has: TimeSeries::column_names() and
/// its train's (docs/model.md §12).
std::vector<std::string> series_column_names(const Model& model);

/// Whether `name` has the form of a train column (`<body>_position`,
/// `_velocity`, `_link_force`, `_seat_force`, `_stop_force`, `_spring_force`).
bool is_train_column_name(const std::string& name);

/// A contact onset or separation located by root finding.
struct ContactEvent {
  double time = 0.0;               ///< [s]
  double cam_angle_deg = 0.0;      ///< [deg]
  bool onset = true;               ///< onset (gap closes) or separation (gap opens)
  double speed = 0.0;              ///< normal approach speed at onset, separation speed at separation [m/s]
  bool impact = false;             ///< onset after a separation with a positive approach speed
  double follower_velocity = 0.0;  ///< q̇ at the event [m/s | rad/s]
  /// An onset that is not an impact: no approach (speed ≤ 0, a graze), or no
  /// separation before it (a re-entry) (docs/model.md §6).
  bool grazing = false;
  /// Valve lash (docs/model.md §12): a separation while a body rests on its
  /// seat, or the onset that takes that lash up. Neither a jump nor an impact.
  bool lash = false;
  /// A separation's cause (dynamics/separation_cause.h: take-up bounce, float,
  /// seat bounce); an onset carries the cause of the separation it ends. None
  /// for lash and for an onset that ends no separation.
  SeparationCause cause = SeparationCause::none;
};

/// How a run ended (summary.json `solver.termination`), in the manner of
/// Ceres' Solver::Summary: every way simulate() can stop before its end time.
enum class Termination {
  converged,           ///< integrated to the end time
  integrator_failure,  ///< the integrator gave up (error-test or corrector failures, a failing RHS, SUNDIALS)
  step_budget,         ///< more internal steps than integrator.max_steps
  wall_time_budget,    ///< longer than integrator.max_wall_time_s
  penetration_limit,   ///< penetration beyond Model::penetration_limit: the contact is far too soft for its load
  left_flat_face,      ///< the contact point ran off the flat face (|offset| > face_width / 2)
  tracking_lost,       ///< the contact pair could not be found again after drift
  no_initial_contact,  ///< no contact pair at the start
};

/// The names summary.json gives a termination (`solver.termination`).
inline constexpr EnumName<Termination> kTerminationNames[] = {{Termination::converged, "converged"},
                                                              {Termination::integrator_failure, "integrator_failure"},
                                                              {Termination::step_budget, "step_budget"},
                                                              {Termination::wall_time_budget, "wall_time_budget"},
                                                              {Termination::penetration_limit, "penetration_limit"},
                                                              {Termination::left_flat_face, "left_flat_face"},
                                                              {Termination::tracking_lost, "tracking_lost"},
                                                              {Termination::no_initial_contact, "no_initial_contact"}};
constexpr std::span<const EnumName<Termination>> enum_names(Termination) { return kTerminationNames; }

struct SolverSummary {
  std::string method;
  double rtol = 0.0, atol = 0.0;
  SolverCounters counters;
  long events = 0;            ///< roots located (onsets, separations, force clamp switches)
  long tracking_resets = 0;   ///< global re-initialisations of the contact pair
  long projections = 0;       ///< drift projections of the differential tracking
  long flights = 0;           ///< flights advanced in closed form (integrator.flight)
  long flight_intervals = 0;  ///< intervals the closed-form flights were followed on
  double run_time_s = 0.0;
  Termination termination = Termination::converged;
  /// Empty when converged; otherwise what stopped the run, naming the time and
  /// cam angle reached (the text of the NumericalError throw_if_failed throws).
  std::string message;
  bool converged() const { return termination == Termination::converged; }
};

/// How accurate a run is (summary.json `solver.error_estimate`).
struct ErrorEstimate {
  double energy_residual = 0.0;     ///< docs/model.md §7, always available
  bool richardson = false;          ///< the fields below were computed
  double position = 0.0;            ///< max |q − q_tight| over the evaluated cycles [m | rad] (coordinate_units.h)
  double peak_contact_force = 0.0;  ///< |F_peak / F_peak,tight − 1| [-]
  double tight_run_time_s = 0.0;    ///< cost of the tighter run [s]
};

struct SimulationResult {
  Metrics metrics;
  /// What `metrics` are over: "window" (the evaluated cycles) or
  /// "periodic_orbit" (simulation.steady_state found a stable orbit: one
  /// period of it; study/steady_state.h), and a sentence saying which and why.
  std::string metrics_over = "window";
  std::string metrics_note;
  SolverSummary solver;
  TimeSeries series;
  TimeSeries samples;  ///< at SimulationOptions::sample_times
  std::vector<ContactEvent> events;
  ErrorEstimate error;
  double evaluated_from = 0.0;  ///< start of the evaluated window [s]
  double end_time = 0.0;        ///< [s]
  /// How long the metrics are over [s]: one period of the orbit when
  /// metrics_over is "periodic_orbit", else end_time − evaluated_from.
  double metrics_duration() const { return orbit_duration > 0.0 ? orbit_duration : end_time - evaluated_from; }
  double orbit_duration = 0.0;  ///< [s] the orbit's period whose metrics replaced the window's (0: none)
  /// Where the run ended: the state (one value per state of Model::layout),
  /// the approach speed of the contact episode then in progress (v₀ [m/s])
  /// and the constant-speed motor's phase [rad]: what a run that continues
  /// this one starts from (SimulationOptions::start).
  std::vector<double> final_state;
  double final_approach_speed = 0.0, final_motor_phase = 0.0;
};

/// A state to start a run from instead of the equilibrium on the law: the
/// periodic study's shooting starts each revolution of its map here.
struct StartState {
  /// One value per state of Model::layout; the contact pair parameters in it
  /// are found again from the others (Newton, as at any start).
  std::vector<double> y;
  double approach_speed = 0.0;  ///< v₀ of the contact episode in progress [m/s] (floored as always)
  double motor_phase = 0.0;     ///< shaft drive at constant motor speed: the motor's angle offset [rad]
};

struct SimulationOptions {
  bool record_series = true;
  /// Whether the metrics and the energy balance follow every internal step
  /// (the model at each step's midpoint and end, and where a peak between
  /// them is due; the energy at its end). A caller that reads only `samples`
  /// (identification) turns this off: the integration is the same to the
  /// last bit, and the metrics and energy residual see only the output and
  /// sample times.
  bool step_metrics = true;
  /// Whether the quadratures (damper, friction and motor work, the separation
  /// integral) are integrated: by Simpson's rule over each step, from the
  /// model at its start, midpoint and end. They never change the steps, so
  /// without them the run is the same to the last bit and spares the
  /// midpoint's evaluation where nothing else needs it; the energy residual
  /// and the separation integral are then NaN. Only a caller that reads
  /// neither (identification's fit runs) turns them off.
  bool quadratures = true;
  /// Extra times [s] (ascending, within the run) at which the state is sampled
  /// from the integrator's dense output into SimulationResult::samples (for
  /// comparing with measured data on its own time base).
  std::vector<double> sample_times;
  /// Called now and then with the fraction of simulated time done, in [0, 1].
  std::function<void(double)> progress;
  /// Start here (at t = 0) instead of in equilibrium on the law
  /// (scene.mechanism.follower.initial); null: there. (A pointer, not an
  /// optional: GCC 12's sanitizer build misreads an optional of it as
  /// maybe-uninitialised wherever options are copied.)
  std::shared_ptr<const StartState> start;
};

/// Runs the scene. When the integrator gives up, a budget (steps, wall time)
/// runs out or the contact leaves what the model describes, returns early with
/// result.solver.termination saying which and result.solver.message naming
/// the time and cam angle; the solver counters are then those reached, the
/// metrics, series and events partial. Throws InputError when the follower has
/// no static equilibrium to start from.
SimulationResult simulate(const SceneConfig& scene, const Model& model, Workspace& ws,
                          const SimulationOptions& options = {});

/// The work quadratures a run of the model integrates (summary.json
/// `model.quadratures`; docs/model.md §7): of drive_work, damper_work,
/// hysteresis_work and friction_work those the model has (the drive's work
/// where the cam turns, the damper's with a damper, the hysteresis with a
/// dissipative contact law, the friction work with friction). The others
/// are zero and left out, as unneeded states are.
std::vector<std::string> integrated_quadratures(const Model& model);

/// The boundary between the status and the exit code: throws
/// NumericalError(result.solver.message) (exit 3) unless the run converged.
void throw_if_failed(const SimulationResult& result);

/// With `integrator.error_estimate = "richardson"`, runs the scene again at a
/// tolerance 100× tighter (rk4: a step 100^(1/4)× shorter, the same factor
/// on its error) and stores the difference in result.error. Does nothing for
/// a run that failed; when the tighter run fails, the result takes its
/// termination and message.
void estimate_error(const SceneConfig& scene, const Model& model, SimulationResult& result);

/// Builds the model (throws InputError for bad geometry), runs it and
/// estimates its error; the status is in result.solver as for simulate().
SimulationResult simulate_scene(const SceneConfig& scene, const std::string& file,
                                const SimulationOptions& options = {});
/// The same on the scene's geometry, already built (dynamics/cam_geometry.h).
SimulationResult simulate_scene(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file,
                                const SimulationOptions& options = {});
/// The same on the scene's model, already built (or with its speed set in
/// place, set_cam_speed): runs it on a fresh workspace and estimates its error.
SimulationResult simulate_scene(const Model& model, const SceneConfig& scene, const SimulationOptions& options = {});

}  // namespace camdyn
