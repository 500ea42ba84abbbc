// summary.json of a simulate run: the metrics in the order Metrics' visit
// lists them, and the solver block with its termination status and message
// after the counters that were there before.
#include "study/simulation_output.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "../dynamics/scenes.h"
#include "dynamics/simulation.h"

namespace camdyn {
namespace {

std::vector<std::string> keys(const Json& object) {
  std::vector<std::string> out;
  for (const auto& item : object.items()) out.push_back(item.key());
  return out;
}

struct SceneRun {
  SceneConfig scene;
  Model model;
  SimulationResult result;
  explicit SceneRun(SceneConfig s) : scene(std::move(s)), model(build_model(scene, "test")) {
    Workspace ws;
    result = simulate(scene, model, ws);
  }
};

TEST(SimulationOutput, SummaryListsEveryMetricOnceInVisitOrder) {
  const SceneRun run(test::cycloidal_cam_scene(700.0));
  const Json summary = summary_json(run.scene, run.model, run.result);
  EXPECT_EQ(keys(summary["metrics"]), metric_names());
  EXPECT_TRUE(summary["metrics"]["impact_count"].is_number_integer());
  EXPECT_EQ(summary["metrics"]["peak_contact_force"].get<double>(), run.result.metrics.peak_contact_force);
}

TEST(SimulationOutput, SolverBlockEndsWithTerminationAndMessage) {
  const SceneRun run(test::cycloidal_cam_scene(700.0));
  const Json solver = summary_json(run.scene, run.model, run.result)["solver"];
  const std::vector<std::string> expected = {"method",
                                             "rtol",
                                             "atol",
                                             "steps",
                                             "rhs_evaluations",
                                             "events",
                                             "tracking_resets",
                                             "run_time_s",
                                             "error_estimate",
                                             "error_test_failures",
                                             "nonlinear_iterations",
                                             "jacobian_evaluations",
                                             "restarts",
                                             "tracking_projections",
                                             "tracking",
                                             "simulated_time_s",
                                             "evaluated_from_s",
                                             "termination",
                                             "message"};
  EXPECT_EQ(keys(solver), expected);
  EXPECT_EQ(solver["termination"], "converged");
  EXPECT_EQ(solver["message"], "");
}

TEST(SimulationOutput, FailedRunNamesItsTerminationInTheSummary) {
  SceneConfig scene = test::cycloidal_cam_scene(700.0);
  scene.integrator.max_steps = 20;
  const SceneRun run(scene);
  const Json solver = summary_json(run.scene, run.model, run.result)["solver"];
  EXPECT_EQ(solver["termination"], "step_budget");
  EXPECT_EQ(solver["message"], run.result.solver.message);
}

}  // namespace
}  // namespace camdyn
