// Multi-start searches with their starts at once on --jobs threads
// (optim/search.h SearchProblem::parallel_starts): the same search as the
// starts one after the other, to the bit (history, each start's result, the
// candidates, the answer), cold and warm-started; and a parallel run killed
// and resumed from its journal ends with the sequential run's result.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "optim/optimize/optimize.h"
#include "optimize_study_text.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

/// Three starts of COBYLA on the quickstart mechanism's splines against the
/// peak contact force at two speeds (the search alone: no rigid stage).
Study three_starts(bool warm) {
  Study s = study_from("{" + quickstart_force_design_fields() + R"(
    "rigid": { "enabled": false },
    "optimizer": { "algorithm": "LN_COBYLA", "max_evaluations": 24, "starts": 3, "seed": 7 } })");
  s.config.optimizer.warm_start = warm;
  return s;
}

std::string bits(double v) { return std::to_string(std::bit_cast<std::uint64_t>(v)); }

/// Everything the search decided, as text to compare to the bit.
std::string search_trace(const OptimizeOutcome& o) {
  std::ostringstream t;
  for (const HistoryRecord& h : o.history)
    t << h.evaluation << ' ' << h.start << ' ' << bits(h.objective) << ' ' << h.valid << h.feasible << ' '
      << bits(h.best_objective) << '\n';
  for (const StartResult& s : o.search.starts) {
    t << "start " << s.index << ' ' << s.stop_reason << ' ' << s.evaluations << ' ' << bits(s.best_objective);
    for (double v : s.x0) t << ' ' << bits(v);
    t << '\n';
  }
  for (const auto& x : o.search.candidates) {
    t << "candidate";
    for (double v : x) t << ' ' << bits(v);
    t << '\n';
  }
  t << "answer";
  for (double v : o.x_optimized) t << ' ' << bits(v);
  t << ' ' << bits(o.selection.chosen().verified.objective) << ' ' << o.search.evaluations << ' '
    << o.search.invalid_evaluations << '\n';
  return t.str();
}

OptimizeOutcome run_with(const Study& s, int jobs, const fs::path& dir = {}) {
  OptimizeOptions options;
  options.threads = jobs;
  options.checkpoint_dir = dir;
  return run_optimize(s.scene, s.config, "test.json", options);
}

class ParallelStarts : public ::testing::TestWithParam<bool> {};

TEST_P(ParallelStarts, TheStartsAtOnceMakeTheSequentialSearchToTheBit) {
  const Study s = three_starts(GetParam());
  const OptimizeOutcome one = run_with(s, 1), three = run_with(s, 3);
  ASSERT_EQ(one.search.starts.size(), 3u);
  EXPECT_EQ(one.history.size(), 24u);
  EXPECT_EQ(search_trace(three), search_trace(one));
  EXPECT_EQ(three.loop_simulations, one.loop_simulations);
  EXPECT_EQ(three.warm_kept, one.warm_kept);
  EXPECT_EQ(one.warm_kept > 0, GetParam());
}

// Killed part-way (the journal's first records kept, the next cut as a kill
// cuts it) and resumed, on three threads: the sequential run's result.
TEST_P(ParallelStarts, AResumedParallelSearchEndsWithTheSequentialResult) {
  const Study s = three_starts(GetParam());
  const std::string tag = GetParam() ? "warm" : "cold";
  const fs::path whole = test::scratch_dir("parallel_starts", tag + "_whole"),
                 resumed = test::scratch_dir("parallel_starts", tag + "_resumed");
  const OptimizeOutcome one = run_with(s, 1), first = run_with(s, 3, whole);
  EXPECT_EQ(search_trace(first), search_trace(one));
  std::ifstream in(whole / "journal.jsonl");
  std::ofstream cut(resumed / "journal.jsonl");
  std::string line;
  for (int i = 0; i < 13 && std::getline(in, line); ++i) cut << line << '\n';
  ASSERT_TRUE(std::getline(in, line));
  cut << line.substr(0, line.size() / 2);
  cut.close();
  const OptimizeOutcome again = run_with(s, 3, resumed);
  EXPECT_EQ(again.resumed_evaluations, 12u);
  EXPECT_EQ(search_trace(again), search_trace(one));
}

INSTANTIATE_TEST_SUITE_P(ColdAndWarm, ParallelStarts, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& p) { return p.param ? "warm" : "cold"; });

}  // namespace
}  // namespace camdyn::optim
