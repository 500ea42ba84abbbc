// summary.json of a simulate run: the metrics in the order Metrics' visit
// lists them, and the solver block with its termination status and message
// after the counters that were there before. The report's verdict banner:
// in contact, separating, or a drop test.
#include "study/simulation_output.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "dynamics/simulation.h"
#include "output/curve_decimation.h"
#include "tests/dynamics/scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

std::vector<std::string> keys(const Json& object) {
  std::vector<std::string> out;
  for (const auto& item : object.items()) out.push_back(item.key());
  return out;
}

struct SceneRun {
  SceneConfig scene;
  Model model;
  SimulationResult result;
  explicit SceneRun(SceneConfig s) : scene(std::move(s)), model(build_model(scene, "test")) {
    Workspace ws;
    result = simulate(scene, model, ws);
  }
};

TEST(SimulationOutput, SummaryListsEveryMetricOnceInVisitOrder) {
  const SceneRun run(test::cycloidal_cam_scene(700.0));
  const Json summary = summary_json(run.scene, run.model, run.result);
  // Every metric but those the scene does not have (a roller without materials:
  // no contact stress, no face excursion; no seat: no float fraction and gap;
  // no spring wire: no spring stress), in visit order.
  std::vector<std::string> applying;
  for_each_metric(run.result.metrics, [&](const char* name, const auto& value, const MetricInfo&) {
    if (metric_value(value)) applying.emplace_back(name);
  });
  EXPECT_EQ(applying.size() + 5, metric_names().size());
  EXPECT_EQ(keys(summary["metrics"]), applying);
  EXPECT_TRUE(summary["metrics"]["impact_count"].is_number_integer());
  EXPECT_EQ(summary["metrics"]["peak_contact_force"].get<double>(), run.result.metrics.peak_contact_force);
}

// summary.json `spring_sizing` (docs/model.md §11) at the run's speed, on a
// harmonic rise and return of the shorter duration β = 120°: the closed form
// F₀ = max(0, h (m ω² π² / (2 β²) − k)) with P_min = 0.
TEST(SimulationOutput, SummarySizesTheSpringForTheRunsSpeedAsTheHarmonicClosedForm) {
  SceneConfig scene = test::cycloidal_cam_scene(1300.0);
  for (SegmentConfig& seg : scene.mechanism.cam.motion_law.segments)
    if (seg.law == SegmentLaw::cycloidal) seg.law = SegmentLaw::harmonic;
  scene.simulation.cycles = 1;
  scene.simulation.discard_cycles = 0;
  const SceneRun run(scene);
  const Json sizing = summary_json(run.scene, run.model, run.result)["spring_sizing"];
  const double omega = 1300.0 * std::numbers::pi / 30.0, beta = 2.0 * std::numbers::pi / 3.0;
  const double h = 0.02, m = 0.3, k = 5000.0;
  const double expected =
      std::max(0.0, h * (m * omega * omega * std::numbers::pi * std::numbers::pi / (2 * beta * beta) - k));
  ASSERT_GT(expected, 0.0);
  EXPECT_NEAR(sizing["required_preload"].get<double>(), expected, test::kConverged * expected);
  EXPECT_EQ(sizing["up_to_rpm"].get<double>(), 1300.0);
  EXPECT_EQ(sizing["min_contact_force"].get<double>(), 0.0);
}

TEST(SimulationOutput, SolverBlockEndsWithTerminationAndMessage) {
  const SceneRun run(test::cycloidal_cam_scene(700.0));
  const Json solver = summary_json(run.scene, run.model, run.result)["solver"];
  const std::vector<std::string> expected = {"method",
                                             "rtol",
                                             "atol",
                                             "steps",
                                             "rhs_evaluations",
                                             "events",
                                             "tracking_resets",
                                             "run_time_s",
                                             "error_estimate",
                                             "error_test_failures",
                                             "nonlinear_iterations",
                                             "jacobian_evaluations",
                                             "restarts",
                                             "tracking_projections",
                                             "flights",
                                             "flight_intervals",
                                             "tracking",
                                             "simulated_time_s",
                                             "evaluated_from_s",
                                             "termination",
                                             "message"};
  EXPECT_EQ(keys(solver), expected);
  EXPECT_EQ(solver["termination"], "converged");
  EXPECT_EQ(solver["message"], "");
}

