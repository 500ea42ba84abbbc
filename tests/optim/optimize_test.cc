// The optimize study end to end, on budgets small enough for CI: the
// kinematic bound on the peak acceleration coefficient, constraint values
// recomputed from the optimised profile, invalid designs, parallel
// simulations, and the command line (files, `camdyn run optimized.json`
// reproducing result.json). The full studies run in optimize_slowtest.cc.
#include "optim/optimize/optimize.h"

#include <gtest/gtest.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize_config.h"
#include "optim/optimize/optimize_output.h"
#include "optim/simulation_pool.h"
#include "optimize_study_text.h"
#include "study/study.h"
#include "tolerance.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

// Same scene, same deterministic integration: only summation order could
// differ, and it does not; 1e-12 leaves room for nothing but that.
constexpr double kReproduced = 1e-12;

/// The quickstart mechanism (cycloidal rise/return, 20 mm) with cheap run settings.
std::string mechanism(double base_radius = 0.04, double roller = 0.01) {
  return R"("mechanism": {
    "cam": { "base_radius": )" +
         std::to_string(base_radius) + R"(, "rpm": 1000,
             "motion_law": "profiles/cycloidal_rise_return.json" },
    "follower": { "shape": { "type": "roller", "radius": )" +
         std::to_string(roller) + R"( }, "mass": 0.3,
                  "spring": { "stiffness": 5000, "preload": 40 } },
    "contact": { "stiffness": 1e10 } },
  "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1 },
  "integrator": { "rtol": 1e-6 })";
}

using test::read_text;

fs::path scratch(const std::string& name) { return test::scratch_dir("optimize_test", name); }

double relative(double a, double b) { return std::abs(a - b) / std::max({std::abs(a), std::abs(b), 1e-300}); }

// Acceptance: minimising the peak acceleration of a rest-to-rest spline rise
// gives C_a = a_max β²/h below the cycloidal 2π and the 3-4-5 10/√3, and
// never below 4 (constant acceleration, the lower bound for any rise).
TEST(Optimize, PeakAccelerationCoefficientBeatsClassicLawsAndRespectsTheBound) {
  Study s = study_from(R"({
    "mechanism": {
      "cam": { "base_radius": 0.05, "rpm": 300, "motion_law": { "segments": [
        { "type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.01 },
        { "type": "dwell", "end_deg": 150 },
        { "type": "return", "law": "cycloidal", "end_deg": 330, "lift": 0.01 },
        { "type": "dwell", "end_deg": 360 } ] } },
      "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": 1e10 } },
    "simulation": { "cycles": 2, "discard_cycles": 1 },
    "integrator": { "rtol": 1e-6 },
    "design": { "segments": ["rise"], "control_points": 8, "degree": 5 },
    "operating_rpm": [300],
    "objective": { "separation": 0, "peak_acceleration": 1 },
    "constraints": { "max_pressure_angle_deg": null },
    "optimizer": { "algorithm": "LN_BOBYQA", "max_evaluations": 400, "xtol_rel": 1e-5 } })");
  const OptimizeOutcome o = run_optimize(s.scene, s.config, "test.json");
  EXPECT_FALSE(o.loop_simulated);
  EXPECT_EQ(o.loop_simulations, 0);
  ASSERT_EQ(o.optimized.kinematics.segments.size(), 2u);
  const SegmentKinematics& rise = o.optimized.kinematics.segments[0];
  ASSERT_EQ(rise.type, "rise");
  // Coefficients are sampled peaks, 4000 points per piece: ≲ 1e-7 relative.
  constexpr double kSampledAcceleration = 1e-6;
  EXPECT_NEAR(o.baseline.kinematics.segments[0].acceleration_coefficient, 2.0 * std::numbers::pi, kSampledAcceleration);
  EXPECT_LT(rise.acceleration_coefficient, 10.0 / std::sqrt(3.0));  // 5.7735, the 3-4-5 polynomial
  EXPECT_GT(rise.acceleration_coefficient, 4.0);
  // The return (180° long) stays well below, so the rise sets the peak.
  EXPECT_NEAR(o.optimized.kinematics.peak_acceleration,
              rise.acceleration_coefficient * 0.01 / std::pow(2.0 * std::numbers::pi / 3.0, 2),
              test::kAmplifiedRoundoff);
  EXPECT_TRUE(o.optimized.feasible);
  EXPECT_LT(o.optimized.objective, 5.77 / (2.0 * std::numbers::pi));
}

