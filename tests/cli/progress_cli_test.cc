// The progress lines of optimise and identify (stderr, on a terminal only):
// what each line must say. A terminal is provided by util-linux `script`,
// which runs the command on a pseudo-terminal and copies what it prints.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_run.h"

namespace {

namespace fs = std::filesystem;

using camdyn::test::Outcome;

const std::string kStudies = std::string(CAMDYN_SOURCE_DIR) + "/studies";

/// Runs `camdyn ARGS` on a pseudo-terminal; stdout and stderr come back
/// together in `out`, with the carriage returns of the redrawn lines.
Outcome run_on_terminal(const std::string& args, const fs::path& dir) {
  return camdyn::test::run_process({"script", "-qec", std::string(CAMDYN_BINARY) + " " + args, "/dev/null"}, dir,
                                   "tty");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ProgressCli, OptimiseShowsEvaluationOfMaxBestObjectiveAndTimeLeft) {
  if (!camdyn::test::on_path("script")) GTEST_SKIP() << "util-linux script is not installed";
  const fs::path dir = camdyn::test::scratch_dir("progress_cli", "optimise");
  const std::string args = "run " + kStudies + "/optimize_jump.json --out " + (dir / "out").string() +
                           " --set optimizer.max_evaluations=3 --set optimizer.evaluation_cycles=2";
  const Outcome o = run_on_terminal(args, dir);
  ASSERT_EQ(o.code, 0) << o.out;
  EXPECT_TRUE(has(o.out, "optimize: evaluation 1 of 3, best objective ")) << o.out;
  EXPECT_TRUE(has(o.out, "(feasible)")) << o.out;
  EXPECT_TRUE(has(o.out, " left at most")) << o.out;  // the time left while evaluations remain
  EXPECT_TRUE(has(o.out, "optimize: evaluation 3 of 3, best objective ")) << o.out;  // the last always shows
  EXPECT_TRUE(has(o.out, "/s, done")) << o.out;

  // Not a terminal: no progress at all.
  const Outcome piped = camdyn::test::run_camdyn(camdyn::test::split_args(args), dir, "piped");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_FALSE(has(piped.err, "evaluation 1 of")) << piped.err;
}

TEST(ProgressCli, IdentifyNamesItsContinuationStageAndIteration) {
  if (!camdyn::test::on_path("script")) GTEST_SKIP() << "util-linux script is not installed";
  const fs::path dir = camdyn::test::scratch_dir("progress_cli", "identify");
  // Two smoothed stages (2 ms, 0.5 ms) then the raw signals; one iteration each keeps it short.
  const std::string args = "run " + kStudies + "/identify_cam_rig/identify_cam_rig.json --out " +
                           (dir / "out").string() + " --set solver.max_iterations=1";
  const Outcome o = run_on_terminal(args, dir);
  ASSERT_EQ(o.code, 0) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 1/3 (smoothed over 2 ms), iteration 0 of at most 1, cost ")) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 2/3 (smoothed over 0.5 ms), iteration 0 of at most 1, cost ")) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 3/3 (raw signals), iteration 0 of at most 1, cost ")) << o.out;

  const Outcome piped = camdyn::test::run_camdyn(camdyn::test::split_args(args), dir, "piped");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_FALSE(has(piped.err, "identify: stage")) << piped.err;
}

}  // namespace
