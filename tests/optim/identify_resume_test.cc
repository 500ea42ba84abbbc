// Resuming a killed identify run (optim/identify/identify_journal.h) and the size
// guard on its records (solver.max_measured_values). A kill is imitated by
// cutting the journal of a finished run after some of its records, the last
// one half-written; the resumed fit must be the uninterrupted fit to the bit.
// The same through real kill -9 of the command: tests/cli/kill_loop.py.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/errors.h"
#include "dynamics/simulation.h"
#include "input_error_of.h"
#include "io/config.h"
#include "optim/identify/identify.h"
#include "optim/identify/identify_journal.h"
#include "study_paths.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

IdentifyProblem load_resumed(const std::string& file, const std::vector<std::string>& overrides = {}) {
  const Json doc = load_config_json(file, overrides);
  return load_identify_problem(doc, config_source(file));
}

/// A noise-free drop record of a known contact (as identify_test.cc makes them).
void write_clean_record(const fs::path& file) {
  SceneConfig truth = load_scene(kDropStudy + "rig.json");
  truth.mechanism.contact.stiffness = 3e9;
  const SimulationResult sim = simulate_scene(truth, "truth");
  std::ofstream out(file);
  out.precision(17);
  out << "time,force_N\n";
  for (std::size_t i = 0; i < sim.series.time.size(); ++i)
    if (sim.series.time[i] >= 1e-4 && sim.series.time[i] <= 5e-4)
      out << sim.series.time[i] << "," << sim.series.contact_force[i] << "\n";
}

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// Everything the fit computes, compared to the bit (not the run time, nor
/// how many simulations came from a journal).
void expect_same_fit(const IdentifyResult& a, const IdentifyResult& b) {
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (std::size_t i = 0; i < a.parameters.size(); ++i) {
    EXPECT_TRUE(same_bits(a.parameters[i].value, b.parameters[i].value)) << a.parameters[i].name;
    EXPECT_TRUE(same_bits(a.parameters[i].std_error.value_or(0.0), b.parameters[i].std_error.value_or(0.0)));
  }
  EXPECT_TRUE(same_bits(a.final_cost, b.final_cost));
  EXPECT_TRUE(same_bits(a.initial_cost, b.initial_cost));
  EXPECT_EQ(a.iterations, b.iterations);
  EXPECT_EQ(a.simulations, b.simulations);
  EXPECT_EQ(a.reused_points, b.reused_points);
  ASSERT_EQ(a.stages.size(), b.stages.size());
  for (std::size_t s = 0; s < a.stages.size(); ++s) EXPECT_EQ(a.stages[s].iterations, b.stages[s].iterations);
  ASSERT_EQ(a.fits.size(), b.fits.size());
  for (std::size_t k = 0; k < a.fits.size(); ++k) EXPECT_EQ(a.fits[k].fitted, b.fits[k].fitted);
}

std::vector<std::string> lines_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

/// A fit with a smoothed continuation stage before the raw one, so that a
/// cut can fall in either stage.
class IdentifyResume : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratch_dir("identify_resume", ::testing::UnitTest::GetInstance()->current_test_info()->name());
    write_clean_record(dir_ / "clean.csv");
    problem_ =
        load_resumed(kIdentifyData + "single.json", {"reference.file=" + (dir_ / "clean.csv").string(),
                                                     "parameters.contact.exponent={\"initial\": 1.5, \"lower\": 1.0, "
                                                     "\"upper\": 2.5}",
                                                     "solver.smoothing=[2e-5]"});
  }
  void TearDown() override { fs::remove_all(dir_); }

  IdentifyResult fit(const fs::path& journal_dir) {
    IdentifyJournal journal(journal_dir, problem_);
    IdentifyOptions options;
    options.threads = 2;
    options.journal = &journal;
    return identify(problem_, options);
  }

  fs::path dir_;
  IdentifyProblem problem_;
};

TEST_F(IdentifyResume, JournalRecordsPointsIteratesAndEveryStage) {
  const IdentifyResult plain = identify(problem_, IdentifyOptions{});
  const IdentifyResult journaled = fit(dir_ / "full");
  expect_same_fit(plain, journaled);  // journaling changes nothing
  EXPECT_EQ(journaled.resumed_simulations, 0);
  int points = 0, iterates = 0, stages = 0;
  for (const std::string& line : lines_of(dir_ / "full" / "journal.jsonl")) {
    points += line.find("\"kind\":\"point\"") != std::string::npos;
    iterates += line.find("\"kind\":\"iterate\"") != std::string::npos;
    stages += line.find("\"kind\":\"stage\"") != std::string::npos;
  }
  EXPECT_GT(points, 0);
  EXPECT_GE(iterates, journaled.iterations);  // every accepted step, and each stage's start
  EXPECT_EQ(stages, 2);                       // the smoothed stage and the raw one
}