// Acceptance: every constraint's reported value is what the geometry code and
// the simulator give for the optimised profile, recomputed from scratch.
TEST(Optimize, ConstraintValuesEqualTheValuesRecomputedFromTheOptimisedProfile) {
  Study s = study_from("{" + mechanism() + R"(,
    "design": { "segments": ["rise", "return"], "control_points": 5, "degree": 5 },
    "operating_rpm": [700, 900],
    "objective": { "separation": 0, "peak_acceleration": 1, "peak_contact_force": 0.5 },
    "constraints": { "max_pressure_angle_deg": 17, "min_radius_of_curvature": 0.006,
                     "max_peak_contact_force": 200, "min_contact_force": 5, "no_separation": true },
    "optimizer": { "algorithm": "LN_COBYLA", "max_evaluations": 30 } })");
  OptimizeOptions options;
  options.threads = 2;
  const OptimizeOutcome o = run_optimize(s.scene, s.config, "test.json", options);
  ASSERT_TRUE(o.optimized.valid);
  // The fifth, no separation at the speeds the rigid design holds, when it holds any.
  ASSERT_EQ(o.constraints.size(), o.proven_rpm.empty() ? 5u : 6u);

  const Model model = build_model(o.optimized_scene, "test.json");
  double peak = 0.0, lowest = INFINITY, fraction = 0.0, proven_fraction = 0.0;
  for (double rpm : s.config.operating_rpm) {
    SceneConfig at = o.optimized_scene;
    at.mechanism.cam.rpm = rpm;
    const Metrics m = simulate_scene(at, "test.json").metrics;
    peak = std::max(peak, m.peak_contact_force);
    lowest = std::min(lowest, m.min_contact_force);
    fraction = std::max(fraction, m.separation_fraction);
    if (std::count(o.proven_rpm.begin(), o.proven_rpm.end(), rpm) > 0)
      proven_fraction = std::max(proven_fraction, m.separation_fraction);
  }
  for (std::size_t i = 0; i < o.constraints.size(); ++i) {
    const ConstraintSpec& spec = o.constraints[i];
    const ConstraintValue& c = o.optimized.constraints[i];
    double expected = 0.0;
    if (spec.name == "max_pressure_angle_deg") expected = model.geometry.max_pressure_angle_deg;
    if (spec.name == "min_radius_of_curvature") expected = model.geometry.min_radius_of_curvature;
    if (spec.name == "max_peak_contact_force") expected = peak;
    if (spec.name == "min_contact_force") expected = lowest;
    if (spec.name == "no_separation") expected = fraction;
    if (spec.name == "no_separation_where_proven") expected = proven_fraction;
    if (spec.dynamic)
      EXPECT_LE(relative(c.value, expected), kReproduced) << spec.name << ": " << c.value << " vs " << expected;
    else
      EXPECT_EQ(c.value, expected) << spec.name;  // the same function on the same law
    const bool holds = spec.sense == ConstraintSpec::Sense::at_most    ? expected <= spec.limit
                       : spec.sense == ConstraintSpec::Sense::at_least ? expected >= spec.limit
                                                                       : expected == 0.0;
    EXPECT_EQ(c.holds, holds) << spec.name;
  }

  // The same values in result.json, and optimized.json is the scene evaluated.
  const fs::path dir = scratch("constraints");
  write_optimize_outputs(dir, o, "constraints", "test.json");
  const Json result = Json::parse(read_text(dir / "result.json"));
  for (std::size_t i = 0; i < o.constraints.size(); ++i) {
    const Json& c = result["optimized"]["constraints"][o.constraints[i].name];
    EXPECT_EQ(c["value"].get<double>(), o.optimized.constraints[i].value) << o.constraints[i].name;
    EXPECT_EQ(c["holds"].get<bool>(), o.optimized.constraints[i].holds);
  }
  const SceneConfig reloaded = load_scene((dir / "optimized.json").string());
  EXPECT_EQ(to_json(reloaded), to_json(o.optimized_scene));
  EXPECT_EQ(reloaded.mechanism.cam.rpm, 900.0);
  EXPECT_EQ(reloaded.study, "simulate");
}