TEST(SimulationOutput, FailedRunNamesItsTerminationInTheSummary) {
  SceneConfig scene = test::cycloidal_cam_scene(700.0);
  scene.integrator.max_steps = 20;
  const SceneRun run(scene);
  const Json solver = summary_json(run.scene, run.model, run.result)["solver"];
  EXPECT_EQ(solver["termination"], "step_budget");
  EXPECT_EQ(solver["message"], run.result.solver.message);
}

// ---------------------------------------------------------------- the spec's example

const std::string kSpecExample = std::string(CAMDYN_TEST_DATA_DIR) + "/spec/interface_simulate.json";

// The simulate example of docs/config.md, "Top level (every study)", leaves out the lift of its return: the
// follower goes back down by the rise before it. The same law with that lift
// written out gives the same run to the bit.
TEST(SpecExample, ReturnWithoutLiftEqualsTheExplicitOne) {
  const std::vector<std::string> shorter = {"simulation.cycles=2"};
  const SceneRun implicit(load_scene(kSpecExample, shorter));
  ASSERT_FALSE(implicit.scene.mechanism.cam.motion_law.segments[2].lift.has_value());
  std::vector<std::string> with_lift = shorter;
  with_lift.push_back("mechanism.cam.motion_law.segments[2].lift=0.02");
  const SceneRun explicit_lift(load_scene(kSpecExample, with_lift));
  ASSERT_TRUE(implicit.result.solver.converged()) << implicit.result.solver.message;
  EXPECT_EQ(metrics_json(implicit.result.metrics), metrics_json(explicit_lift.result.metrics));
  EXPECT_EQ(implicit.result.series.kinematic_position, explicit_lift.result.series.kinematic_position);
  EXPECT_EQ(implicit.result.series.contact_force, explicit_lift.result.series.contact_force);
}

TEST(SpecExample, UnequalExplicitReturnLiftIsAnInputError) {
  const SceneConfig scene = load_scene(kSpecExample, {"mechanism.cam.motion_law.segments[2].lift=0.019"});
  try {
    build_model(scene, kSpecExample);
    FAIL() << "a return of 19 mm after a rise of 20 mm was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lift mismatch"), std::string::npos) << e.what();
  }
}

TEST(SpecExample, ReturnWithoutLiftTakesTheRisesSinceTheLastReturn) {
  // Two lobes: rise 10 mm, return, rise 5 mm, return: each return goes back by its own rise.
  SceneConfig scene = load_scene(kSpecExample);
  auto& segments = scene.mechanism.cam.motion_law.segments;
  segments = {segments[0], segments[2], segments[0], segments[2]};
  for (std::size_t i = 0; i < 4; ++i) segments[i].end_deg = 90.0 * static_cast<double>(i + 1);
  segments[0].lift = 0.01;
  segments[2].lift = 0.005;
  const Model model = build_model(scene, "two lobes");
  EXPECT_NEAR(model.law->eval(std::numbers::pi / 2).s, 0.01, 1e-15);
  EXPECT_NEAR(model.law->eval(std::numbers::pi).s, 0.0, 1e-15);
  EXPECT_NEAR(model.law->eval(1.5 * std::numbers::pi).s, 0.005, 1e-15);
  // A return with nothing to go back down from names its lift.
  segments[1].lift = 0.01;
  segments[3].lift.reset();
  segments[2].type = SegmentType::dwell;
  segments[2].lift.reset();
  segments[2].law = SegmentLaw::none;
  try {
    build_model(scene, "no rise");
    FAIL() << "a return without a rise before it was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam.motion_law.segments[3].lift") << e.what();
  }
}

bool starts_with(const std::string& text, const std::string& head) { return text.rfind(head, 0) == 0; }

