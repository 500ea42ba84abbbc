// The compare study through the command line: every case at every grid
// point, failures recorded without stopping the others, jump onset where the
// rigid model puts it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "tolerance.h"

namespace {

using camdyn::test::kConverged;
using camdyn::test::read_text;
using camdyn::test::run_camdyn;
using camdyn::test::without_last_column;

namespace fs = std::filesystem;

std::vector<std::map<std::string, std::string>> read_csv(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) header.push_back(cell);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::map<std::string, std::string> row;
    std::stringstream ls(line);
    size_t i = 0;
    for (std::string cell; i < header.size(); ++i) {
      if (!std::getline(ls, cell, ',')) cell.clear();
      row[header[i]] = cell;
    }
    rows.push_back(row);
  }
  return rows;
}

TEST(CompareStudy, RunsEveryCaseAtEveryGridPointAndRecordsFailures) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_compare_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  std::ofstream(dir / "study.json") << R"({
    "extends": ")" << quickstart << R"(",
    "name": "laws", "study": "compare",
    "mechanism": { "follower": { "damping": 0.0 } },
    "simulation": { "cycles": 3, "discard_cycles": 1 },
    "cases": [ { "name": "cycloidal" },
               { "name": "soft", "set": ["mechanism.contact.stiffness=1e4"] } ],
    "grid": { "mechanism.cam.rpm": [900, 1100, 1250, 1400] }
  })";
  ASSERT_EQ(run_camdyn({"run", (dir / "study.json").string(), "--quiet", "--out", (dir / "out").string()}, dir).code,
            0);
  const auto rows = read_csv(dir / "out" / "comparison.csv");
  ASSERT_EQ(rows.size(), 8u);
  int failed = 0;
  for (const auto& row : rows) {
    if (row.at("case") == "soft") {
      EXPECT_EQ(row.at("status"), "failed");  // the contact cannot carry the preload
      EXPECT_FALSE(row.at("error").empty());
      ++failed;
      continue;
    }
    ASSERT_EQ(row.at("status"), "ok") << row.at("error");
    const double rpm = std::stod(row.at("mechanism.cam.rpm"));
    const double jump = std::stod(row.at("jump_speed_rpm"));
    const double separation = std::stod(row.at("separation_fraction"));
    // The rigid model (no damper) bounds the jump: none well below it, separation above it.
    if (rpm < 0.95 * jump) {
      EXPECT_EQ(separation, 0.0) << rpm;
    }
    if (rpm > 1.1 * jump) {
      EXPECT_GT(separation, 0.0) << rpm;
    }
  }
  EXPECT_EQ(failed, 4);
  EXPECT_TRUE(fs::exists(dir / "out" / "comparison.json"));
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html"));
  fs::remove_all(dir);
}

// A scratch folder per test, removed at the end.
class CompareCli : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("camdyn_compare_" + std::string(test->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure()) fs::remove_all(dir_);
  }
  // 2 cases × 6 speeds of the quickstart cam, two cycles each (about 0.1 s a run).
  fs::path write_study(const std::string& extra = "") {
    fs::path file = dir_ / "study.json";
    std::ofstream(file) << R"({
      "extends": ")" << CAMDYN_SOURCE_DIR
                        << R"(/studies/quickstart.json",
      "name": "resume", "study": "compare",
      "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1.0 },
      "cases": [ { "name": "cycloidal" },
                 { "name": "stiff", "set": ["mechanism.contact.stiffness=1e11"] } ],
      "grid": { "mechanism.cam.rpm": [900, 1000, 1100, 1200, 1300, 1400] })"
                        << extra << "}";
    return file;
  }
  fs::path dir_;
};

