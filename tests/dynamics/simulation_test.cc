// How simulate() ends: a run that gives up returns its termination status
// and message instead of throwing, and throw_if_failed turns that status into
// the NumericalError (exit 3) the callers raised before.
#include "dynamics/simulation.h"

#include <gtest/gtest.h>
#include <regex.h>  // POSIX: std::regex trips a false -Wmaybe-uninitialized in GCC 12 sanitizer builds

#include <string>

#include "common/errors.h"
#include "scenes.h"

namespace camdyn {
namespace {

// The text the budget checks have always thrown: "... exceeded at t = T s, cam angle A deg".
const std::string kWhere = R"( at t = [-+0-9.e]+ s, cam angle [-+0-9.e]+ deg$)";

// The test cam with its integrator config changed by `change`, run; a throw fails the test.
template <class F>
SimulationResult run_with(F change) {
  SceneConfig scene = test::cycloidal_cam_scene(700.0);
  change(scene.integrator);
  const Model model = build_model(scene, "test");
  Workspace ws;
  SimulationResult r;
  EXPECT_NO_THROW(r = simulate(scene, model, ws));
  return r;
}

// The message throw_if_failed throws for `result`, or "" when it does not throw.
std::string thrown_message(const SimulationResult& result) {
  try {
    throw_if_failed(result);
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "";
}

/// Whether `text` contains a match of the POSIX extended regular expression `pattern`.
bool contains_match(const std::string& text, const std::string& pattern) {
  regex_t re;
  if (regcomp(&re, pattern.c_str(), REG_EXTENDED | REG_NOSUB) != 0) {
    ADD_FAILURE() << "bad pattern " << pattern;
    return false;
  }
  const bool found = regexec(&re, text.c_str(), 0, nullptr, 0) == 0;
  regfree(&re);
  return found;
}

// `r` ended with `termination` and a message matching `pattern`, which
// throw_if_failed throws as it is.
void expect_failure(const SimulationResult& r, Termination termination, const std::string& pattern) {
  EXPECT_EQ(r.solver.termination, termination) << to_string(r.solver.termination);
  EXPECT_FALSE(r.solver.converged());
  EXPECT_TRUE(contains_match(r.solver.message, pattern)) << r.solver.message;
  EXPECT_EQ(thrown_message(r), r.solver.message);
}

TEST(SimulationTermination, CompleteRunConvergesWithEmptyMessage) {
  const SimulationResult r = run_with([](IntegratorConfig&) {});
  EXPECT_EQ(r.solver.termination, Termination::converged);
  EXPECT_TRUE(r.solver.converged());
  EXPECT_EQ(r.solver.message, "");
  EXPECT_EQ(to_string(r.solver.termination), "converged");
  EXPECT_NO_THROW(throw_if_failed(r));
}

TEST(SimulationTermination, StepBudgetReturnsStatusAndThrowIfFailedThrowsItsMessage) {
  const SimulationResult r = run_with([](IntegratorConfig& ic) { ic.max_steps = 20; });
  expect_failure(r, Termination::step_budget,
                 R"(^step budget of 20 steps \(integrator\.max_steps\) exceeded)" + kWhere);
  EXPECT_EQ(to_string(r.solver.termination), "step_budget");
  EXPECT_EQ(r.solver.counters.steps, 21);  // the check runs after every step: stopped at the first one over
}

TEST(SimulationTermination, WallTimeBudgetReturnsStatus) {
  const SimulationResult r = run_with([](IntegratorConfig& ic) { ic.max_wall_time_s = 0.0; });
  expect_failure(r, Termination::wall_time_budget,
                 R"(^wall-time budget of 0\.000000 s \(integrator\.max_wall_time_s\) exceeded)" + kWhere);
}

TEST(SimulationTermination, IntegratorThatGivesUpIsAnIntegratorFailureNamingTimeAndAngle) {
  const SimulationResult r = run_with([](IntegratorConfig& ic) {
    ic.rtol = 1e-40;  // below round-off: CVODES refuses the first step
    ic.atol = 1e-60;
  });
  expect_failure(
      r, Termination::integrator_failure,
      R"(^CVODES CVode failed \(CV_TOO_MUCH_ACC\) .* \(integrating at t = 0 s, cam angle [-+0-9.e]+ deg\)$)");
}

TEST(SimulationTermination, IntegratorThatCannotStartIsAnIntegratorFailure) {
  const SimulationResult r = run_with([](IntegratorConfig& ic) { ic.rtol = -1.0; });
  // Set-up failures keep SUNDIALS' text as it is (no "integrating at").
  expect_failure(r, Termination::integrator_failure, R"(^CVODES CVodeSStolerances failed \(CV_ILL_INPUT\)[^(]*$)");
}

TEST(SimulationTermination, SimulateSceneSkipsTheErrorEstimateOfAFailedRun) {
  SceneConfig scene = test::cycloidal_cam_scene(700.0);
  scene.integrator.max_steps = 20;
  scene.integrator.error_estimate = ErrorEstimateMethod::richardson;
  const SimulationResult r = simulate_scene(scene, "test");
  EXPECT_EQ(r.solver.termination, Termination::step_budget);
  EXPECT_FALSE(r.error.richardson);
}

}  // namespace
}  // namespace camdyn
