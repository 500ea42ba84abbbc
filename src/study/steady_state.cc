#include "study/steady_state.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <exception>
#include <memory>

#include "dynamics/poincare_map.h"
#include "io/json_archive.h"
#include "study/periodic_orbit.h"

namespace camdyn {

namespace {

// The largest scaled difference between two section points [-].
double scaled_distance(const PoincareMap& map, const SectionPoint& a, const SectionPoint& b) {
  double d = 0.0;
  for (std::size_t j = 0; j < a.x.size(); ++j) d = std::max(d, std::abs(a.x[j] - b.x[j]) / map.scales()[j]);
  return d;
}

bool ended_on_section(const PoincareMap& map, const SimulationResult& result) {
  const double revolutions = result.end_time / map.period();
  return std::abs(revolutions - std::round(revolutions)) < 1e-9 && !result.final_state.empty();
}

// `revolutions` revolutions from `p` with their metrics.
SimulationResult run_from(const PoincareMap& map, const SectionPoint& p, int revolutions) {
  Workspace ws = make_workspace(map.model());
  SimulationOptions run;
  run.record_series = false;
  run.start = std::make_shared<const StartState>(map.start(p));
  return simulate(map.scene_for(revolutions), map.model(), ws, run);
}

// The analysis from the run's end when it ended on the section (a whole
// number of revolutions), else from a transient of its own.
PeriodicAnalysis analyse(const PoincareMap& map, const SimulationResult& result, const PeriodicOptions& options) {
  if (ended_on_section(map, result)) return analyse_from(map, map.point(result), options);
  return analyse_steady_state(map, options);
}

// Where the run has already settled: one more revolution from its end returns
// to within the shooting's tolerance, so the run converged onto a period-1
// orbit by itself (a repelling orbit is not approached by a forward run) and
// that revolution is one period of it. Costs one revolution instead of a
// Newton search with its Jacobian.
bool settled(const PoincareMap& map, const SimulationResult& result, const PeriodicOptions& options,
             SimulationResult& revolution, SteadyStateOutcome& o) {
  if (!ended_on_section(map, result)) return false;
  const SectionPoint p = map.point(result);
  revolution = run_from(map, p, 1);
  o.revolutions = 1;
  if (!revolution.solver.converged()) return false;
  const double residual = scaled_distance(map, p, map.point(revolution));
  if (!(residual <= options.tolerance)) return false;
  o.on_orbit = true;
  o.period = 1;
  o.motion = to_string(MotionKind::periodic);
  o.note =
      "metrics over one period of the period-1 orbit the run had settled on (one more revolution returns to "
      "within " +
      format_shortest(residual) + " of its start)";
  return true;
}

PeriodicOptions options_for(SteadyStateSearch effort, int threads) {
  PeriodicOptions options;
  options.threads = threads;
  if (effort == SteadyStateSearch::evaluation) {
    options.max_period = 2;
    options.lyapunov_revolutions = 0;  // no classification: the window's metrics stay
  }
  return options;
}

// The search and the run along the orbit; the metrics replaced when it succeeds.
SteadyStateOutcome search(const SceneConfig& scene, const Model& model, SimulationResult& result,
                          SteadyStateSearch effort, int threads) {
  SteadyStateOutcome o;
  o.asked = true;
  try {
    const PoincareMap map(scene, model, "");
    const PeriodicOptions options = options_for(effort, threads);
    SimulationResult revolution;
    if (settled(map, result, options, revolution, o)) {
      result.metrics = revolution.metrics;
      result.metrics_over = "periodic_orbit";
      result.orbit_duration = revolution.end_time - revolution.evaluated_from;
      return o;
    }
    const PeriodicAnalysis a = analyse(map, result, options);
    o.motion = to_string(a.motion);
    o.revolutions += a.revolutions;
    if (!a.orbit) {
      o.note = "no stable periodic orbit up to period " + std::to_string(options.max_period) + " (" + o.motion + ")" +
               (a.unreached_orbits.empty()
                    ? ""
                    : " that the motion reaches (a stable period-" + std::to_string(a.unreached_orbits.front().period) +
                          " orbit coexists with it)") +
               ": metrics over the evaluated window";
      return o;
    }
    const SimulationResult orbit = run_from(map, a.orbit->fixed_point, a.orbit->period);
    if (!orbit.solver.converged()) {
      o.note = "the run along the orbit failed (" + orbit.solver.message + "): metrics over the evaluated window";
      return o;
    }
    result.metrics = orbit.metrics;
    result.metrics_over = "periodic_orbit";
    result.orbit_duration = orbit.end_time - orbit.evaluated_from;
    o.on_orbit = true;
    o.period = a.orbit->period;
    o.spectral_radius = a.orbit->spectral_radius();
    o.note = "metrics over one period of the stable period-" + std::to_string(o.period) + " orbit";
  } catch (const std::exception& e) {
    o.note = std::string("the steady-state search failed (") + e.what() + "): metrics over the evaluated window";
  }
  return o;
}

}  // namespace

SteadyStateOutcome apply_steady_state(const SceneConfig& scene, const Model& model, SimulationResult& result,
                                      SteadyStateSearch effort, int threads) {
  if (!scene.simulation.steady_state || !result.solver.converged()) return {};
  SteadyStateOutcome o = search(scene, model, result, effort, threads);
  result.metrics_note = o.note;
  return o;
}

}  // namespace camdyn