std::size_t count_lines(const std::string& text) {
  return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

TEST_F(CompareCli, JobsOneAndTwoWriteTheSameTable) {
  const fs::path study = write_study();
  ASSERT_EQ(run_camdyn({"run", study.string(), "--jobs", "1", "--out", (dir_ / "j1").string()}, dir_, "j1").code, 0)
      << read_text(dir_ / "j1.err");
  ASSERT_EQ(run_camdyn({"run", study.string(), "--jobs", "2", "--out", (dir_ / "j2").string()}, dir_, "j2").code, 0)
      << read_text(dir_ / "j2.err");
  const std::string one = without_last_column(dir_ / "j1" / "comparison.csv");
  EXPECT_EQ(count_lines(one), 13u);
  EXPECT_EQ(one, without_last_column(dir_ / "j2" / "comparison.csv"));
}

// A real SIGKILL part-way, then a rerun with the same --out: the finished
// runs are not done again, and the table equals an uninterrupted run's.
TEST_F(CompareCli, KilledStudyResumesToTheUninterruptedTable) {
  const fs::path study = write_study();
  ASSERT_EQ(run_camdyn({"run", study.string(), "--jobs", "2", "--out", (dir_ / "whole").string()}, dir_, "whole").code,
            0);

  const fs::path out = dir_ / "killed", journal = out / "journal.jsonl";
  const pid_t pid = camdyn::test::spawn({CAMDYN_BINARY, "run", study.string(), "--jobs", "1", "--out", out.string()},
                                        dir_ / "killed.out", dir_ / "killed.err");
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (count_lines(read_text(journal)) < 4 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ::kill(pid, SIGKILL);
  ASSERT_EQ(camdyn::test::wait_for(pid), 128 + SIGKILL) << "the study ended before it could be killed";
  const std::string before = read_text(journal);
  const std::size_t done = count_lines(before) - 1;  // the header line is not a run
  ASSERT_GE(done, 3u);
  ASSERT_LT(done, 12u);
  EXPECT_FALSE(fs::exists(out / "comparison.csv"));
  // A record cut off mid-write (as a kill during write() leaves it) must be ignored.
  std::ofstream(journal, std::ios::app) << R"({"index": 11, "case": "stiff", "status": "o)";

  ASSERT_EQ(run_camdyn({"run", study.string(), "--jobs", "2", "--out", out.string()}, dir_, "resumed").code, 0)
      << read_text(dir_ / "resumed.err");
  EXPECT_NE(read_text(dir_ / "resumed.err").find("resuming: " + std::to_string(done) + " of 12 runs already done"),
            std::string::npos)
      << read_text(dir_ / "resumed.err");
  const std::string after = read_text(journal);
  EXPECT_EQ(after.substr(0, before.size()), before);  // finished runs kept, not redone
  EXPECT_EQ(count_lines(after), 13u);                 // header + each run once
  EXPECT_EQ(without_last_column(out / "comparison.csv"), without_last_column(dir_ / "whole" / "comparison.csv"));

  // Once complete, a rerun does nothing but rewrite the outputs from the journal.
  ASSERT_EQ(run_camdyn({"run", study.string(), "--out", out.string()}, dir_, "again").code, 0);
  EXPECT_NE(read_text(dir_ / "again.err").find("resuming: 12 of 12 runs"), std::string::npos);
  EXPECT_EQ(read_text(journal), after);
}

TEST_F(CompareCli, JournalOfAnotherStudyIsRefused) {
  const fs::path study = write_study();
  const std::string out = (dir_ / "out").string();
  ASSERT_EQ(run_camdyn({"run", study.string(), "--out", out}, dir_, "first").code, 0);
  EXPECT_EQ(
      run_camdyn({"run", study.string(), "--out", out, "--set", "mechanism.follower.mass=0.4"}, dir_, "other").code, 2);
  const std::string err = read_text(dir_ / "other.err");
  EXPECT_NE(err.find("journal.jsonl"), std::string::npos) << err;
  EXPECT_NE(err.find("different compare study"), std::string::npos) << err;
}

TEST_F(CompareCli, InlineCaseOverlaysAndBestMarks) {
  const fs::path study = write_study(R"(,
      "overlays": [ { "mechanism.cam.rpm": 1300 } ])");
  // Replace the second case by an inline config (merged over the study's scene).
  std::string text = read_text(study);
  const std::string from = R"({ "name": "stiff", "set": ["mechanism.contact.stiffness=1e11"] })";
  text.replace(text.find(from), from.size(),
               R"({ "name": "heavy", "config": { "mechanism": { "follower": { "mass": 0.45 } } } })");
  std::ofstream(study) << text;
  ASSERT_EQ(run_camdyn({"run", study.string(), "--out", (dir_ / "out").string()}, dir_, "run").code, 0)
      << read_text(dir_ / "run.err");
  const auto rows = read_csv(dir_ / "out" / "comparison.csv");
  ASSERT_EQ(rows.size(), 12u);
  for (const auto& row : rows) ASSERT_EQ(row.at("status"), "ok") << row.at("error");
  // The heavier follower jumps earlier: jump speed scales as 1/sqrt(m) (each
  // refined by a golden-section search).
  const double light = std::stod(rows.front().at("jump_speed_rpm")),
               heavy = std::stod(rows.back().at("jump_speed_rpm"));
  EXPECT_NEAR(heavy / light, std::sqrt(0.3 / 0.45), kConverged);
  const std::string html = read_text(dir_ / "out" / "report.html");
  EXPECT_NE(html.find("Contact force against cam angle (last revolution), mechanism.cam.rpm=1300"), std::string::npos);
  EXPECT_NE(html.find("Follower displacement against cam angle"), std::string::npos);
  // A translating follower's lift of millimetres, in mm (output/plot_style.h length_unit).
  EXPECT_NE(html.find("follower displacement [mm]"), std::string::npos);
  EXPECT_NE(html.find("class=\"num best\""), std::string::npos);
  EXPECT_NE(html.find("Best case per metric"), std::string::npos);
  // The overlay runs carry their last revolution in the journal.
  const std::string journal = read_text(dir_ / "out" / "journal.jsonl");
  std::size_t overlays = 0;
  for (std::size_t at = journal.find("\"overlay\""); at != std::string::npos; at = journal.find("\"overlay\"", at + 1))
    ++overlays;
  EXPECT_EQ(overlays, 2u);  // both cases at 1300 rpm
}

// An oscillating arm's follower coordinate is its angle: the overlay of its
// motion and its kinematic error are drawn in rad, its spring in N m/rad.
TEST_F(CompareCli, ArmsMotionIsDrawnInRad) {
  const fs::path study = dir_ / "study.json";
  std::ofstream(study) << R"({
    "extends": ")" << CAMDYN_SOURCE_DIR
                       << R"(/studies/followers/oscillating_roller.json",
    "name": "arm", "study": "compare",
    "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1.0 },
    "grid": { "mechanism.follower.spring.stiffness": [40, 50], "mechanism.cam.rpm": [1000, 1100] },
    "overlays": [ { "mechanism.cam.rpm": 1000 } ]
  })";
  ASSERT_EQ(run_camdyn({"run", study.string(), "--out", (dir_ / "out").string()}, dir_, "run").code, 0)
      << read_text(dir_ / "run.err");
  for (const auto& row : read_csv(dir_ / "out" / "comparison.csv"))
    ASSERT_EQ(row.at("status"), "ok") << row.at("error");
  const std::string html = read_text(dir_ / "out" / "report.html");
  EXPECT_NE(html.find("follower displacement [rad]"), std::string::npos);
  EXPECT_EQ(html.find("follower displacement [m]"), std::string::npos);
  EXPECT_NE(html.find("max_kinematic_error [rad]"), std::string::npos);
  EXPECT_NE(html.find("mechanism.follower.spring.stiffness [N m/rad]"), std::string::npos);
}

