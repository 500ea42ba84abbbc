// The progress lines of optimise and identify (stderr, on a terminal only):
// what each line must say. A terminal is provided by util-linux `script`,
// which runs the command on a pseudo-terminal and copies what it prints.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "required_tool.h"
#include "study_paths.h"

namespace {

/// Whether `line` shows a time left as the progress line writes it, rounded,
/// followed by `tail`: "~01:15 left", "~1:02:03 left at most". (By hand:
/// <regex> under GCC 12's sanitizers warns, an error there.)
bool has_time_left(const std::string& line, const std::string& tail) {
  auto digits = [&](std::size_t at, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k)
      if (at + k >= line.size() || std::isdigit(static_cast<unsigned char>(line[at + k])) == 0) return false;
    return true;
  };
  for (std::size_t at = line.find('~'); at != std::string::npos; at = line.find('~', at + 1)) {
    std::size_t p = at + 1;
    if (!digits(p, 1)) continue;
    while (digits(p, 1)) ++p;
    if (p >= line.size() || line[p] != ':' || !digits(p + 1, 2)) continue;
    p += 3;
    if (p < line.size() && line[p] == ':' && digits(p + 1, 2)) p += 3;
    if (line.compare(p, tail.size(), tail) == 0) return true;
  }
  return false;
}

namespace fs = std::filesystem;

using camdyn::test::Outcome;

/// Runs `camdyn ARGS` on a pseudo-terminal; stdout and stderr come back
/// together in `out`, with the carriage returns of the redrawn lines.
Outcome run_on_terminal(const std::string& args, const fs::path& dir) {
  return camdyn::test::run_process({"script", "-qec", std::string(CAMDYN_BINARY) + " " + args, "/dev/null"}, dir,
                                   "tty");
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ProgressCli, OptimiseShowsEvaluationOfMaxBestObjectiveAndTimeLeft) {
  REQUIRE_TOOL(camdyn::test::on_path("script"), "util-linux's script");
  const fs::path dir = camdyn::test::scratch_dir("progress_cli", "optimise");
  const std::string args = "run " + kStudiesDir + "/optimize_jump.json --out " + (dir / "out").string() +
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
  REQUIRE_TOOL(camdyn::test::on_path("script"), "util-linux's script");
  const fs::path dir = camdyn::test::scratch_dir("progress_cli", "identify");
  // Two smoothed stages (2 ms, 0.5 ms) then the raw signals; one iteration each keeps it short.
  const std::string args = "run " + kStudiesDir + "/identify_cam_rig/identify_cam_rig.json --out " +
                           (dir / "out").string() + " --set solver.max_iterations=1";
  const Outcome o = run_on_terminal(args, dir);
  ASSERT_EQ(o.code, 0) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 1/3 (smoothed over 2 ms), iteration 0 of at most 1, cost ")) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 2/3 (smoothed over 0.5 ms), iteration 0 of at most 1, cost ")) << o.out;
  EXPECT_TRUE(has(o.out, "identify: stage 3/3 (raw signals), iteration 0 of at most 1, cost ")) << o.out;
  // Past the first iteration, the time left if every stage takes all its iterations.
  EXPECT_TRUE(has(o.out, "iteration 0 of at most 1, cost ")) << o.out;
  bool stage_with_time = false;  // "identify: stage 2/3 ..., ~mm:ss left at most"
  for (std::size_t at = 0; (at = o.out.find("identify: stage ", at)) != std::string::npos; ++at) {
    const std::string line = o.out.substr(at, o.out.find_first_of("\r\n", at) - at);
    const char stage = line.size() > 16 ? line[16] : ' ';
    stage_with_time = stage_with_time || ((stage == '2' || stage == '3') && line.compare(17, 3, "/3 ") == 0 &&
                                          has_time_left(line, " left at most"));
  }
  EXPECT_TRUE(stage_with_time) << o.out;

  const Outcome piped = camdyn::test::run_camdyn(camdyn::test::split_args(args), dir, "piped");
  ASSERT_EQ(piped.code, 0) << piped.err;
  EXPECT_FALSE(has(piped.err, "identify: stage")) << piped.err;
}

// The progress of `study` while runs remain: "<study>: k/n runs, ... ~mm:ss left",
// then its last line, "done".
void expect_runs_with_time_left(const std::string& study, const std::string& out) {
  bool with_time = false;
  const std::string prefix = study + ": ";
  for (std::size_t at = out.find(prefix); at != std::string::npos; at = out.find(prefix, at + 1)) {
    const std::string line = out.substr(at, out.find_first_of("\r\n", at) - at);
    if (line.find(" runs, ") == std::string::npos) continue;
    with_time = with_time || has_time_left(line, " left");
  }
  EXPECT_TRUE(with_time) << study << ": no time left shown\n" << out;
  EXPECT_TRUE(has(out, " elapsed, done")) << out;
}

// Every study that runs more than one simulation shows the time left,
// estimated from the work finished: the scan and bisection of speed_limit,
// the references and runs of convergence, the runs of compare, the speed
// ranges of a jump map (docs/config.md, "Commands").
TEST(ProgressCli, EveryMultiRunStudyShowsTheTimeLeft) {
  REQUIRE_TOOL(camdyn::test::on_path("script"), "util-linux's script");
  const fs::path dir = camdyn::test::scratch_dir("progress_cli", "multi_run");
  const std::string quickstart = kStudiesDir + "/quickstart.json";
  {
    std::ofstream(dir / "convergence.json") << R"({
      "extends": ")" << quickstart << R"(", "name": "convergence", "study": "convergence",
      "simulation": { "cycles": 2, "discard_cycles": 1 },
      "methods": ["cvode_bdf"], "tolerances": [1e-5, 1e-6], "reference": { "method": "cvode_bdf", "rtol": 1e-8 } })";
    std::ofstream(dir / "compare.json") << R"({
      "extends": ")" << quickstart << R"(", "name": "compare", "study": "compare",
      "simulation": { "cycles": 2, "discard_cycles": 1 }, "grid": { "mechanism.cam.rpm": [1000, 1100, 1200] } })";
  }
  const struct {
    std::string study, args;
  } runs[] = {
      {"speed_limit", quickstart + " --set study=speed_limit --set simulation.cycles=2 --set " +
                          R"('speed_limit={"low_rpm": 1000, "high_rpm": 1300, "scan": 3, "tolerance_rpm": 50}')"},
      {"convergence", (dir / "convergence.json").string()},
      {"compare", (dir / "compare.json").string()},
      {"jump_map", quickstart + " --set study=jump_map --set " +
                       R"('jump_map={"low_rpm": 1000, "high_rpm": 1300, "speeds": 4, "ranges": 2, )" +
                       R"("transient_revolutions": 5, "samples": 5}' --set 'periodic={"max_period": 1, )" +
                       R"("lyapunov_revolutions": 10}')"},
  };
  for (const auto& run : runs) {
    const Outcome o = run_on_terminal("run " + run.args + " --out " + (dir / run.study).string(), dir);
    ASSERT_EQ(o.code, 0) << run.study << "\n" << o.out;
    expect_runs_with_time_left(run.study, o.out);
  }
}

}  // namespace