// Undercut cams inside an evaluation are invalid designs, not a failed run.
TEST(Optimize, InvalidDesignsAreCountedAndReportedNotFatal) {
  Study s = study_from(R"({
    "mechanism": {
      "cam": { "base_radius": 0.02, "rpm": 300, "motion_law": { "segments": [
        { "type": "rise", "law": "cycloidal", "end_deg": 90, "lift": 0.02 },
        { "type": "dwell", "end_deg": 150 },
        { "type": "return", "law": "cycloidal", "end_deg": 300, "lift": 0.02 },
        { "type": "dwell", "end_deg": 360 } ] } },
      "follower": { "shape": { "type": "roller", "radius": 0.02 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": 1e10 } },
    "simulation": { "cycles": 2, "discard_cycles": 1 },
    "integrator": { "rtol": 1e-6 },
    "design": { "segments": ["rise"], "control_points": 6, "degree": 5 },
    "operating_rpm": [300],
    "objective": { "separation": 0, "peak_jerk": 1 },
    "constraints": { "max_pressure_angle_deg": null, "min_radius_of_curvature": 0.001 },
    "optimizer": { "algorithm": "GN_CRS2_LM", "max_evaluations": 40, "seed": 2 } })");
  const OptimizeOutcome o = run_optimize(s.scene, s.config, "test.json");
  EXPECT_GT(o.search.invalid_evaluations, 0);
  EXPECT_TRUE(o.optimized.valid);
  long invalid = 0;
  for (const HistoryRecord& h : o.history) {
    if (h.valid) continue;
    ++invalid;
    EXPECT_NE(h.error.find("undercut"), std::string::npos) << h.error;
    EXPECT_TRUE(std::isfinite(h.objective));
    EXPECT_FALSE(h.feasible);
  }
  EXPECT_EQ(invalid, o.search.invalid_evaluations);

  const fs::path dir = scratch("invalid");
  write_optimize_outputs(dir, o, "invalid", "test.json");  // throws on any NaN
  const std::string history = read_text(dir / "history.csv");
  EXPECT_EQ(history.substr(0, history.find('\n')),
            "evaluation,objective,min_radius_of_curvature,feasible,start,kind,valid,best_objective,error");
  EXPECT_NE(history.find(",1000,,0,0,nlopt,0,"), std::string::npos);  // empty constraint cell, invalid
  EXPECT_EQ(Json::parse(read_text(dir / "result.json"))["invalid_evaluations"].get<long>(),
            o.search.invalid_evaluations);
}

TEST(SimulationPool, ParallelRunsEqualSerialRuns) {
  const SceneConfig base = load_scene(std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json");
  std::vector<SceneConfig> scenes;
  for (double rpm : {800.0, 1100.0, 1300.0}) {
    SceneConfig s = base;
    s.mechanism.cam.rpm = rpm;
    s.simulation.cycles = 2.0;
    scenes.push_back(s);
  }
  scenes.push_back(scenes.front());
  scenes.back().mechanism.follower.shape.radius = 0.05;  // the worker's error, not the batch's
  scenes.back().mechanism.cam.base_radius = 0.002;
  SimulationOptions options;
  options.record_series = false;
  SimulationPool serial(1, "test.json"), parallel(3, "test.json");
  for (int round = 0; round < 2; ++round) {  // workers are reused
    const auto a = serial.run(scenes, options), b = parallel.run(scenes, options);
    ASSERT_EQ(a.size(), scenes.size());
    ASSERT_EQ(b.size(), scenes.size());
    for (std::size_t i = 0; i + 1 < scenes.size(); ++i) {
      ASSERT_EQ(a[i].status, SimulationOutcome::Status::ok) << a[i].error;
      ASSERT_EQ(b[i].status, SimulationOutcome::Status::ok) << b[i].error;
      EXPECT_EQ(a[i].result.metrics.peak_contact_force, b[i].result.metrics.peak_contact_force);
      EXPECT_EQ(a[i].result.metrics.separation_integral, b[i].result.metrics.separation_integral);
      EXPECT_EQ(a[i].result.solver.counters.steps, b[i].result.solver.counters.steps);
    }
    EXPECT_EQ(a.back().status, SimulationOutcome::Status::input_error);
    EXPECT_EQ(b.back().status, SimulationOutcome::Status::input_error);
  }
  EXPECT_EQ(parallel.simulations(), 8);
}

// ---------------------------------------------------------------- command line

using test::Outcome;

Outcome run_cli(const std::string& args) { return test::run_camdyn(test::split_args(args), scratch("io")); }

const std::string kJump = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_jump.json";

TEST(OptimizeCli, ValidatePrintsTheResolvedStudyAndNamesBadFields) {
  const Outcome ok = run_cli("validate " + kJump);
  ASSERT_EQ(ok.code, 0) << ok.err;
  const Json resolved = Json::parse(ok.out);
  EXPECT_EQ(resolved["study"], "optimize");
  EXPECT_EQ(resolved["optimizer"]["algorithm"], "LN_COBYLA");
  EXPECT_TRUE(resolved["optimizer"].contains("evaluation_rtol"));
  EXPECT_EQ(resolved["mechanism"]["cam"]["rpm"], 1300.0);  // defaults to the top operating speed
  EXPECT_EQ(resolved["design"]["control_points"], 6);

  const Outcome typo = run_cli("validate " + kJump + " --set design.control_point=4");
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.err.find("--set design.control_point=4: design.control_point"), std::string::npos) << typo.err;
  EXPECT_NE(typo.err.find("control_points"), std::string::npos) << typo.err;
  const Outcome range = run_cli("validate " + kJump + " --set optimizer.evaluation_cycles=1");
  EXPECT_EQ(range.code, 2);
  EXPECT_NE(range.err.find("optimizer.evaluation_cycles"), std::string::npos) << range.err;
  // 2e9 control points filled 4 GB before validate ended.
  const Outcome many = run_cli("validate " + kJump + " --set design.control_points=2000000000");
  EXPECT_EQ(many.code, 2);
  EXPECT_NE(many.err.find("design.control_points: must be at most 100 per segment"), std::string::npos) << many.err;
}

// Acceptance (reduced budget): the outputs exist, and `camdyn run
// optimized.json` reproduces the optimized metrics of result.json.
TEST(OptimizeCli, OptimizedConfigReproducesTheReportedMetrics) {
  const fs::path dir = scratch("jump");
  const Outcome run = run_cli("run " + kJump + " --out " + dir.string() +
                              " --jobs 2 --set optimizer.max_evaluations=12 --set simulation.cycles=2");
  ASSERT_EQ(run.code, 0) << run.err;
  for (const char* f : {"result.json", "history.csv", "optimized.json", "report.html"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  const Json result = Json::parse(read_text(dir / "result.json"));
  for (const char* key : {"evaluations", "run_time_s", "algorithm", "stop_reason", "baseline", "optimized"})
    EXPECT_TRUE(result.contains(key)) << key;
  EXPECT_EQ(result["evaluations"].get<long>(), 12);
  EXPECT_EQ(result["baseline"]["metrics"].size(), 3u);
  EXPECT_GT(result["baseline"]["metrics"][2]["separation_fraction"].get<double>(), 0.0);  // it jumps at 1300 rpm
  const std::string history = read_text(dir / "history.csv");
  const bool proven = !result["rigid_stage"]["proven_rpm"].empty();
  EXPECT_EQ(history.substr(0, history.find('\n')),
            std::string("evaluation,objective,max_pressure_angle_deg,min_radius_of_curvature,min_contact_force,"
                        "no_separation,") +
                (proven ? "no_separation_where_proven," : "") + "feasible,start,kind,valid,best_objective,error");
  EXPECT_EQ(std::count(history.begin(), history.end(), '\n'), 13);
  const std::size_t feasible_column = proven ? 7 : 6;

  // The loop's best objective is the verified objective of optimized.json to
  // within the integration tolerance and the window's own effect: the rigid
  // stage's design stays on the cam, so the metrics are periodic once the
  // start's transient has died out, and the loop's shorter window and looser
  // rtol (1e-7) change them only by the integration error, taken here as
  // 20 rtol relative, and by what is left of the transient, which the run
  // measures itself (window_check.relative_change: the objective over a
  // longer window).
  std::istringstream rows(history);
  std::string line;
  std::getline(rows, line);
  double loop_best = INFINITY;
  while (std::getline(rows, line)) {
    std::vector<std::string> cells;
    std::stringstream cs(line);
    for (std::string cell; std::getline(cs, cell, ',');) cells.push_back(cell);
    ASSERT_GT(cells.size(), feasible_column) << line;
    if (cells[feasible_column] == "1") loop_best = std::min(loop_best, std::stod(cells[1]));
  }
  const double verified = result["optimized"]["objective"]["value"].get<double>();
  const double window_change = result["window_check"]["relative_change"].get<double>();
  // (Only when the answer is the search's: the baseline or the rigid design may win.)
  if (result["chosen"] == "dynamic") {
    EXPECT_NEAR(loop_best, verified, (20.0 * 1e-7 + window_change) * std::abs(verified));
  }

  const fs::path rerun = dir / "rerun";
  const Outcome again = run_cli("run " + (dir / "optimized.json").string() + " --out " + rerun.string() + " --quiet");
  ASSERT_EQ(again.code, 0) << again.err;
  const Json summary = Json::parse(read_text(rerun / "summary.json"));
  const Json& top = result["optimized"]["metrics"][2];
  EXPECT_EQ(top["rpm"].get<double>(), 1300.0);
  for (const auto& [key, value] : summary["metrics"].items()) {
    ASSERT_TRUE(top.contains(key)) << key;
    if (value.is_null()) {
      EXPECT_TRUE(top[key].is_null()) << key;
      continue;
    }
    EXPECT_LE(relative(value.get<double>(), top[key].get<double>()), 1e-9) << key;
  }
}

// Acceptance of the rigid-model stage: with `objective: {separation: 1}`
// alone and no no_separation constraint, the design written to
// optimized.json, re-run at each operating speed, never leaves the cam; the
// certificate and the rigid jump speed are on stdout and in result.json.
TEST(OptimizeCli, SeparationObjectiveAloneGivesADesignThatStaysOnTheCam) {
  const fs::path dir = scratch("separation_only");
  const Outcome run =
      run_cli("run " + kJump + " --out " + dir.string() + " --jobs 2 --set optimizer.max_evaluations=16" +
              " --set objective={\"separation\":1} --set constraints.no_separation=false" +
              " --set constraints.min_contact_force=null");
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("certificate (rigid model"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("rigid-model jump speed"), std::string::npos) << run.out;
  const Json result = Json::parse(read_text(dir / "result.json"));
  const Json& cert = result["rigid_stage"]["certificate"];
  EXPECT_TRUE(cert["all_feasible"].get<bool>());
  EXPECT_GT(cert["family_jump_free_rpm"].get<double>(), 1300.0);
  EXPECT_LE(cert["family_jump_free_rpm"].get<double>(), cert["any_law_jump_free_rpm"].get<double>());
  // The design stays on the cam, so its motion is periodic once started: the
  // objective over a window twice as long is the same to within its tolerance.
  const Json& window = result["window_check"];
  ASSERT_TRUE(window["checked"].get<bool>()) << window.dump();
  EXPECT_TRUE(window["converged"].get<bool>()) << window.dump();
  EXPECT_LE(window["relative_change"].get<double>(), window["tolerance"].get<double>());
  // And it is the objective on the periodic steady state: at every speed the
  // window's end is on a stable orbit, whose metrics give the same objective.
  const Json& steady = window["steady_state"];
  ASSERT_TRUE(steady["checked"].get<bool>()) << steady.dump();
  EXPECT_EQ(steady["speeds_on_orbit"].get<int>(), 3) << steady.dump();
  EXPECT_TRUE(steady["agrees"].get<bool>()) << steady.dump();
  // optimized.json carries the study's geometric constraints as cam limits,
  // and `camdyn validate` re-checks them; a limit the cam breaks is refused.
  const Outcome valid = run_cli("validate " + (dir / "optimized.json").string());
  ASSERT_EQ(valid.code, 0) << valid.err;
  const Json limits = Json::parse(valid.out)["mechanism"]["cam"]["limits"];
  EXPECT_EQ(limits["max_pressure_angle_deg"].get<double>(), 30.0);
  EXPECT_EQ(limits["min_radius_of_curvature"].get<double>(), 0.006);
  const Outcome broken =
      run_cli("validate " + (dir / "optimized.json").string() + " --set mechanism.cam.limits.max_pressure_angle_deg=5");
  EXPECT_EQ(broken.code, 2);
  EXPECT_NE(broken.err.find("mechanism.cam.limits.max_pressure_angle_deg"), std::string::npos) << broken.err;
  for (const double rpm : {1000.0, 1150.0, 1300.0}) {
    const fs::path rerun = dir / ("rerun_" + std::to_string(static_cast<int>(rpm)));
    const Outcome again = run_cli("run " + (dir / "optimized.json").string() + " --out " + rerun.string() +
                                  " --quiet --set mechanism.cam.rpm=" + std::to_string(rpm));
    ASSERT_EQ(again.code, 0) << again.err;
    const Json m = Json::parse(read_text(rerun / "summary.json"))["metrics"];
    EXPECT_EQ(m["separation_fraction"].get<double>(), 0.0) << rpm;
    EXPECT_EQ(m["impact_count"].get<long>(), 0) << rpm;
    EXPECT_GT(m["jump_speed_rpm"].get<double>(), 1300.0) << rpm;
  }
}

// A target above the certificate's bound: reported infeasible with the bound,
// exit 0, and the best design is still written.
TEST(OptimizeCli, TargetAboveTheBoundIsReportedInfeasibleAndTheBestDesignWritten) {
  const fs::path dir = scratch("above_bound");
  const Outcome run = run_cli("run " + kJump + " --out " + dir.string() +
                              " --jobs 2 --set optimizer.max_evaluations=4 --set operating_rpm=[1000,2500]" +
                              " --set simulation.cycles=2 --set optimizer.evaluation_cycles=1.5");
  ASSERT_EQ(run.code, 0) << run.err;
  EXPECT_NE(run.out.find("2500 rpm: INFEASIBLE, above the family's bound"), std::string::npos) << run.out;
  const Json result = Json::parse(read_text(dir / "result.json"));
  const Json& cert = result["rigid_stage"]["certificate"];
  EXPECT_FALSE(cert["all_feasible"].get<bool>());
  EXPECT_TRUE(cert["speeds"][0]["feasible"].get<bool>());
  EXPECT_FALSE(cert["speeds"][1]["feasible"].get<bool>());
  EXPECT_LT(cert["any_law_jump_free_rpm"].get<double>(), 2500.0);
  EXPECT_TRUE(fs::exists(dir / "optimized.json"));
  EXPECT_TRUE(result["rigid_stage"]["design"]["made"].get<bool>());
  // Nothing can stay on the cam at 2500 rpm, so nothing meets no_separation:
  // the answer says so (red), and stdout never claims the constraints hold.
  EXPECT_EQ(result["verdict"], "bad");
  EXPECT_FALSE(result["candidates"][result["chosen"].get<std::string>()]["feasible"].get<bool>());
  EXPECT_EQ(run.out.find("constraints all hold"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("constraints VIOLATED"), std::string::npos) << run.out;
  EXPECT_NE(read_text(dir / "report.html").find("class=\"verdict bad\""), std::string::npos);
}

// Kill -9 part-way: history.csv, the best design so far and the journal are
// on disk and parse, and a re-run of the same study into the same folder
// replays the journal: the same search (tests/cli/kill_loop.py checks that
// the outputs equal an uninterrupted run's).
TEST(OptimizeCli, AKilledRunLeavesItsHistoryAndBestDesignAndARerunReplaysIt) {
  const fs::path dir = scratch("killed");
  const std::vector<std::string> argv = {CAMDYN_BINARY, "run", kJump,     "--out", (dir / "out").string(),
                                         "--jobs",      "2",   "--quiet", "--set", "optimizer.max_evaluations=60"};
  const pid_t pid = test::spawn(argv, dir / "first.out", dir / "first.err");
  ASSERT_GT(pid, 0);
  bool seen = false;
  for (int i = 0; i < 1200 && !seen; ++i) {  // up to 60 s for the first evaluations
    seen = fs::exists(dir / "out" / "best_design.json") && fs::exists(dir / "out" / "history.csv") &&
           read_text(dir / "out" / "journal.jsonl").find("\"kind\":\"evaluation\"") != std::string::npos;
    if (!seen) ::usleep(50000);
  }
  ::kill(pid, SIGKILL);
  EXPECT_EQ(test::wait_for(pid), 128 + SIGKILL) << read_text(dir / "first.err");
  ASSERT_TRUE(seen) << read_text(dir / "first.err");
  EXPECT_FALSE(fs::exists(dir / "out" / "result.json"));  // it did not finish

  std::istringstream history(read_text(dir / "out" / "history.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(history, line));
  EXPECT_EQ(line.rfind("evaluation,objective,", 0), 0u) << line;
  long rows = 0;
  while (std::getline(history, line)) {
    EXPECT_EQ(std::stol(line.substr(0, line.find(','))), ++rows) << line;
  }
  EXPECT_GE(rows, 1);
  const Json best = Json::parse(read_text(dir / "out" / "best_design.json"));
  EXPECT_EQ(best["study"], "simulate");
  const std::string journal = read_text(dir / "out" / "journal.jsonl");
  const std::string killed_history = read_text(dir / "out" / "history.csv");

  // The same study again: it replays the journal and completes; the history
  // of the killed run is the start of the re-run's (the same search).
  const Outcome again = test::run_camdyn(std::vector<std::string>(argv.begin() + 1, argv.end()), dir);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("replayed from the journal of an earlier run"), std::string::npos) << again.out;
  const Json result = Json::parse(read_text(dir / "out" / "result.json"));
  EXPECT_GE(result["resumed_evaluations"].get<long>(), 1);
  EXPECT_FALSE(fs::exists(dir / "out" / "best_design.json"));
  EXPECT_EQ(read_text(dir / "out" / "journal.jsonl").rfind(journal, 0), 0u) << "journal lines rewritten";
  EXPECT_EQ(read_text(dir / "out" / "history.csv").rfind(killed_history, 0), 0u) << "not the same search";
}

}  // namespace
}  // namespace camdyn::optim
