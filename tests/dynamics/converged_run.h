// A scene simulated with a model built for it, the run expected to converge
// (a failure names the solver's message): the tests that check a run's
// outputs against a closed form start from it.
#pragma once

#include <gtest/gtest.h>

#include "dynamics/model.h"
#include "dynamics/simulation.h"

namespace camdyn::test {

inline SimulationResult converged_run(const SceneConfig& scene) {
  const Model model = build_model(scene, "test");
  Workspace ws = make_workspace(model);
  SimulationResult r = simulate(scene, model, ws);
  EXPECT_TRUE(r.solver.converged()) << r.solver.message;
  return r;
}

}  // namespace camdyn::test