// A `name` that is not a string threw a JSON type error out of the study
// (exit 1) before any case's scene could report it (found by scene_fuzzer,
// docs/fuzzing.md).
TEST_F(CompareCli, NameThatIsNotAStringIsAnInputError) {
  const fs::path study = write_study();
  EXPECT_EQ(run_camdyn({"validate", study.string(), "--set", "name=[1]"}, dir_, "validate").code, 2);
  const std::string err = read_text(dir_ / "validate.err");
  EXPECT_NE(err.find("name"), std::string::npos) << err;
  EXPECT_EQ(err.find("type_error"), std::string::npos) << err;
}

// Two axes of 1e5 values ask for 2e10 runs: listing them exhausted the
// machine's memory (validate ran out of 10 GB instead of ending). The run
// count is checked against --max-memory before any run is listed.
TEST_F(CompareCli, GridBeyondTheMemoryBudgetIsRefusedBeforeItIsListed) {
  std::string speeds, dampings;
  for (int i = 0; i < 100000; ++i) {
    speeds += (i ? "," : "") + std::to_string(600 + i);
    dampings += (i ? "," : "") + std::to_string(i);
  }
  const fs::path study = dir_ / "huge.json";
  std::ofstream(study) << R"({ "extends": ")" << CAMDYN_SOURCE_DIR << R"(/studies/quickstart.json",
      "study": "compare", "grid": { "mechanism.cam.rpm": [)"
                       << speeds << R"(], "mechanism.follower.damping": [)" << dampings << "] } }";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(run_camdyn({"validate", study.string()}, dir_, "huge").code, 2);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  const std::string err = read_text(dir_ / "huge.err");
  EXPECT_NE(err.find("grid: the study asks for 1e+10 runs"), std::string::npos) << err;
  EXPECT_NE(err.find("more than the memory budget of 2048 MB (--max-memory)"), std::string::npos) << err;
  // 2 cases x 6 speeds = 12 runs of about 1 KB: over a budget of 0.01 MB, within the default one.
  EXPECT_EQ(run_camdyn({"validate", write_study().string(), "--max-memory", "0.01"}, dir_, "small").code, 2);
  EXPECT_EQ(run_camdyn({"validate", write_study().string()}, dir_, "default").code, 0)
      << read_text(dir_ / "default.err");
}

TEST_F(CompareCli, BadOverlayKeyIsAnInputError) {
  const fs::path study = write_study(R"(,
      "overlays": [ { "mechanism.cam.rpm": 1234 } ])");
  EXPECT_EQ(run_camdyn({"run", study.string(), "--out", (dir_ / "out").string()}, dir_, "run").code, 2);
  EXPECT_NE(read_text(dir_ / "run.err").find("overlays[0].mechanism.cam.rpm"), std::string::npos)
      << read_text(dir_ / "run.err");
}

}  // namespace

