// A budget never becomes a conclusion, and a journal cannot lie
// (docs/outputs-and-resume.md, "Budgets" and "Checksums"):
// * a speed_limit whose runs all run out of integrator.max_steps exits 3 and
//   says nothing of where the follower leaves the cam;
// * a tolerance_rpm no bisection can reach is refused at validation;
// * a jump map stopped by --max-study-time exits 3, and resumed without it
//   ends with the outputs of an uninterrupted run;
// * a journal record with one changed digit is recomputed with a warning;
// * a journal that is a FIFO or a directory is refused (exit 2), no hang;
// * a convergence study whose wall-time budget runs out exits 3.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using camdyn::test::Outcome;
using camdyn::test::read_text;

/// Runs `camdyn args` but kills it after `limit_s` (a hang is a failure, not a stuck test).
Outcome run_with_timeout(const std::vector<std::string>& args, const fs::path& dir, double limit_s) {
  std::vector<std::string> argv = {CAMDYN_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  const pid_t pid = camdyn::test::spawn(argv, dir / "timed.out", dir / "timed.err");
  Outcome o;
  if (pid < 0) return o;
  const auto start = std::chrono::steady_clock::now();
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > limit_s) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      ADD_FAILURE() << "camdyn did not end within " << limit_s << " s";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  o.out = read_text(dir / "timed.out");
  o.err = read_text(dir / "timed.err");
  return o;
}

std::vector<std::string> speed_limit_args(const fs::path& out, const std::string& fields) {
  return {"run", kQuickstart, "--out", out.string(), "--quiet", "--set", "study=speed_limit", "--set", fields};
}

// Every speed runs out of its 20 steps: nothing is known about contact, so
// there is no limit, no "leaves the cam" and no report verdict. (The scan
// stops after its first batch, 500 … 1233 rpm one job at a time: a speed in
// it failed, so 1600 rpm cannot change the answer.)
TEST(BudgetConclusions, ASpeedLimitWhoseRunsAllRunOutOfStepsIsWithheld) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "speed_limit_steps");
  std::vector<std::string> args =
      speed_limit_args(dir / "out", R"(speed_limit={"low_rpm": 500, "high_rpm": 1600, "scan": 4})");
  args.insert(args.end(), {"--set", "integrator.max_steps=20", "--jobs", "1"});
  const Outcome o = camdyn::test::run_camdyn(args, dir);
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_TRUE(contains(o.err, "3 of 3 simulated speeds were cut short by a budget (integrator.max_steps)")) << o.err;
  EXPECT_TRUE(contains(o.err, "withheld")) << o.err;
  EXPECT_FALSE(contains(o.out, "leaves the cam")) << o.out;
  EXPECT_FALSE(contains(o.out, "stays on the cam")) << o.out;
  EXPECT_FALSE(fs::exists(dir / "out" / "report.html"));
  EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
  const Json j = Json::parse(read_text(dir / "out" / "speed_limit.json"));
  EXPECT_TRUE(j["speed_limit_rpm"].is_null()) << j.dump();
  EXPECT_TRUE(j["limited"].is_null()) << j.dump();
  EXPECT_TRUE(j["first_failure_rpm"].is_null()) << j.dump();
  EXPECT_EQ(j["budget_cut_runs"], 3);
  EXPECT_TRUE(j["conclusion_withheld"].is_string());
  for (const Json& c : j["checks"]) {
    EXPECT_EQ(c["status"], "failed: budget") << c.dump();
    EXPECT_EQ(c["budget"], "integrator.max_steps") << c.dump();
  }
}

TEST(BudgetConclusions, AToleranceBelowTheResolutionOfTheSpeedsIsRefused) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "tolerance");
  const std::string unreachable = R"(speed_limit={"low_rpm": 500, "high_rpm": 1600, "tolerance_rpm": 1e-310})";
  for (const char* command : {"validate", "run"}) {
    std::vector<std::string> args = speed_limit_args(dir / "out", unreachable);
    if (std::string(command) == "validate")
      args = {"validate", kQuickstart, "--set", "study=speed_limit", "--set", unreachable};
    const Outcome o = run_with_timeout(args, dir, 60.0);
    EXPECT_EQ(o.code, 2) << command << ": " << o.err;
    EXPECT_TRUE(contains(o.err, "speed_limit.tolerance_rpm")) << o.err;
    EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
  }
  // 1e-9 × 1600 rpm is the finest accepted.
  const Outcome finest =
      camdyn::test::run_camdyn({"validate", kQuickstart, "--set", "study=speed_limit", "--set",
                                R"(speed_limit={"low_rpm": 500, "high_rpm": 1600, "tolerance_rpm": 1.7e-6})"},
                               dir);
  EXPECT_EQ(finest.code, 0) << finest.err;
}

