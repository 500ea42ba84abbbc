// `simulation.steady_state`: the metrics of a run over one period of the
// periodic orbit it settles on, instead of over its evaluated window. The
// orbit is found by the periodic study's shooting (study/periodic_orbit.h),
// started from the run's end; when no stable orbit converges (chaotic or
// slowly settling motion, or a drive that does not set the speed) the
// window's metrics stay and the run says why. simulate, compare runs and
// optimize evaluations all go through here.
#pragma once

#include <string>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "scene/scene.h"

namespace camdyn {

/// What a run's metrics are over (summary.json `metrics_over`, `steady_state`).
struct SteadyStateOutcome {
  bool asked = false;     ///< simulation.steady_state was set
  bool on_orbit = false;  ///< the metrics are over one period of a stable orbit
  int period = 0;         ///< of that orbit [revolutions]
  double spectral_radius = 0.0;
  std::string motion;    ///< periodic, chaotic, quasi_periodic, unresolved (empty when not asked)
  std::string note;      ///< one sentence: the orbit, or why the window's metrics stay
  long revolutions = 0;  ///< integrated for the search
};

/// How much one search may cost. `full` (simulate, compare runs) tries
/// periods up to 8 and classifies a motion without a stable orbit by its
/// Lyapunov exponent; `evaluation` (optimize, which searches hundreds of
/// times) tries periods 1 and 2 and leaves an unresolved motion on the
/// window's metrics without classifying it. Either is deterministic.
enum class SteadyStateSearch { full, evaluation };

/// With scene.simulation.steady_state and a converged `result`, replaces
/// result.metrics by those over one period of the stable orbit when one is
/// found; otherwise leaves them. A run that has already settled (one more
/// revolution returns to its end within the tolerance) needs no search. Never throws for the search itself (a failed
/// search leaves the window's metrics and says so); `threads` for the
/// Jacobian columns.
SteadyStateOutcome apply_steady_state(const SceneConfig& scene, const Model& model, SimulationResult& result,
                                      SteadyStateSearch effort = SteadyStateSearch::full, int threads = 1);

}  // namespace camdyn