namespace {

// A train's metrics are compare columns beside the others (issue 57 item 5):
// on the DOHC lash train they are the simulate run's own summary.json
// figures of the same scene, to the bit; a single follower leaves them
// empty (null), and its report has no column no run fills.
TEST_F(CompareCli, TrainMetricsAreColumnsAndEqualTheSimulateRuns) {
  const std::string dohc = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/dohc_bucket_lash.json";
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  std::ofstream(dir_ / "study.json") << R"({
    "extends": ")" << dohc << R"(",
    "name": "trains", "study": "compare",
    "mechanism": { "cam": { "rpm": 2000 } },
    "simulation": { "cycles": 2, "discard_cycles": 1, "steady_state": false },
    "cases": [ { "name": "dohc" }, { "name": "single", "config": ")"
                                     << quickstart << R"(" } ]
  })";
  ASSERT_EQ(run_camdyn({"run", (dir_ / "study.json").string(), "--quiet", "--out", (dir_ / "out").string()}, dir_).code,
            0);
  ASSERT_EQ(run_camdyn({"run", dohc, "--quiet", "--out", (dir_ / "sim").string(), "--set", "mechanism.cam.rpm=2000",
                        "--set", "simulation.cycles=2", "--set", "simulation.discard_cycles=1", "--set",
                        "simulation.steady_state=false"},
                       dir_)
                .code,
            0);
  const nlohmann::json compared = nlohmann::json::parse(read_text(dir_ / "out" / "comparison.json"));
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir_ / "sim" / "summary.json"));
  const nlohmann::json& train = summary.at("metrics");
  bool saw_dohc = false, saw_single = false;
  for (const nlohmann::json& row : compared.at("results")) {
    ASSERT_EQ(row.at("status"), "ok") << row.at("error");
    const nlohmann::json& m = row.at("metrics");
    for (const char* name : {"min_link_force", "link_separation_fraction", "max_seating_velocity", "seat_impacts",
                             "peak_spring_force", "take_up_bounces", "seat_bounces", "max_seat_bounce_height"}) {
      if (row.at("case") == "dohc") {
        saw_dohc = true;
        EXPECT_EQ(m.at(name).get<double>(), train.at(name).get<double>()) << name;
      } else {
        saw_single = true;
        EXPECT_TRUE(m.at(name).is_null()) << name;
      }
    }
  }
  EXPECT_TRUE(saw_dohc && saw_single);
  const std::string header = read_text(dir_ / "out" / "comparison.csv").substr(0, 4096);
  EXPECT_NE(header.find("take_up_bounces"), std::string::npos);
}

}  // namespace