std::vector<std::string> jump_map_args(const fs::path& out) {
  return {"run",
          kQuickstart,
          "--out",
          out.string(),
          "--quiet",
          "--jobs",
          "1",
          "--set",
          "study=jump_map",
          "--set",
          R"(jump_map={"low_rpm": 1000, "high_rpm": 1200, "speeds": 3, "ranges": 3, "transient_revolutions": 5,
             "samples": 5})",
          "--set",
          R"(periodic={"max_period": 1, "lyapunov_revolutions": 10})"};
}

/// What must be equal between two runs of a jump map: the CSVs, and the JSON
/// without its run time and resume counter.
struct JumpMapOutputs {
  std::string speeds_csv, impacts_csv;
  Json json;
};

JumpMapOutputs jump_map_outputs(const fs::path& out) {
  JumpMapOutputs o{read_text(out / "jump_map.csv"), read_text(out / "impacts.csv"),
                   Json::parse(read_text(out / "jump_map.json"))};
  o.json.erase("run_time_s");
  o.json.erase("resumed_ranges");
  return o;
}

void expect_same(const JumpMapOutputs& a, const JumpMapOutputs& b) {
  EXPECT_EQ(a.speeds_csv, b.speeds_csv);
  EXPECT_EQ(a.impacts_csv, b.impacts_csv);
  EXPECT_EQ(a.json, b.json);
}

// Stopped part-way by the study's budget: exit 3; the re-run without the
// budget computes the cut ranges again (the ones the budget cut are not kept
// as failed speeds) and ends where an uninterrupted run does.
TEST(BudgetConclusions, AJumpMapStoppedByItsBudgetResumesToTheUninterruptedResult) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "jump_map_resume");
  const auto start = std::chrono::steady_clock::now();
  const Outcome whole = camdyn::test::run_camdyn(jump_map_args(dir / "whole"), dir, "whole");
  const double whole_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(whole.code, 0) << whole.err;
  const JumpMapOutputs expected = jump_map_outputs(dir / "whole");

  // Half the uninterrupted time: the first range done, a later one cut (a
  // smaller budget if the machine was quicker this time).
  Outcome stopped;
  for (double budget = 0.5 * whole_s; budget > 0.01 * whole_s; budget /= 2) {
    fs::remove_all(dir / "out");
    std::vector<std::string> args = jump_map_args(dir / "out");
    args.insert(args.end(), {"--max-study-time", std::to_string(budget)});
    stopped = camdyn::test::run_camdyn(args, dir, "stopped");
    if (stopped.code != 0) break;
  }
  ASSERT_EQ(stopped.code, 3) << stopped.err;
  EXPECT_TRUE(contains(stopped.err, "--max-study-time")) << stopped.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
  std::istringstream journal(read_text(dir / "out" / "journal.jsonl"));
  std::string line;
  std::getline(journal, line);  // the header
  while (std::getline(journal, line)) {
    const Json record = Json::parse(line);
    EXPECT_EQ(record["status"], "ok") << line;  // nothing the budget cut is kept
    for (const Json& p : record["points"]) EXPECT_TRUE(p["ok"].get<bool>()) << line;
  }

  const Outcome resumed = camdyn::test::run_camdyn(jump_map_args(dir / "out"), dir, "resumed");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  expect_same(jump_map_outputs(dir / "out"), expected);
  EXPECT_TRUE(fs::exists(dir / "out" / "complete.json"));
}

/// Changes one digit of `line` (the first after `"key":`) so that it stays valid JSON.
std::string change_a_digit(std::string line, const std::string& key) {
  std::size_t at = line.find("\"" + key + "\":");
  at = line.find_first_of("0123456789", at + key.size() + 3);
  line[at] = line[at] == '9' ? '8' : static_cast<char>(line[at] + 1);  // never a leading 0
  return line;
}