TEST(SimulationVerdict, BelowTheJumpSpeedStaysInContactWithItsMinimumForce) {
  const SceneRun run(test::cycloidal_cam_scene(700.0));
  ASSERT_EQ(run.result.metrics.separation_fraction, 0.0);
  const Verdict v = simulation_verdict(run.scene, run.model, run.result);
  EXPECT_EQ(v.tone, Verdict::Tone::good);
  EXPECT_TRUE(starts_with(v.headline, "stays in contact, minimum contact force " +
                                          format_number(run.result.metrics.min_contact_force, 4) + " N at "))
      << v.headline;
  ASSERT_FALSE(v.details.empty());
  EXPECT_NE(v.details.front().find("(this run is at 700 rpm)"), std::string::npos) << v.details.front();
}

TEST(SimulationVerdict, AboveTheJumpSpeedNamesLiftOffLandingAndJumpSpeed) {
  const SceneRun run(test::cycloidal_cam_scene(3000.0));
  ASSERT_GT(run.result.metrics.separation_fraction, 0.0);
  const Verdict v = simulation_verdict(run.scene, run.model, run.result);
  EXPECT_EQ(v.tone, Verdict::Tone::bad);
  // The first lift-off of the evaluated window and the landing after it.
  const auto& events = run.result.events;
  const auto lift_off = std::find_if(events.begin(), events.end(), [&](const ContactEvent& e) {
    return !e.onset && e.time >= run.result.evaluated_from;
  });
  ASSERT_NE(lift_off, events.end());
  const auto landing = std::find_if(lift_off, events.end(), [](const ContactEvent& e) { return e.onset; });
  ASSERT_NE(landing, events.end());
  const auto degrees = [](double a) { return format_number(std::fmod(a, 360.0), 4) + "°"; };
  EXPECT_TRUE(starts_with(v.headline, "separates at " + degrees(lift_off->cam_angle_deg) + ", lands at " +
                                          degrees(landing->cam_angle_deg) + " at " + format_number(landing->speed, 4) +
                                          " m/s; rigid-model jump speed "))
      << v.headline;
  EXPECT_NE(v.headline.find("(this run is at 3000 rpm)"), std::string::npos) << v.headline;
}

TEST(SimulationVerdict, DropTestSaysWhereItLandsAndNoCamSpeed) {
  const SceneRun run(test::drop_scene(ContactModel::hunt_crossley, 0.5));
  const Verdict v = simulation_verdict(run.scene, run.model, run.result);
  EXPECT_TRUE(starts_with(v.headline, "drop test: lands at t = ")) << v.headline;
  EXPECT_NE(v.headline.find("peak contact force " + format_number(run.result.metrics.peak_contact_force, 4) + " N"),
            std::string::npos)
      << v.headline;
  EXPECT_NE(v.headline.find("rebound"), std::string::npos) << v.headline;
  EXPECT_EQ(v.headline.find("rpm"), std::string::npos) << v.headline;
  for (const std::string& line : v.details) EXPECT_EQ(line.find("rpm"), std::string::npos) << line;
}

TEST(SimulationVerdict, ReportLeadsWithTheBannerAndEndsWithTheSolverTable) {
  const SceneRun run(test::cycloidal_cam_scene(3000.0));
  const Report report = simulation_report(run.scene, run.model, run.result);
  ASSERT_TRUE(report.verdict.has_value());
  ASSERT_FALSE(report.appendix.empty());
  EXPECT_EQ(report.appendix.back().title, "Solver");
  for (const Table& t : report.tables) EXPECT_NE(t.title, "Solver");
  // The last revolution on 0–360° with the lift-off and impact markers and the rigid-model force.
  ASSERT_FALSE(report.plots.empty());
  const Plot& motion = report.plots.front();
  ASSERT_TRUE(motion.xrange.has_value());
  EXPECT_EQ(*motion.xrange, std::make_pair(0.0, 360.0));
  const Plot& force = report.plots[1];
  std::vector<std::string> labels;
  for (const Series& s : force.series) labels.push_back(s.label);
  for (const char* label : {"contact force", "rigid model", "lift-off", "impact"})
    EXPECT_NE(std::find(labels.begin(), labels.end(), label), labels.end()) << label;
  for (const Series& s : force.series)
    for (double x : s.x)
      if (std::isfinite(x)) {
        EXPECT_GE(x, 0.0);
        EXPECT_LE(x, 360.0);
      }
}

