// Shared by the simulation loop's pieces (docs/model.md §6): the state and
// quadratures a run holds, why a run stopped, where on the cam it was, and
// the run's plan (its end, the evaluated window, the output grid and the
// longest step). Internal to dynamics/: simulation.h is the interface.
#pragma once

#include <array>
#include <string>

#include "dynamics/simulation.h"
#include "integrate/integrator.h"
#include "scene/scene.h"

namespace camdyn {

/// A run's state vector, room for the largest model [StateLayout].
using RunState = std::array<double, StateLayout::kMax>;
/// A run's quadratures (docs/model.md §7), by index [J, J, J, J, m s].
using RunQuadratures = std::array<double, Model::kQuadratures>;

/// Why a run stopped before its end time; converged while it did not.
struct RunFailure {
  Termination termination = Termination::converged;
  std::string message;
  explicit operator bool() const { return termination != Termination::converged; }
};

/// "at t = … s, cam angle … deg": where a message happened.
std::string where(const Model& model, double t);

/// The quadratures' integrand at an evaluation [W, W, W, W, m].
RunQuadratures quadrature_integrand(const Evaluation& ev);

/// A run's times [s].
struct RunPlan {
  double t_end = 0.0, t_eval = 0.0, output_dt = 0.0, max_step = 0.0;
};

/// The plan of a scene's run on a model: the end time, the evaluated
/// window's start, the output step and the longest integrator step.
RunPlan plan_run(const SceneConfig& scene, const Model& model);

/// The integrator's options from the config and the plan.
IntegratorOptions integrator_options(const IntegratorConfig& ic, const RunPlan& p);

}  // namespace camdyn
