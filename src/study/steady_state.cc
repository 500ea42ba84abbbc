#include "study/steady_state.h"

#include <cmath>
#include <exception>
#include <memory>

#include "dynamics/poincare_map.h"
#include "study/periodic_orbit.h"

namespace camdyn {

namespace {

// The analysis from the run's end when it ended on the section (a whole
// number of revolutions), else from a transient of its own.
PeriodicAnalysis analyse(const PoincareMap& map, const SimulationResult& result, const PeriodicOptions& options) {
  const double revolutions = result.end_time / map.period();
  if (std::abs(revolutions - std::round(revolutions)) < 1e-9 && !result.final_state.empty())
    return analyse_from(map, map.point(result), options);
  return analyse_steady_state(map, options);
}

// The search and the run along the orbit; the metrics replaced when it succeeds.
SteadyStateOutcome search(const SceneConfig& scene, const Model& model, SimulationResult& result, int threads) {
  SteadyStateOutcome o;
  o.asked = true;
  try {
    const PoincareMap map(scene, model, "");
    PeriodicOptions options;
    options.threads = threads;
    const PeriodicAnalysis a = analyse(map, result, options);
    o.motion = to_string(a.motion);
    o.revolutions = a.revolutions;
    if (!a.orbit) {
      o.note = "no stable periodic orbit up to period " + std::to_string(options.max_period) + " (" + o.motion +
               "): metrics over the evaluated window";
      return o;
    }
    Workspace ws = make_workspace(model);
    SimulationOptions run;
    run.record_series = false;
    run.start = std::make_shared<const StartState>(map.start(a.orbit->fixed_point));
    const SimulationResult orbit = simulate(map.scene_for(a.orbit->period), model, ws, run);
    if (!orbit.solver.converged()) {
      o.note = "the run along the orbit failed (" + orbit.solver.message + "): metrics over the evaluated window";
      return o;
    }
    result.metrics = orbit.metrics;
    result.metrics_over = "periodic_orbit";
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
                                      int threads) {
  if (!scene.simulation.steady_state || !result.solver.converged()) return {};
  SteadyStateOutcome o = search(scene, model, result, threads);
  result.metrics_note = o.note;
  return o;
}

}  // namespace camdyn
