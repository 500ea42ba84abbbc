// camdyn::simulate (<camdyn/simulate.h>) is the internal simulate_scene
// (dynamics/simulation.h), to the bit: the same metrics, counters, series
// and events; a run that stops early is a status, as in summary.json.
#include <camdyn/simulate.h>
#include <gtest/gtest.h>

#include <cstring>
#include <optional>
#include <string>
#include <thread>

#include "common/errors.h"
#include "dynamics/metrics.h"
#include "dynamics/simulation.h"
#include "io/config.h"

namespace camdyn {
namespace {

const std::string kQuickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";

/// The same double, bit for bit (EXPECT_EQ would also take -0.0 for 0.0).
bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(Simulate, GivesTheInternalRunToTheBit) {
  const SimulationResult internal = simulate_scene(load_scene(kQuickstart), kQuickstart);
  const Result result = simulate(Scene::load(kQuickstart));

  std::size_t metrics = 0;
  for_each_metric(internal.metrics, [&](const char* name, const auto& value, const MetricInfo&) {
    const std::optional<double> v = metric_value(value);  // none: a metric the scene does not have
    ASSERT_EQ(result.metrics.count(name), v ? 1U : 0U) << name;
    if (!v) return;
    EXPECT_TRUE(same_bits(result.metrics.at(name), *v)) << name << ": " << result.metrics.at(name) << " vs " << *v;
    ++metrics;
  });
  EXPECT_EQ(result.metrics.size(), metrics);

  EXPECT_EQ(termination_name(result.solver.termination), to_string(internal.solver.termination));
  EXPECT_EQ(result.solver.method, internal.solver.method);
  EXPECT_EQ(result.solver.steps, internal.solver.counters.steps);
  EXPECT_EQ(result.solver.rhs_evaluations, internal.solver.counters.rhs_evaluations);
  EXPECT_EQ(result.solver.events, internal.solver.events);

  ASSERT_EQ(result.series.names, TimeSeries::column_names());
  const auto columns = internal.series.columns();
  ASSERT_EQ(result.series.values.size(), columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c) {
    const std::string& name = result.series.names[c];
    ASSERT_EQ(result.series[name].size(), columns[c]->size()) << name;
    for (std::size_t i = 0; i < columns[c]->size(); ++i) {
      ASSERT_TRUE(same_bits(result.series[name][i], (*columns[c])[i])) << name << " row " << i;
    }
  }

  ASSERT_EQ(result.events.size(), internal.events.size());
  for (std::size_t i = 0; i < internal.events.size(); ++i) {
    EXPECT_TRUE(same_bits(result.events[i].time, internal.events[i].time)) << i;
    EXPECT_EQ(result.events[i].onset, internal.events[i].onset) << i;
    EXPECT_EQ(result.events[i].impact, internal.events[i].impact) << i;
    EXPECT_TRUE(same_bits(result.events[i].speed, internal.events[i].speed)) << i;
  }
  EXPECT_TRUE(same_bits(result.evaluated_from, internal.evaluated_from));
  EXPECT_TRUE(same_bits(result.end_time, internal.end_time));
}

// A Scene is immutable: threads may simulate one scene (one Model) at once,
// each run with its own workspace, and get the run a single thread gets.
TEST(Simulate, OneSceneFromTwoThreadsGivesTheSameRun) {
  const Scene scene = Scene::load(kQuickstart);
  SimulateOptions options;
  options.record_series = false;
  const Result alone = simulate(scene, options);
  Result first, second;
  std::thread other([&] { first = simulate(scene, options); });
  second = simulate(scene, options);
  other.join();
  for (const Result* r : {&first, &second}) {
    EXPECT_EQ(r->solver.steps, alone.solver.steps);
    for (const auto& [name, value] : alone.metrics) EXPECT_TRUE(same_bits(r->metrics.at(name), value)) << name;
  }
}

TEST(Simulate, SamplesAtTheRequestedTimes) {
  SimulateOptions options;
  options.record_series = false;
  options.sample_times = {0.05, 0.1};
  const Result result = simulate(Scene::load(kQuickstart), options);
  EXPECT_EQ(result.series.rows(), 0U);
  ASSERT_EQ(result.samples.rows(), 2U);
  EXPECT_EQ(result.samples["time"][0], 0.05);
  EXPECT_EQ(result.samples["time"][1], 0.1);
}

TEST(Simulate, ABudgetThatRunsOutIsAStatusNotAnException) {
  const Result result = simulate(Scene::load(kQuickstart, {"integrator.max_steps=50"}));
  EXPECT_EQ(result.solver.termination, TerminationStatus::step_budget);
  EXPECT_FALSE(result.solver.converged());
  EXPECT_FALSE(result.solver.message.empty());
  EXPECT_THROW(throw_if_failed(result), NumericalError);
}

}  // namespace
}  // namespace camdyn
