// Warm-started evaluations of the optimize loop (optimizer.warm_start;
// optim/simulation_pool.h, docs/optimize.md "Warm starts"): a warm
// evaluation's objective is the design's (the steady state's, as the cold
// evaluation's) within the study's own settling criterion; a warm start that
// has not settled is run cold, to the bit; and a resumed warm search (its
// journal cut as a kill cuts it) retraces the uninterrupted one to the bit.
// That the warm search ends as well as the cold one is
// warm_start_slowtest.cc's (whole studies).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "optim/optimize/design.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize.h"
#include "optim/simulation_pool.h"
#include "optimize_study_text.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

/// The quickstart mechanism's splines against the peak contact force (optimize_study_text.h).
Study force_study(int max_evaluations) {
  return study_from("{" + quickstart_force_design_fields() + R"(
    "optimizer": { "algorithm": "LN_COBYLA", "max_evaluations": )" +
                    std::to_string(max_evaluations) + R"(, "warm_start": true } })");
}

double relative_difference(double a, double b) {
  return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300});
}

bool same_double_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// The design `x` moved by `share` of each bound range.
std::vector<double> moved(const DesignSpace& space, std::vector<double> x, double share) {
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += share * (space.upper()[i] - space.lower()[i]);
  return x;
}

struct Evaluated {
  Study study = force_study(1);
  SimulationPool pool{2, "test.json"};
  DesignEvaluator evaluator{study.config, "test.json", pool};
  DesignSpace space{study.scene, study.config.design, "test.json"};

  Evaluated() {
    EvaluationSettings full;
    const DesignEvaluation baseline = evaluator.evaluate(study.scene, full, true);
    evaluator.set_normalisation(evaluator.normalisation_from(baseline));
  }
  DesignEvaluation at(const std::vector<double>& x, const std::vector<std::optional<SectionPoint>>* warm) const {
    EvaluationSettings loop = loop_settings(study.config.optimizer);
    loop.warm = warm;
    loop.end_points = true;
    return evaluator.evaluate(space.scene(x), loop, true);
  }
  /// The design's objective over one period of each speed's periodic orbit.
  DesignEvaluation on_orbit(const std::vector<double>& x) const {
    SceneConfig scene = space.scene(x);
    scene.simulation.steady_state = true;
    return evaluator.evaluate(scene, loop_settings(study.config.optimizer), true);
  }
};

// The design moved by a search step (1e-3 of each range): started where the
// previous design's runs ended, one revolution returns to its start within
// kWarmStartTolerance, and the objective and constraints are the steady
// state's within WindowCheck::kTolerance, the criterion the study itself
// calls an objective settled by (as is the cold evaluation's).
TEST(WarmStart, AWarmEvaluationEqualsTheSteadyStateWithinTheSettlingTolerance) {
  const Evaluated t;
  const std::vector<double> x0 = t.space.initial(), x1 = moved(t.space, x0, 1e-3);
  const DesignEvaluation first = t.at(x0, nullptr);
  ASSERT_TRUE(first.valid) << first.error;
  ASSERT_EQ(first.end_points.size(), 2u);
  for (const auto& p : first.end_points) ASSERT_TRUE(p.has_value());

  const DesignEvaluation cold = t.at(x1, nullptr), warm = t.at(x1, &first.end_points), orbit = t.on_orbit(x1);
  ASSERT_TRUE(cold.valid && warm.valid && orbit.valid) << cold.error << warm.error << orbit.error;
  EXPECT_EQ(cold.warm_speeds, 0);
  EXPECT_EQ(warm.warm_speeds, 2);  // both kept: the motion had settled
  for (const SpeedResult& s : orbit.speeds) ASSERT_EQ(s.result.metrics_over, "periodic_orbit") << s.rpm;
  EXPECT_LE(relative_difference(warm.objective, orbit.objective), WindowCheck::kTolerance) << warm.objective;
  EXPECT_LE(relative_difference(cold.objective, orbit.objective), WindowCheck::kTolerance) << cold.objective;
  ASSERT_EQ(warm.constraints.size(), orbit.constraints.size());
  for (std::size_t i = 0; i < warm.constraints.size(); ++i) {
    EXPECT_LE(relative_difference(warm.constraints[i].value, orbit.constraints[i].value), WindowCheck::kTolerance);
    EXPECT_EQ(warm.constraints[i].holds, cold.constraints[i].holds);
  }
  ASSERT_EQ(warm.end_points.size(), 2u);  // the next evaluation's warm starts
  for (const auto& p : warm.end_points) EXPECT_TRUE(p.has_value());
}

