// The whole study's budgets (common/study_budget.h). Wall time (`camdyn run
// --max-study-time`): past it a study stops within a moment, exits 3 naming
// the budget and where it stopped, keeps what finished in its journal (never
// a run the budget cut short, journaled as failed), and a re-run into the
// same folder finishes the study. Memory (`--max-memory`): what an input asks
// to hold is refused before it is allocated, by validate and run alike.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;

using camdyn::test::Outcome;
using camdyn::test::read_text;

/// What a stop on the budget may take beyond the budget [s] (a run checks it every step).
constexpr double kStopWithin = 5.0;
/// How much slower a sanitised build runs the studies (ASan, UBSan and the
/// fuzz preset's coverage): a budget meant to fall inside a stage after the
/// study's set-up is that much longer there.
constexpr double kBuildSlowdown = CAMDYN_SANITIZED ? 4.0 : 1.0;

/// The records of a journal (its lines after the header).
std::vector<nlohmann::json> journal_records(const fs::path& path) {
  std::istringstream lines(read_text(path));
  std::vector<nlohmann::json> records;
  std::string line;
  for (bool header = true; std::getline(lines, line); header = false)
    if (!header) records.push_back(nlohmann::json::parse(line));
  return records;
}

/// Runs `args` (after `run CONFIG`) with a budget of `budget_s` and checks the stop.
Outcome run_over_budget(const std::string& config, std::vector<std::string> args, const fs::path& dir,
                        double budget_s) {
  args.insert(args.begin(), {"run", config, "--quiet", "--out", (dir / "out").string(), "--max-study-time",
                             std::to_string(budget_s)});
  const auto start = std::chrono::steady_clock::now();
  const Outcome o = camdyn::test::run_camdyn(args, dir);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_LT(seconds, budget_s + kStopWithin);
  EXPECT_TRUE(contains(o.err, "wall-time budget of")) << o.err;
  EXPECT_TRUE(contains(o.err, "--max-study-time")) << o.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
  return o;
}

TEST(StudyBudget, ASimulateRunStopsNamingTheBudgetAndTheCamAngle) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "simulate");
  const Outcome o = run_over_budget(kStudies + "quickstart.json", {"--set", "simulation.cycles=5000"}, dir, 0.3);
  EXPECT_TRUE(contains(o.err, "cam angle")) << o.err;
}

TEST(StudyBudget, ACompareKeepsItsFinishedRunsAndARerunFinishesIt) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "compare");
  const Outcome o = run_over_budget(kStudies + "compare_laws.json", {"--jobs", "1"}, dir, 0.3);
  EXPECT_TRUE(contains(o.err, " runs of the compare study")) << o.err;
  const auto records = journal_records(dir / "out" / "journal.jsonl");
  EXPECT_LT(records.size(), 60u);
  for (const auto& r : records) EXPECT_EQ(r["status"], "ok") << r.dump();  // nothing cut short is journaled

  const Outcome again = camdyn::test::run_camdyn(
      {"run", kStudies + "compare_laws.json", "--quiet", "--out", (dir / "out").string()}, dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(contains(again.out, "0 failed")) << again.out;
  EXPECT_TRUE(fs::exists(dir / "out" / "complete.json"));
}

TEST(StudyBudget, AnOptimizeKeepsItsEvaluationsAndARerunReplaysThem) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "optimize");
  const std::vector<std::string> sets = {"--set", "optimizer.max_evaluations=120", "--set", "simulation.cycles=3",
                                         "--set", "operating_rpm=[1000]",          "--set", "rigid.enabled=false"};
  const Outcome o = run_over_budget(kStudies + "optimize_force.json", sets, dir, 0.5 * kBuildSlowdown);
  EXPECT_TRUE(contains(o.err, "evaluations of the search")) << o.err;
  const auto records = journal_records(dir / "out" / "journal.jsonl");
  for (const auto& r : records) EXPECT_TRUE(r["valid"].get<bool>()) << r.dump();  // nothing cut short

  std::vector<std::string> args = {"run", kStudies + "optimize_force.json", "--quiet", "--out", (dir / "out").string()};
  args.insert(args.end(), sets.begin(), sets.end());
  const Outcome again = camdyn::test::run_camdyn(args, dir);
  ASSERT_EQ(again.code, 0) << again.err;
  if (!records.empty()) {
    EXPECT_TRUE(contains(again.out, "replayed from the journal")) << again.out;
  }
}

TEST(StudyBudget, AnIdentifyStopsInItsStageAndARerunResumes) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "identify");
  const std::string config = kStudies + "identify_drop/identify_drop.json";
  run_over_budget(config, {}, dir, 0.15);
  const Outcome again = camdyn::test::run_camdyn({"run", config, "--quiet", "--out", (dir / "out").string()}, dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "complete.json"));
}

// `validate` refuses what `run` would: a time series beyond --max-memory is
// exit 2 naming the field, and a larger budget takes it.
TEST(StudyBudget, ValidateAndRunRefuseATimeSeriesBeyondTheMemoryBudget) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "memory");
  const std::vector<std::string> config = {kStudies + "quickstart.json", "--set", "simulation.output_step_deg=0.001"};
  for (const char* command : {"validate", "run"}) {
    std::vector<std::string> args = {command};
    args.insert(args.end(), config.begin(), config.end());
    args.insert(args.end(), {"--max-memory", "100"});
    if (std::string(command) == "run") args.insert(args.end(), {"--quiet", "--out", (dir / "out").string()});
    const Outcome o = camdyn::test::run_camdyn(args, dir);
    EXPECT_EQ(o.code, 2) << command << ": " << o.err;
    EXPECT_TRUE(contains(o.err, "simulation.output_step_deg")) << o.err;
    EXPECT_TRUE(contains(o.err, "more than the memory budget of 100 MB (--max-memory)")) << o.err;
  }
  std::vector<std::string> args = {"validate"};
  args.insert(args.end(), config.begin(), config.end());
  args.insert(args.end(), {"--max-memory", "1000"});
  EXPECT_EQ(camdyn::test::run_camdyn(args, dir).code, 0);
}

TEST(StudyBudget, ABudgetMustBePositive) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget", "positive");
  const Outcome o = camdyn::test::run_camdyn(
      {"run", kStudies + "quickstart.json", "--out", (dir / "out").string(), "--max-study-time", "0"}, dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_TRUE(contains(o.err, "--max-study-time")) << o.err;
}

// The rigid stage's linear programmes (here on a follower train's held
// response) and the layout search stop on the study's budget too (they ran
// seconds past it: probe_fields.py and run_fuzzer).
TEST(StudyBudget, AnOptimizeOnATrainStopsInItsRigidStage) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget_cli", "rigid_stage");
  const Outcome o = run_over_budget(kStudies + "valvetrain/optimize_train.json", {}, dir, 0.3);
  EXPECT_TRUE(contains(o.err, "rigid stage") || contains(o.err, "held train")) << o.err;
}

TEST(StudyBudget, ALayoutSearchStops) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget_cli", "layout");
  const Outcome o = run_over_budget(kStudies + "layout_packaging_arm.json", {}, dir, 0.2);
  EXPECT_TRUE(contains(o.err, "layout search")) << o.err;
}

// A fit of many starts stops on the study's budget too: a start the budget
// cut is not a failed start to step over (1,000 of them ran on past it).
TEST(StudyBudget, AnIdentifyOfManyStartsStops) {
  const fs::path dir = camdyn::test::scratch_dir("study_budget_cli", "identify_starts");
  run_over_budget(kStudies + "identify_drop/identify_drop.json", {"--set", "solver.starts=1000"}, dir, 1.0);
}

}  // namespace