// One changed digit in a journal record (still valid JSON): the record fails
// its checksum, is recomputed with a warning, and the outputs are those of
// an uninterrupted run, not the changed value.
TEST(BudgetConclusions, AJournalRecordWithAChangedDigitIsRecomputed) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "journal_digit");
  ASSERT_EQ(camdyn::test::run_camdyn(jump_map_args(dir / "out"), dir, "whole").code, 0);
  const JumpMapOutputs expected = jump_map_outputs(dir / "out");

  std::istringstream lines(read_text(dir / "out" / "journal.jsonl"));
  std::string text, line;
  for (int n = 1; std::getline(lines, line); ++n)
    text += (n == 2 ? change_a_digit(line, "peak_contact_force") : line) + "\n";
  ASSERT_NE(text, read_text(dir / "out" / "journal.jsonl"));
  { std::ofstream(dir / "out" / "journal.jsonl", std::ios::binary | std::ios::trunc) << text; }
  const Outcome again = camdyn::test::run_camdyn(jump_map_args(dir / "out"), dir, "again");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(contains(again.err, "line 2 fails its checksum")) << again.err;
  EXPECT_TRUE(contains(again.err, "resuming: 2 of 3 runs already done")) << again.err;
  expect_same(jump_map_outputs(dir / "out"), expected);
}

// A journal of an earlier camdyn (no checksums) is not trusted either.
TEST(BudgetConclusions, AJournalWithoutChecksumsIsRecomputed) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "journal_unverified");
  ASSERT_EQ(camdyn::test::run_camdyn(jump_map_args(dir / "out"), dir, "whole").code, 0);
  const JumpMapOutputs expected = jump_map_outputs(dir / "out");
  std::istringstream lines(read_text(dir / "out" / "journal.jsonl"));
  std::string text, line;
  for (int n = 1; std::getline(lines, line); ++n) {
    Json j = Json::parse(line);
    if (n > 1) j.erase("checksum");
    text += j.dump() + "\n";
  }
  { std::ofstream(dir / "out" / "journal.jsonl", std::ios::binary | std::ios::trunc) << text; }
  const Outcome again = camdyn::test::run_camdyn(jump_map_args(dir / "out"), dir, "again");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(contains(again.err, "has no checksum")) << again.err;
  EXPECT_FALSE(contains(again.err, "resuming:")) << again.err;
  expect_same(jump_map_outputs(dir / "out"), expected);
}

TEST(BudgetConclusions, AJournalThatIsAFifoOrADirectoryIsRefused) {
  for (const char* kind : {"fifo", "directory"}) {
    const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", std::string("journal_") + kind);
    const fs::path journal = dir / "out" / "journal.jsonl";
    fs::create_directories(dir / "out");
    if (std::string(kind) == "fifo") {
      ASSERT_EQ(::mkfifo(journal.c_str(), 0644), 0);
    } else {
      fs::create_directories(journal);
    }
    const Outcome o = run_with_timeout(jump_map_args(dir / "out"), dir, 60.0);
    EXPECT_EQ(o.code, 2) << kind << ": " << o.err;
    EXPECT_TRUE(contains(o.err, journal.string())) << o.err;
    EXPECT_TRUE(contains(o.err, "not a regular file")) << o.err;
    EXPECT_TRUE(contains(o.err, std::string(kind) == "fifo" ? "a FIFO" : "a directory")) << o.err;
  }
}

// The study's wall time runs out part-way, in the runs after the reference
// (an rk4 run of 0.0005° steps takes far longer than the budget): the study
// is not finished, exit 3, never 0.
TEST(BudgetConclusions, AConvergenceStudyStoppedByItsBudgetExits3) {
  const fs::path dir = camdyn::test::scratch_dir("budget_conclusions", "convergence");
  const Outcome o =
      run_with_timeout({"run", kQuickstart, "--quiet", "--out", (dir / "out").string(), "--max-study-time", "2",
                        "--set", "study=convergence", "--set", R"(methods=["cvode_bdf", "rk4"])", "--set",
                        "tolerances=[1e-5]", "--set", "rk4_steps_deg=[0.0005]", "--set",
                        R"(reference={"method": "cvode_bdf", "rtol": 1e-8})", "--set", "simulation.cycles=2"},
                       dir, 120.0);
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_TRUE(contains(o.err, "--max-study-time")) << o.err;
  // On a slow machine the budget may run out in the reference run already (exit 3 as well).
  if (!contains(o.err, "reference run")) {
    EXPECT_TRUE(contains(o.err, "of 4 runs were cut short or not started")) << o.err;
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "complete.json"));
}

}  // namespace
