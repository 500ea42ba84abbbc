// A convergence study whose reference run fails (study/convergence.h): the
// reference is retried with a larger step budget, and when it still fails the
// study writes every run that finished, says the reference is missing, and
// exits 3 (issue: it aborted and lost every finished run).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli_run.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

// One cvode_bdf run at rtol 1e-3 (about 900 steps) against a reference at
// rtol 1e-12, under a step budget of `max_steps`.
test::Outcome run_with_budget(const fs::path& dir, long max_steps) {
  return test::run_camdyn(
      {"run", kQuickstart, "--out", (dir / "out").string(), "--quiet", "--set", "study=convergence", "--set",
       R"(methods=["cvode_bdf"])", "--set", "tolerances=[1e-3]", "--set", R"(tracking=["differential"])", "--set",
       R"(reference={"method": "cvode_bdf", "rtol": 1e-12})", "--set",
       R"(simulation={"cycles": 2, "discard_cycles": 1})", "--set",
       "integrator.max_steps=" + std::to_string(max_steps)},
      dir);
}

TEST(ConvergenceReference, AReferenceOverItsStepBudgetIsRetriedWithALargerOne) {
  const fs::path dir = test::scratch_dir("convergence_reference_test", "retried");
  const test::Outcome r = run_with_budget(dir, 3000);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = test::read_text(dir / "out" / "work_precision.csv");
  EXPECT_NE(csv.find(",ok,"), std::string::npos) << csv;
}

TEST(ConvergenceReference, AMissingReferenceKeepsTheFinishedRunsAndExitsThree) {
  const fs::path dir = test::scratch_dir("convergence_reference_test", "missing");
  const test::Outcome r = run_with_budget(dir, 1000);
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("the reference run of scene 'base' failed"), std::string::npos) << r.err;
  const std::string csv = test::read_text(dir / "out" / "work_precision.csv");
  EXPECT_NE(csv.find("no reference to measure against"), std::string::npos) << csv;
  EXPECT_EQ(csv.find(",0,0,failed"), std::string::npos) << "the finished run keeps its counters: " << csv;
  const std::string html = test::read_text(dir / "out" / "report.html");
  EXPECT_NE(html.find("reference run of scene &#39;base&#39; missing"), std::string::npos);
}

// A scene set to arkode_erk at order 8 (integrator.order): the study's other
// methods run at their own default order (issue 38: the DIRK run inherited
// the order 8 it does not offer and failed).
TEST(ConvergenceReference, TheScenesOrderStaysWithItsMethod) {
  const fs::path dir = test::scratch_dir("convergence_reference_test", "order");
  const test::Outcome r = test::run_camdyn({"run",
                                            kQuickstart,
                                            "--out",
                                            (dir / "out").string(),
                                            "--quiet",
                                            "--set",
                                            "study=convergence",
                                            "--set",
                                            R"(methods=["arkode_erk", "arkode_dirk"])",
                                            "--set",
                                            "tolerances=[1e-4]",
                                            "--set",
                                            R"(tracking=["differential"])",
                                            "--set",
                                            R"(reference={"method": "cvode_bdf", "rtol": 1e-10})",
                                            "--set",
                                            R"(simulation={"cycles": 2, "discard_cycles": 1})",
                                            "--set",
                                            "integrator.method=arkode_erk",
                                            "--set",
                                            "integrator.order=8"},
                                           dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = test::read_text(dir / "out" / "work_precision.csv");
  EXPECT_EQ(csv.find("failed"), std::string::npos) << csv;
  EXPECT_NE(csv.find("arkode_dirk"), std::string::npos) << csv;
}

}  // namespace
}  // namespace camdyn
