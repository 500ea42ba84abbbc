// How a run starts (docs/model.md §6): on the law at quasi-static
// equilibrium, or from a given state (SimulationOptions::start). Internal to
// dynamics/: simulation.h is the interface.
#pragma once

#include "dynamics/run_plan.h"
#include "dynamics/simulation.h"

namespace camdyn {

/// Initial state: given by the scene, or on the law at quasi-static
/// equilibrium (the contact force supplies exactly the law's acceleration);
/// the pair by Newton from the cam angle (global search if that fails); a
/// roller spinning without slip; a shaft twisted to carry the initial cam
/// torque. Writes model.layout.size values to y.
RunFailure initial_state(const SceneConfig& scene, const Model& model, Workspace& ws, double* y);

/// A given start: every state as given except the pair parameters, which
/// warm-started Newton (global search if that fails) finds from the others
/// at t = 0, as the drift projection does.
RunFailure given_state(const Model& model, Workspace& ws, const StartState& start, double* y);

}  // namespace camdyn
