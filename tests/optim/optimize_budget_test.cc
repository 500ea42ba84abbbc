// An optimize study never concludes from a run a budget cut short
// (docs/optimize.md "Budgets"): a verification of a candidate cut short
// withholds the answer (exit 3, no verdict), and a search whose evaluations a
// budget cut says so instead of "no valid design".
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_run.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "optim/optimize/optimize.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;
using camdyn::optim::CandidateKind;
using camdyn::optim::CandidateVerification;
using camdyn::optim::OptimizeOutcome;

const std::string kForce = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_force.json";

/// The error a real simulation gives when integrator.max_steps cuts it short.
std::string step_budget_error() {
  camdyn::SceneConfig scene = camdyn::load_scene(kQuickstart);
  scene.integrator.max_steps = 20;
  camdyn::SimulationOptions options;
  options.record_series = false;
  const camdyn::SimulationResult r = camdyn::simulate_scene(scene, kQuickstart, options);
  EXPECT_EQ(r.solver.termination, camdyn::Termination::step_budget);
  return "at 1300 rpm: " + r.solver.message;
}

CandidateVerification candidate(CandidateKind kind, bool valid, const std::string& error = "") {
  CandidateVerification c;
  c.kind = kind;
  c.available = true;
  c.verified.valid = valid;
  c.verified.error = error;
  return c;
}

TEST(OptimizeBudget, AVerificationCutShortByABudgetWithholdsTheAnswer) {
  OptimizeOutcome out;
  out.selection.candidates = {candidate(CandidateKind::baseline, true),
                              candidate(CandidateKind::rigid, false, step_budget_error()),
                              candidate(CandidateKind::dynamic, true)};
  camdyn::optim::withhold_on_budget(out);
  EXPECT_EQ(out.budget_cut_evaluations, 1u);
  EXPECT_NE(out.withheld.find("1 of 3 verifications"), std::string::npos) << out.withheld;
  EXPECT_NE(out.withheld.find("integrator.max_steps"), std::string::npos) << out.withheld;
  EXPECT_EQ(out.budget_cut_names(), "integrator.max_steps");
}

TEST(OptimizeBudget, ACandidateThatIsInvalidForThePhysicsDoesNotWithholdIt) {
  OptimizeOutcome out;
  CandidateVerification missing;
  missing.kind = CandidateKind::rigid;  // not available: the rigid stage made no design
  out.selection.candidates = {candidate(CandidateKind::baseline, true), missing,
                              candidate(CandidateKind::dynamic, false, "the cam undercuts at 120 deg")};
  camdyn::optim::withhold_on_budget(out);
  EXPECT_TRUE(out.withheld.empty()) << out.withheld;
  EXPECT_EQ(out.budget_cut_evaluations, 0u);
}

// Every evaluation of the search cut short by optimizer.evaluation_max_wall_time_s:
// exit 3 saying that a budget cut them, never an answer.
TEST(OptimizeBudget, ASearchWhoseEvaluationsABudgetCutSaysSo) {
  const fs::path dir = camdyn::test::scratch_dir("optimize_budget", "search");
  const camdyn::test::Outcome o =
      camdyn::test::run_camdyn({"run", kForce, "--out", (dir / "out").string(), "--quiet", "--set",
                                "optimizer.evaluation_max_wall_time_s=1e-9", "--set", "optimizer.max_evaluations=4"},
                               dir);
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find("4 of them were cut short by a budget (integrator.max_wall_time_s)"), std::string::npos)
      << o.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "report.html"));
  EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
}

}  // namespace
