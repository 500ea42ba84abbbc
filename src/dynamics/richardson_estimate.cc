#include <algorithm>
#include <cmath>

#include "dynamics/simulation.h"

namespace camdyn {

void estimate_error(const SceneConfig& scene, const Model& model, SimulationResult& result) {
  if (scene.integrator.error_estimate != ErrorEstimateMethod::richardson || !result.solver.converged()) return;
  SceneConfig tight = scene;
  if (scene.integrator.method == IntegrationMethod::rk4) {
    tight.integrator.step = scene.integrator.step.value_or(0.0) / std::pow(100.0, 0.25);
  } else {
    tight.integrator.rtol = scene.integrator.rtol / 100.0;
    tight.integrator.atol = scene.integrator.atol / 100.0;
  }
  Workspace ws;
  const SimulationResult reference = simulate(tight, model, ws);
  if (!reference.solver.converged()) {
    result.solver.termination = reference.solver.termination;
    result.solver.message = reference.solver.message;
    return;
  }
  ErrorEstimate& e = result.error;
  e.richardson = true;
  e.position = 0.0;
  const TimeSeries& a = result.series;
  const TimeSeries& b = reference.series;
  for (size_t i = 0; i < std::min(a.time.size(), b.time.size()); ++i)
    if (a.time[i] >= result.evaluated_from)
      e.position = std::max(e.position, std::abs(a.follower_position[i] - b.follower_position[i]));
  const double f_ref = reference.metrics.peak_contact_force;
  e.peak_contact_force = f_ref > 0.0 ? std::abs(result.metrics.peak_contact_force / f_ref - 1.0) : 0.0;
  e.tight_run_time_s = reference.solver.run_time_s;
}

}  // namespace camdyn
