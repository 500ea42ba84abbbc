// The optimize journal (optim/optimize/optimize_journal.h): an evaluation read back is
// the one written, to the bit; a line cut by a kill is dropped; a journal of
// another study is refused. The replay itself (a killed optimize re-run ends
// with the uninterrupted run's outputs) is tests/cli/kill_loop.py's.
#include "optim/optimize/optimize_journal.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/errors.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

JournaledEvaluation sample_evaluation() {
  JournaledEvaluation e;
  e.valid = true;
  e.objective = 0.1 + 0.2;  // not a short decimal
  e.feasible = false;
  e.constraints = {ConstraintValue{1.0 / 3.0, -0.0, std::numeric_limits<double>::denorm_min(), false},
                   ConstraintValue{std::numeric_limits<double>::infinity(), 2.5e-300, -7.0, true}};
  e.simulations = 3;
  return e;
}

void expect_same_bits(double a, double b) {
  EXPECT_EQ(std::bit_cast<std::uint64_t>(a), std::bit_cast<std::uint64_t>(b));
}

TEST(OptimizeJournal, AnEvaluationReadBackIsTheOneWrittenToTheBit) {
  const fs::path dir = test::scratch_dir("optimize_journal", "bits");
  const std::vector<double> x = {0.1, -0.0, 1e-310};
  {
    OptimizeJournal journal(dir, "f1", 3, 2);
    EXPECT_EQ(journal.resumed(), 0u);
    journal.add(x, sample_evaluation());
    journal.add(x, JournaledEvaluation{});  // a design already journaled is not journaled again
    JournaledEvaluation invalid;
    invalid.error = "the spline \"crossed\" itself";
    invalid.objective = 1e300;
    invalid.constraints.resize(2);
    journal.add({0.2, 0.0, 0.0}, invalid);
  }
  const OptimizeJournal journal(dir, "f1", 3, 2);
  EXPECT_EQ(journal.resumed(), 2u);
  const JournaledEvaluation* e = journal.find(x);
  ASSERT_NE(e, nullptr);
  const JournaledEvaluation want = sample_evaluation();
  EXPECT_TRUE(e->valid);
  EXPECT_FALSE(e->feasible);
  EXPECT_EQ(e->simulations, 3);
  expect_same_bits(e->objective, want.objective);
  ASSERT_EQ(e->constraints.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    expect_same_bits(e->constraints[i].value, want.constraints[i].value);
    expect_same_bits(e->constraints[i].margin, want.constraints[i].margin);
    expect_same_bits(e->constraints[i].residual, want.constraints[i].residual);
    EXPECT_EQ(e->constraints[i].holds, want.constraints[i].holds);
  }
  const JournaledEvaluation* bad = journal.find({0.2, 0.0, 0.0});
  ASSERT_NE(bad, nullptr);
  EXPECT_EQ(bad->error, "the spline \"crossed\" itself");
  EXPECT_EQ(journal.find({0.2, -0.0, 0.0}), nullptr);  // -0.0 is another design to the bit
}

TEST(OptimizeJournal, ALineCutByAKillIsDroppedAndTheOthersKept) {
  const fs::path dir = test::scratch_dir("optimize_journal", "cut");
  {
    OptimizeJournal journal(dir, "f1", 1, 2);
    journal.add({1.0}, sample_evaluation());
    journal.add({2.0}, sample_evaluation());
  }
  const fs::path path = dir / "journal.jsonl";
  fs::resize_file(path, fs::file_size(path) - 20);  // the last line without its end
  const OptimizeJournal journal(dir, "f1", 1, 2);
  EXPECT_EQ(journal.resumed(), 1u);
  EXPECT_NE(journal.find({1.0}), nullptr);
  EXPECT_EQ(journal.find({2.0}), nullptr);
}

// optimizer.warm_start: an evaluation depends on its start's earlier ones,
// so the journal keeps each start's evaluations apart and gives back where
// each speed's run ended (the warm states of the replayed search), to the bit.
TEST(OptimizeJournal, AWarmStartedSearchIsJournaledPerStartWithItsEndPoints) {
  const fs::path dir = test::scratch_dir("optimize_journal", "warm");
  SectionPoint end;
  end.x = {1.0 / 3.0, -0.0, 2e-310};
  end.approach_speed = 0.1 + 0.2;
  end.motor_phase = -1.0 / 7.0;
  {
    OptimizeJournal journal(dir, "f1", 1, 2, true);
    JournaledEvaluation e = sample_evaluation();
    e.start = 1;
    e.end_points = {std::nullopt, end};
    journal.add({1.0}, e);
  }
  const OptimizeJournal journal(dir, "f1", 1, 2, true);
  EXPECT_EQ(journal.find({1.0}, 0), nullptr);  // start 0 did not evaluate it
  const JournaledEvaluation* e = journal.find({1.0}, 1);
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->start, 1);
  ASSERT_EQ(e->end_points.size(), 2u);
  EXPECT_FALSE(e->end_points[0].has_value());
  ASSERT_TRUE(e->end_points[1].has_value());
  ASSERT_EQ(e->end_points[1]->x.size(), 3u);
  for (std::size_t j = 0; j < 3; ++j) expect_same_bits(e->end_points[1]->x[j], end.x[j]);
  expect_same_bits(e->end_points[1]->approach_speed, end.approach_speed);
  expect_same_bits(e->end_points[1]->motor_phase, end.motor_phase);
}

TEST(OptimizeJournal, AJournalOfAnotherStudyIsRefused) {
  const fs::path dir = test::scratch_dir("optimize_journal", "other");
  { OptimizeJournal journal(dir, "f1", 1, 0); }
  EXPECT_THROW(OptimizeJournal(dir, "f2", 1, 0), InputError);
}

}  // namespace
}  // namespace camdyn::optim