// A warm start far from the design's orbit (10 % of the lift off) does not
// return to itself in one revolution: the run is made cold, and the
// evaluation is the cold one to the bit.
TEST(WarmStart, AnUnsettledWarmStartIsRunColdToTheBit) {
  const Evaluated t;
  const std::vector<double> x0 = t.space.initial();
  const DesignEvaluation first = t.at(x0, nullptr);
  ASSERT_TRUE(first.valid) << first.error;
  std::vector<std::optional<SectionPoint>> far = first.end_points;
  for (auto& p : far) {
    ASSERT_TRUE(p.has_value());
    p->x[0] += 0.1 * 0.02;  // the follower coordinate [m], a tenth of the 20 mm lift
  }
  const long rejected = t.pool.warm_rejected();
  const DesignEvaluation cold = t.at(x0, nullptr), warm = t.at(x0, &far);
  EXPECT_EQ(t.pool.warm_rejected() - rejected, 2);
  EXPECT_EQ(warm.warm_speeds, 0);
  EXPECT_TRUE(same_double_bits(warm.objective, cold.objective));
  EXPECT_TRUE(same_double_bits(warm.objective, first.objective));  // and the evaluation is the design's alone
}

std::vector<std::string> history_lines(const OptimizeOutcome& o) {
  std::vector<std::string> lines;
  for (const HistoryRecord& h : o.history) {
    std::ostringstream line;
    line << h.start << ' ' << std::bit_cast<std::uint64_t>(h.objective) << ' ' << h.valid << ' ' << h.feasible;
    lines.push_back(line.str());
  }
  return lines;
}

// A warm search killed and resumed: without a journal, with one, and resumed
// from the first records of one (the rest as a kill leaves them: gone, the
// last one cut), it is the same search to the bit, and keeps most runs warm.
TEST(WarmStart, AResumedSearchRetracesTheUninterruptedOneToTheBit) {
  Study study = force_study(16);
  study.config.rigid.enabled = false;  // the search alone
  OptimizeOptions options;
  options.threads = 2;
  const OptimizeOutcome plain = run_optimize(study.scene, study.config, "test.json", options);
  ASSERT_TRUE(plain.optimized.valid);
  EXPECT_GT(plain.warm_kept, plain.warm_rejected);

  const fs::path whole = test::scratch_dir("warm_start", "whole"), resumed = test::scratch_dir("warm_start", "resumed");
  options.checkpoint_dir = whole;
  const OptimizeOutcome journaled = run_optimize(study.scene, study.config, "test.json", options);
  EXPECT_EQ(history_lines(journaled), history_lines(plain));

  // The header and the first evaluations, and half of the next line.
  std::ifstream in(whole / "journal.jsonl");
  std::ofstream cut(resumed / "journal.jsonl");
  std::string line;
  for (int i = 0; i < 9 && std::getline(in, line); ++i) cut << line << '\n';
  ASSERT_TRUE(std::getline(in, line));
  cut << line.substr(0, line.size() / 2);
  cut.close();
  options.checkpoint_dir = resumed;
  const OptimizeOutcome again = run_optimize(study.scene, study.config, "test.json", options);
  EXPECT_EQ(again.resumed_evaluations, 8u);
  EXPECT_EQ(history_lines(again), history_lines(plain));
  ASSERT_EQ(again.x_optimized.size(), plain.x_optimized.size());
  for (std::size_t i = 0; i < again.x_optimized.size(); ++i)
    EXPECT_TRUE(same_double_bits(again.x_optimized[i], plain.x_optimized[i])) << i;
  EXPECT_TRUE(same_double_bits(again.optimized.objective, plain.optimized.objective));
}

}  // namespace
}  // namespace camdyn::optim