TEST_F(IdentifyResume, RunCutAnywhereResumesToTheUninterruptedFitToTheBit) {
  const IdentifyResult whole = fit(dir_ / "full");
  const std::vector<std::string> lines = lines_of(dir_ / "full" / "journal.jsonl");
  ASSERT_GT(lines.size(), 8U);
  for (const std::size_t kept : {std::size_t{1}, lines.size() / 3, 2 * lines.size() / 3, lines.size() - 1}) {
    SCOPED_TRACE("journal cut after " + std::to_string(kept) + " of " + std::to_string(lines.size()) + " lines");
    const fs::path cut = dir_ / ("cut" + std::to_string(kept));
    fs::create_directories(cut);
    {
      std::ofstream out(cut / "journal.jsonl", std::ios::binary);
      for (std::size_t i = 0; i < kept; ++i) out << lines[i] << "\n";
      out << lines[kept].substr(0, lines[kept].size() / 2);  // killed while writing this one
    }
    const IdentifyResult resumed = fit(cut);
    expect_same_fit(whole, resumed);
    if (kept > 1) {
      EXPECT_GT(resumed.resumed_simulations, 0);
    }
    EXPECT_LT(resumed.resumed_simulations, whole.simulations);
    // Resumed, the journal is whole again: a further re-run simulates nothing.
    const IdentifyResult again = fit(cut);
    expect_same_fit(whole, again);
    EXPECT_EQ(again.resumed_simulations, whole.simulations);
  }
}

TEST_F(IdentifyResume, JournalOfAChangedStudyIsRefused) {
  fit(dir_ / "full");
  const IdentifyProblem changed = load_resumed(
      kIdentifyData + "single.json", {"reference.file=" + (dir_ / "clean.csv").string(), "solver.smoothing=[3e-5]"});
  const InputError e = test::input_error_of([&] { const IdentifyJournal journal(dir_ / "full", changed); });
  EXPECT_EQ(e.path(), "hash");
  EXPECT_NE(e.reason().find("different identify study"), std::string::npos) << e.reason();
}

TEST_F(IdentifyResume, ChangedRecordChangesTheFingerprint) {
  std::ofstream(dir_ / "clean.csv", std::ios::app) << "6e-4,0\n";
  const IdentifyProblem changed =
      load_resumed(kIdentifyData + "single.json", {"reference.file=" + (dir_ / "clean.csv").string(),
                                                   "parameters.contact.exponent={\"initial\": 1.5, "
                                                   "\"lower\": 1.0, \"upper\": 2.5}",
                                                   "solver.smoothing=[2e-5]"});
  EXPECT_NE(changed.fingerprint, problem_.fingerprint);
  EXPECT_EQ(
      load_resumed(kIdentifyData + "single.json", {"reference.file=" + (dir_ / "clean.csv").string(),
                                                   "parameters.contact.exponent={\"initial\": 1.5, \"lower\": 1.0, "
                                                   "\"upper\": 2.5}",
                                                   "solver.smoothing=[2e-5]"})
          .fingerprint,
      changed.fingerprint);
}

// Issue 19 item 7: a record of 10 million samples validated in 2 s, then the
// fit ran for minutes at 8 GB. Its rows are counted before any is read, and
// it is refused naming the field, the limit and the memory it would need.
TEST(IdentifyRecordSize, TenMillionSamplesAreRefusedBeforeTheyAreRead) {
  const fs::path dir = test::scratch_dir("identify_resume", "big");
  {
    std::ofstream out(dir / "big.csv", std::ios::binary);
    out << "time,force_N\n";
    // Times far beyond the run: reading the rows would fail on line 2, so
    // the size message proves they were counted, not read.
    const std::string rows = [] {
      std::string block;
      for (int i = 0; i < 100000; ++i) block += "1,0\n";
      return block;
    }();
    for (int i = 0; i < 100; ++i) out << rows;
  }
  const InputError e = test::input_error_of(
      [&] { load_resumed(kIdentifyData + "single.json", {"reference.file=" + (dir / "big.csv").string()}); });
  EXPECT_EQ(e.path(), "reference.file");
  EXPECT_NE(e.reason().find("10000000 samples"), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("solver.max_measured_values = 500000"), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("8000 MB"), std::string::npos) << e.reason();  // 10^7 values × 800 bytes
  fs::remove_all(dir);
}

TEST(IdentifyRecordSize, LimitCountsEveryExperimentAndNamesTheOneOverIt) {
  // identify_drop: four records of 800 samples; the limit falls in the third.
  const InputError e = test::input_error_of(
      [] { load_resumed(kDropStudy + "identify_drop.json", {"solver.max_measured_values=2000"}); });
  EXPECT_EQ(e.path(), "experiments[2].reference.file");
  EXPECT_NE(e.reason().find("2400 measured values in all"), std::string::npos) << e.reason();
  EXPECT_NO_THROW(load_resumed(kDropStudy + "identify_drop.json", {"solver.max_measured_values=3201"}));
}

}  // namespace
}  // namespace camdyn::optim
