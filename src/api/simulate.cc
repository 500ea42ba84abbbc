#include <camdyn/simulate.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>

#include "api/argument_checks.h"
#include "api/scene_impl.h"
#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/metrics.h"
#include "dynamics/run_plan.h"
#include "dynamics/series_columns.h"
#include "dynamics/simulation.h"
#include "study/steady_state.h"

namespace camdyn {

namespace {

TerminationStatus public_status(Termination termination) {
  switch (termination) {
    case Termination::converged:
      return TerminationStatus::converged;
    case Termination::integrator_failure:
      return TerminationStatus::integrator_failure;
    case Termination::step_budget:
      return TerminationStatus::step_budget;
    case Termination::wall_time_budget:
      return TerminationStatus::wall_time_budget;
    case Termination::penetration_limit:
      return TerminationStatus::penetration_limit;
    case Termination::left_flat_face:
      return TerminationStatus::left_flat_face;
    case Termination::tracking_lost:
      return TerminationStatus::tracking_lost;
    case Termination::no_initial_contact:
      return TerminationStatus::no_initial_contact;
  }
  throw std::logic_error("unknown termination");
}

RunSummary public_summary(const SolverSummary& s, const ErrorEstimate& error) {
  RunSummary r;
  r.termination = public_status(s.termination);
  r.message = s.message;
  r.method = s.method;
  r.rtol = s.rtol;
  r.atol = s.atol;
  r.steps = s.counters.steps;
  r.rhs_evaluations = s.counters.rhs_evaluations;
  r.error_test_failures = s.counters.error_test_failures;
  r.nonlinear_iterations = s.counters.nonlinear_iterations;
  r.jacobian_evaluations = s.counters.jacobian_evaluations;
  r.reinitialisations = s.counters.reinitialisations;
  r.events = s.events;
  r.tracking_resets = s.tracking_resets;
  r.projections = s.projections;
  r.run_time_s = s.run_time_s;
  r.error_estimated = error.richardson;
  r.error_position = error.position;
  r.error_peak_contact_force = error.peak_contact_force;
  return r;
}

Columns public_columns(const TimeSeries& series, bool oscillating) {
  Columns columns;
  columns.names = series.all_names();
  for (const std::string& name : columns.names) columns.units.push_back(series_column_unit(name, oscillating));
  for (const std::vector<double>* column : series.all_columns()) columns.values.push_back(*column);
  return columns;
}

std::map<std::string, double> public_metrics(const Metrics& metrics) {
  std::map<std::string, double> named;
  for_each_metric(metrics, [&](const char* name, const auto& value, const MetricInfo&) {
    if (const std::optional<double> v = metric_value(value)) named[name] = *v;  // absent where it does not apply
  });
  if (metrics.train) {
    const TrainMetrics& t = *metrics.train;
    for_each_train_metric(t, [&](const char* name, double value, bool, const char*) { named[name] = value; });
    for (std::size_t i = 0; i < t.bodies.size(); ++i) named["max_lift_error:" + t.bodies[i]] = t.max_lift_error[i];
  }
  return named;
}

Result public_result(SimulationResult&& run, bool oscillating) {
  Result result;
  result.metrics = public_metrics(run.metrics);
  result.solver = public_summary(run.solver, run.error);
  result.series = public_columns(run.series, oscillating);
  result.samples = public_columns(run.samples, oscillating);
  result.events.reserve(run.events.size());
  for (const ContactEvent& e : run.events)
    result.events.push_back(
        {e.time, e.cam_angle_deg, e.onset, e.speed, e.impact, e.grazing, e.lash, std::string(enum_name(e.cause))});
  result.metrics_over = run.metrics_over;
  result.steady_state = run.metrics_note;
  result.evaluated_from = run.evaluated_from;
  result.end_time = run.end_time;
  return result;
}

}  // namespace

const char* termination_name(TerminationStatus status) {
  switch (status) {
    case TerminationStatus::converged:
      return "converged";
    case TerminationStatus::integrator_failure:
      return "integrator_failure";
    case TerminationStatus::step_budget:
      return "step_budget";
    case TerminationStatus::wall_time_budget:
      return "wall_time_budget";
    case TerminationStatus::penetration_limit:
      return "penetration_limit";
    case TerminationStatus::left_flat_face:
      return "left_flat_face";
    case TerminationStatus::tracking_lost:
      return "tracking_lost";
    case TerminationStatus::no_initial_contact:
      return "no_initial_contact";
  }
  return "unknown";
}

const std::vector<double>& Columns::operator[](std::string_view name) const {
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) {
    if (names[i] == name) return values[i];
  }
  throw std::out_of_range("camdyn::Columns: no column '" + std::string(name) + "'");
}

// What simulate_scene (dynamics/simulation.h) does, on the model the scene
// built when it was loaded: the same run, to the bit; then, as `camdyn run`,
// the steady state's metrics when the scene asks for them. The options are
// checked first, naming no file: they are arguments, not the config's.
Result simulate(const Scene& scene, const SimulateOptions& options) {
  const Scene::Impl& impl = *scene.impl_;
  check_jobs("jobs", options.jobs);
  check_times_within_run("sample_times", options.sample_times, plan_run(impl.scene, impl.model).t_end);
  SimulationOptions run_options;
  run_options.record_series = options.record_series;
  run_options.sample_times = options.sample_times;
  run_options.progress = options.progress;
  SimulationResult run = naming_file(impl.file, [&] {
    Workspace ws;
    SimulationResult r = simulate(impl.scene, impl.model, ws, run_options);
    estimate_error(impl.scene, impl.model, r);
    const int threads =
        options.jobs > 0 ? options.jobs : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
    // only with simulation.steady_state and a converged run
    apply_steady_state(impl.scene, impl.model, r, SteadyStateSearch::full, threads);
    return r;
  });
  return public_result(std::move(run), impl.model.follower.oscillating());
}

struct InterruptCheck::Impl {
  explicit Impl(std::function<bool()> interrupted) : scope(std::move(interrupted)) {}
  InterruptScope scope;  // common/study_budget.h
};

InterruptCheck::InterruptCheck(std::function<bool()> interrupted)
    : impl_(std::make_unique<Impl>(std::move(interrupted))) {}

InterruptCheck::~InterruptCheck() = default;

void throw_if_failed(const Result& result) {
  if (!result.solver.converged()) throw NumericalError(result.solver.message);
}

std::string column_unit(std::string_view name, bool oscillating) { return series_column_unit(name, oscillating); }

std::vector<std::pair<std::string, std::string>> series_column_units() {
  std::vector<std::pair<std::string, std::string>> units;
  for (const SeriesColumn& c : kSeriesColumns) units.emplace_back(c.name, c.unit);
  return units;
}

std::vector<std::pair<std::string, std::string>> train_column_units() {
  std::vector<std::pair<std::string, std::string>> units;
  for (const TrainColumnSuffix& c : kTrainColumns) units.emplace_back(c.suffix, c.unit);
  return units;
}

}  // namespace camdyn
