// camdyn::simulate (<camdyn/simulate.h>) is the internal simulate_scene
// (dynamics/simulation.h), to the bit: the same metrics, counters, series
// and events; a run that stops early is a status, as in summary.json.
#include <camdyn/simulate.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "dynamics/metrics.h"
#include "dynamics/simulation.h"
#include "input_error_of.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

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

// Every column carries its unit, from the one table that names the columns
// (dynamics/series_columns.h): the values under a name are the run's column of
// that name, and the units are those docs/config.md, "Outputs of `simulate`", gives.
TEST(Simulate, ColumnsCarryTheirUnitsAndTheirNamesValues) {
  const std::string file = kStudies + "valvetrain/pushrod_rocker.json";
  const std::vector<std::string> overrides = {"simulation.cycles=1", "simulation.discard_cycles=0"};
  const SimulationResult internal = simulate_scene(load_scene(file, overrides), file);
  const Result result = simulate(Scene::load(file, overrides));
  ASSERT_EQ(result.series.units.size(), result.series.names.size());
  for (std::size_t c = 0; c < result.series.names.size(); ++c)
    EXPECT_EQ(result.series.units[c], column_unit(result.series.names[c])) << result.series.names[c];
  const std::pair<const char*, const char*> expected[] = {{"time", "s"},
                                                          {"cam_angle_deg", "deg"},
                                                          {"follower_position", "m"},
                                                          {"gap", "m"},
                                                          {"contact_force", "N"},
                                                          {"cam_speed_rpm", "rpm"},
                                                          {"valve_position", "m"},
                                                          {"valve_velocity", "m/s"},
                                                          {"valve_link_force", "N"},
                                                          {"valve_seat_force", "N"},
                                                          {"pushrod_rocker_link_force", "N"}};
  for (const auto& [name, unit] : expected) EXPECT_EQ(column_unit(name), unit) << name;
  EXPECT_EQ(result.series["follower_position"], internal.series.follower_position);
  EXPECT_EQ(result.series["gap"], internal.series.gap);
  EXPECT_EQ(result.series["contact_force"], internal.series.contact_force);
  EXPECT_EQ(result.series["cam_speed_rpm"], internal.series.cam_speed_rpm);
  // An arm's coordinate is an angle; its own seat acts along it, a train body's does not.
  EXPECT_EQ(column_unit("follower_acceleration", true), "rad/s^2");
  EXPECT_EQ(column_unit("follower_seat_force", true), "N m");
  EXPECT_EQ(column_unit("valve_seat_force", true), "N");
  EXPECT_EQ(column_unit("no_such_column"), "");
  EXPECT_EQ(column_unit("_position"), "");
  EXPECT_EQ(series_column_units().size(), TimeSeries::column_names().size());
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

// The options are checked as config fields are: InputError naming the option
// (no file) and the offending element, before anything runs.
TEST(Simulate, SampleTimesMustBeFiniteAscendingAndWithinTheRun) {
  const Scene scene = Scene::load(kQuickstart);
  // simulation.cycles = 4 at 1300 rpm [s].
  const double t_end = 4 * 60.0 / 1300.0;
  const auto error_for = [&](std::vector<double> times) {
    SimulateOptions options;
    options.record_series = false;
    options.sample_times = std::move(times);
    return test::input_error_of([&] { simulate(scene, options); });
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const InputError& e :
       {error_for({0.01, nan, 0.02}), error_for({0.01, inf}), error_for({0.02, 0.01}), error_for({-0.01}),
        error_for({0.0, std::nextafter(t_end, 1.0)}), error_for(std::vector<double>(kMaxPointsPerCall + 1, 0.0))}) {
    EXPECT_EQ(e.path(), "sample_times");
    EXPECT_EQ(e.file(), "");
  }
  EXPECT_EQ(error_for({0.01, nan, 0.02}).reason(), "sample_times[1] is nan: must be a finite number [s]");
  EXPECT_NE(error_for({0.02, 0.01}).reason().find("must be ascending"), std::string::npos);
  EXPECT_NE(error_for({-0.01}).reason().find("before the run's start"), std::string::npos);
  EXPECT_NE(error_for({0.0, std::nextafter(t_end, 1.0)}).reason().find("after the run's end"), std::string::npos);
  EXPECT_NE(error_for(std::vector<double>(kMaxPointsPerCall + 1, 0.0)).reason().find("at most 1000000"),
            std::string::npos);

  SimulateOptions whole_run;
  whole_run.record_series = false;
  whole_run.sample_times = {0.0, t_end};
  const Result result = simulate(scene, whole_run);
  EXPECT_EQ(result.end_time, t_end);
  EXPECT_EQ(result.samples["time"], whole_run.sample_times);
}

TEST(Simulate, JobsAreZeroToTheCap) {
  const Scene scene = Scene::load(kQuickstart);
  for (const int jobs : {-1, kMaxJobs + 1}) {
    SimulateOptions options;
    options.jobs = jobs;
    EXPECT_EQ(test::input_error_of([&] { simulate(scene, options); }).path(), "jobs") << jobs;
  }
}

TEST(Simulate, AProgressHookThatThrowsAbandonsTheRun) {
  SimulateOptions options;
  options.record_series = false;
  struct Stop {};
  long calls = 0;
  options.progress = [&](double) {
    ++calls;
    throw Stop{};
  };
  // Long enough that the hook is called (every 0.25 s of wall time) before it ends.
  EXPECT_THROW(simulate(Scene::load(kQuickstart, {"simulation.cycles=400"}), options), Stop);
  EXPECT_EQ(calls, 1);
}

// An interrupt check that fires stops the run (and its steady-state search)
// as a used-up study budget would: a status, not an exception; once the
// check's scope ends, runs go on as before.
TEST(Simulate, AnInterruptCheckThatFiresStopsTheRunAsABudget) {
  const Scene scene = Scene::load(kQuickstart, {"simulation.cycles=400", "simulation.steady_state=true"});
  SimulateOptions options;
  options.record_series = false;
  long polls = 0;
  Result result;
  {
    const InterruptCheck check([&] { return ++polls >= 2; });
    result = simulate(scene, options);
  }
  EXPECT_EQ(polls, 2);
  EXPECT_EQ(result.solver.termination, TerminationStatus::wall_time_budget);
  EXPECT_NE(result.solver.message.find("interrupted"), std::string::npos) << result.solver.message;
  const Result after = simulate(Scene::load(kQuickstart), options);
  EXPECT_TRUE(after.solver.converged()) << after.solver.message;
}

// The check is polled on the thread that made it only.
TEST(Simulate, AnInterruptCheckIsNotPolledOnOtherThreads) {
  long polls = 0;
  const InterruptCheck check([&] {
    ++polls;
    return true;
  });
  SimulateOptions options;
  options.record_series = false;
  Result result;
  std::thread worker([&] { result = simulate(Scene::load(kQuickstart, {"simulation.cycles=100"}), options); });
  worker.join();
  EXPECT_EQ(polls, 0);
  EXPECT_TRUE(result.solver.converged()) << result.solver.message;
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
