// A speed_limit study journals every simulated speed (docs/outputs-and-resume.md):
// killed part-way (SIGKILL, twice) and then stopped by --max-study-time, it
// resumes without the budget to exactly the outputs of an uninterrupted run,
// and no speed is simulated twice.
#include <gtest/gtest.h>
#include <signal.h>
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
using camdyn::test::read_text;

/// A scan of 4 speeds, of which 3 are simulated (500 … 1600 rpm: the first
/// batch reaches 1233 rpm, the first grid speed above the rigid-model jump
/// speed ≈ 1180 rpm, where the quickstart leaves the cam, so 1600 rpm cannot
/// change the answer), and a bisection of 5 (20 rpm tolerance: it leaves the
/// cam between 866 and 1233 rpm); 10 revolutions a speed so that a kill can
/// land part-way.
std::vector<std::string> args(const fs::path& out) {
  return {"run",
          kQuickstart,
          "--out",
          out.string(),
          "--quiet",
          "--jobs",
          "1",
          "--set",
          "study=speed_limit",
          "--set",
          R"(speed_limit={"low_rpm": 500, "high_rpm": 1600, "scan": 4, "tolerance_rpm": 20})",
          "--set",
          "simulation.cycles=10"};
}

std::size_t count_lines(const std::string& text) {
  std::size_t n = 0;
  for (const char c : text) n += c == '\n';
  return n;
}

/// speed_limit.json without what differs between an uninterrupted and a resumed run.
Json outputs(const fs::path& out) {
  Json j = Json::parse(read_text(out / "speed_limit.json"));
  j.erase("run_time_s");
  j.erase("resumed_checks");
  return j;
}

/// Starts the study into `out` and kills it once its journal holds `records` speeds.
void kill_after(const fs::path& out, std::size_t records, const fs::path& dir) {
  std::vector<std::string> argv = {CAMDYN_BINARY};
  const std::vector<std::string> rest = args(out);
  argv.insert(argv.end(), rest.begin(), rest.end());
  const pid_t pid = camdyn::test::spawn(argv, dir / "killed.out", dir / "killed.err");
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (count_lines(read_text(out / "journal.jsonl")) < records + 1 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ::kill(pid, SIGKILL);
  ASSERT_EQ(camdyn::test::wait_for(pid), 128 + SIGKILL) << "the study ended before it could be killed";
}

TEST(SpeedLimitResume, KilledAndBudgetStoppedRunsResumeToTheUninterruptedOutputs) {
  const fs::path dir = camdyn::test::scratch_dir("speed_limit_resume", "loop");
  const auto start = std::chrono::steady_clock::now();
  const camdyn::test::Outcome whole = camdyn::test::run_camdyn(args(dir / "whole"), dir, "whole");
  const double whole_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(whole.code, 0) << whole.err;
  const Json expected = outputs(dir / "whole");
  ASSERT_EQ(expected["checks"].size(), 8u) << expected.dump();
  ASSERT_EQ(expected["scan_skipped"], 1) << expected.dump();
  ASSERT_TRUE(expected["limited"].get<bool>());

  const fs::path out = dir / "out";
  kill_after(out, 2, dir);  // in the scan
  kill_after(out, 5, dir);  // in the bisection
  const std::string before_budget = read_text(out / "journal.jsonl");
  ASSERT_GE(count_lines(before_budget), 6u);
  EXPECT_FALSE(fs::exists(out / "complete.json"));

  // A budget too small for the 2 speeds left: exit 3, the limit withheld, the journal kept.
  std::vector<std::string> budgeted = args(out);
  budgeted.insert(budgeted.end(), {"--max-study-time", std::to_string(0.02 * whole_s)});
  const camdyn::test::Outcome stopped = camdyn::test::run_camdyn(budgeted, dir, "stopped");
  ASSERT_EQ(stopped.code, 3) << stopped.err;
  EXPECT_NE(stopped.err.find("withheld"), std::string::npos) << stopped.err;
  EXPECT_TRUE(outputs(out)["speed_limit_rpm"].is_null());

  const std::string journal_before = read_text(out / "journal.jsonl");
  const camdyn::test::Outcome resumed = camdyn::test::run_camdyn(args(out), dir, "resumed");
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(outputs(out), expected);
  EXPECT_TRUE(fs::exists(out / "complete.json"));
  const std::size_t kept = count_lines(journal_before) - 1;
  EXPECT_EQ(Json::parse(read_text(out / "speed_limit.json"))["resumed_checks"], kept);
  const std::string after = read_text(out / "journal.jsonl");
  EXPECT_EQ(after.substr(0, journal_before.size()), journal_before);  // kept, not redone
  EXPECT_EQ(count_lines(after), 9u);                                  // the header and each speed once
}

// A record changed by hand fails its checksum: that speed is simulated again.
TEST(SpeedLimitResume, AChangedRecordIsSimulatedAgain) {
  const fs::path dir = camdyn::test::scratch_dir("speed_limit_resume", "changed");
  const fs::path out = dir / "out";
  ASSERT_EQ(camdyn::test::run_camdyn(args(out), dir, "first").code, 0);
  const Json expected = outputs(out);
  std::istringstream in(read_text(out / "journal.jsonl"));
  std::string header, first, rest, line;
  std::getline(in, header);
  std::getline(in, first);
  while (std::getline(in, line)) rest += line + "\n";
  const std::size_t at = first.find("\"values\":\"") + 12;  // a hex digit of the speed's bits
  first[at] = first[at] == 'f' ? 'e' : 'f';
  { std::ofstream(out / "journal.jsonl", std::ios::trunc) << header << "\n" << first << "\n" << rest; }
  const camdyn::test::Outcome again = camdyn::test::run_camdyn(args(out), dir, "again");
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.err.find("fails its checksum"), std::string::npos) << again.err;
  EXPECT_EQ(outputs(out), expected);
  EXPECT_EQ(Json::parse(read_text(out / "speed_limit.json"))["resumed_checks"], 7);
}

}  // namespace