/// The unit the report's metrics table gives `metric`.
std::string metric_unit_in_report(const std::string& kind, const std::string& metric) {
  const SceneRun run(test::follower_scene(kind, 1000.0));
  const Report report = simulation_report(run.scene, run.model, run.result);
  for (const Table& t : report.tables)
    for (const std::vector<std::string>& row : t.rows)
      if (t.columns.size() == 3 && row.front() == metric) return row[2];
  ADD_FAILURE() << "no metric " << metric;
  return "";
}

// The kinematic error is |q − s(θ)|: an arm's in rad; contact quantities stay m.
TEST(SimulationOutput, ArmsKinematicErrorIsInRad) {
  EXPECT_EQ(metric_unit_in_report("oscillating_roller", "max_kinematic_error"), "rad");
  EXPECT_EQ(metric_unit_in_report("oscillating_roller", "max_penetration"), "m");
  EXPECT_EQ(metric_unit_in_report("translating_roller", "max_kinematic_error"), "m");
}

// timeseries.csv holds the series exactly: every number reads back to the
// same double, column by column in column_names' order.
TEST(SimulationOutput, TimeSeriesCsvReadsBackToTheSameDoubles) {
  const SceneRun run(test::cycloidal_cam_scene(3000.0));
  const TimeSeries& ts = run.result.series;
  ASSERT_GT(ts.time.size(), 100u);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("camdyn-timeseries-" + std::to_string(::getpid()) + ".csv");
  write_timeseries_csv(path, ts);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::string header;
  for (const std::string& name : TimeSeries::column_names()) header += (header.empty() ? "" : ",") + name;
  EXPECT_EQ(line, header);
  const auto columns = ts.columns();
  std::size_t row = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(row, ts.time.size());
    const char* p = line.c_str();
    for (std::size_t c = 0; c < columns.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(p, &end);
      ASSERT_EQ(v, (*columns[c])[row]) << "row " << row << ", column " << c << ": " << line;
      ASSERT_EQ(*end, c + 1 < columns.size() ? ',' : '\0') << line;
      p = end + 1;
    }
    ++row;
  }
  EXPECT_EQ(row, ts.time.size());
  std::filesystem::remove(path);
}

// The whole-run plots are reduced per pixel column when drawn; the last
// revolution is drawn from every point.
TEST(SimulationOutput, LastRevolutionIsPlottedAtFullResolution) {
  SceneConfig scene = test::cycloidal_cam_scene(3000.0);
  scene.simulation.cycles = 12.0;
  scene.simulation.output_step_deg = 0.25;  // 1,441 points a revolution, 17,281 in all
  const SceneRun run(scene);
  const Report report = simulation_report(run.scene, run.model, run.result);
  int revolution = 0, whole = 0;
  for (const Plot& plot : report.plots) {
    if (starts_with(plot.title, "Last revolution")) {
      ++revolution;
      EXPECT_TRUE(plot.full_resolution) << plot.title;
      const std::vector<Series> drawn = plotted_series(plot);
      ASSERT_FALSE(drawn.empty());
      EXPECT_GE(drawn.front().x.size(), 1441u) << plot.title;
    } else if (starts_with(plot.title, "Whole run")) {
      ++whole;
      EXPECT_FALSE(plot.full_resolution) << plot.title;
      ASSERT_FALSE(plot.series.empty());
      EXPECT_EQ(plot.series.front().x.size(), run.result.series.time.size());
      for (const Series& s : plotted_series(plot)) EXPECT_LE(s.x.size(), 2 * kPlotColumns + 2) << plot.title;
    }
  }
  EXPECT_GE(revolution, 3);
  EXPECT_GE(whole, 1);
}

}  // namespace
}  // namespace camdyn
