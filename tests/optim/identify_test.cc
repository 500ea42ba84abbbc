// Contact identification (optim/identify/): config and data checks, the
// identifiability verdict, and the acceptance fits on the committed synthetic
// drop records of studies/identify_drop (made by its generate.py from known
// parameters plus 1 % noise). The cam-rig fit is in identify_slowtest.cc.
#include "optim/identify/identify.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/errors.h"
#include "dynamics/simulation.h"
#include "input_error_of.h"
#include "io/config.h"
#include "io/csv_reader.h"
#include "io/json_archive.h"
#include "optim/identify/identify_output.h"
#include "study_paths.h"
#include "tolerance.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

// The truth generate.py simulated the drop records with.
constexpr double kTrueStiffness = 2.5e9;  // [N/m^n]
constexpr double kTrueExponent = 1.45;
constexpr double kTrueRestitution = 0.7;

IdentifyProblem load_problem(const std::string& file, const std::vector<std::string>& overrides = {}) {
  const Json doc = load_config_json(file, overrides);
  return load_identify_problem(doc, config_source(file));
}

const ParameterEstimate& estimate(const IdentifyResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters)
    if (p.name == name) return p;
  throw std::out_of_range(name);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += x + "\n";
  return s;
}

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_identify_" + std::to_string(getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

int run_identify_cli(const std::string& args, const fs::path& dir, std::string* err = nullptr) {
  const test::Outcome o = test::run_camdyn(test::split_args(args), dir);
  if (err != nullptr) *err = o.err;
  return o.code;
}

/// The drop `truth` simulated, its contact force around the impact written
/// as a noise-free record (time,force_N) to `file`; with `scatter` [N], a
/// fixed normal scatter of that standard deviation is added (seed 1).
void write_clean_identify_record(const SceneConfig& truth, const fs::path& file, double scatter = 0.0) {
  const SimulationResult sim = simulate_scene(truth, "truth");
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::ofstream out(file);
  out.precision(17);
  out << "time,force_N\n";
  for (std::size_t i = 0; i < sim.series.time.size(); ++i) {
    if (sim.series.time[i] < 1e-4 || sim.series.time[i] > 5e-4) continue;  // around the impact
    out << sim.series.time[i] << "," << sim.series.contact_force[i] + scatter * noise(rng) << "\n";
  }
}

// ---------------------------------------------------------------- config

TEST(IdentifyConfig, UnknownSolverKeyIsSuggested) {
  const InputError e =
      test::input_error_of([] { load_problem(kIdentifyData + "single.json", {"solver.max_iteration=5"}); });
  EXPECT_EQ(e.path(), "solver.max_iteration");
  EXPECT_NE(e.reason().find("did you mean 'max_iterations'"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, MisspeltStudyKeyIsSuggested) {
  const InputError e = test::input_error_of([] { load_problem(kIdentifyData + "single.json", {"experiment=[]"}); });
  EXPECT_EQ(e.path(), "experiment");
  EXPECT_NE(e.reason().find("did you mean 'experiments'"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, ParameterMustBeANumericFieldOfTheScene) {
  InputError e = test::input_error_of(
      [] { load_problem(kIdentifyData + "single.json", {"parameters.contact.stifness.initial=1e9"}); });
  EXPECT_EQ(e.path(), "parameters.contact.stifness");
  EXPECT_NE(e.reason().find("did you mean 'stiffness'"), std::string::npos) << e.what();
  e = test::input_error_of([] { load_problem(kIdentifyData + "single.json", {"parameters.contact.model.initial=1"}); });
  EXPECT_NE(e.reason().find("not a numeric field"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, BoundsAreChecked) {
  InputError e = test::input_error_of(
      [] { load_problem(kIdentifyData + "single.json", {"parameters.contact.stiffness.lower=-1"}); });
  EXPECT_EQ(e.path(), "parameters.contact.stiffness.lower");  // log scale needs > 0
  e = test::input_error_of(
      [] { load_problem(kIdentifyData + "single.json", {"parameters.contact.stiffness.upper=1e6"}); });
  EXPECT_EQ(e.path(), "parameters.contact.stiffness.upper");  // below lower
  // A bound the scene itself rejects is caught before the solver can step onto it.
  e = test::input_error_of([] {
    load_problem(kIdentifyData + "single.json",
                 {"parameters.contact.restitution.initial=0.5", "parameters.contact.restitution.upper=1.5"});
  });
  EXPECT_EQ(e.path(), "parameters.contact.restitution.upper");
  EXPECT_NE(e.reason().find("restitution"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, ReferenceSignalsAreTimeseriesColumns) {
  const InputError e = test::input_error_of(
      [] { load_problem(kIdentifyData + "single.json", {"reference.signals={\"contact_forse\": \"force_N\"}"}); });
  EXPECT_EQ(e.path(), "reference.signals.contact_forse");
  EXPECT_NE(e.reason().find("did you mean 'contact_force'"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, ReferenceAndExperimentsExcludeEachOther) {
  const InputError e = test::input_error_of([] {
    load_problem(
        kIdentifyData + "single.json",
        {"experiments=[{\"reference\": {\"file\": \"good.csv\", \"signals\": {\"contact_force\": \"force_N\"}}}]"});
  });
  EXPECT_NE(e.reason().find("exactly one of 'reference'"), std::string::npos) << e.what();
}

TEST(IdentifyConfig, ExperimentCannotSetASharedParameter) {
  const InputError e = test::input_error_of(
      [] { load_problem(kDropStudy + "identify_drop.json", {"experiments[0].set.contact.stiffness=1e9"}); });
  EXPECT_EQ(e.path(), "experiments[0].set.contact.stiffness");
}

TEST(IdentifyConfig, SetOverridesParameterFieldsByDottedPath) {
  // --set parameters.contact.stiffness.initial=... arrives nested; it refines the entry.
  const IdentifyProblem p = load_problem(kIdentifyData + "single.json", {"parameters.contact.stiffness.initial=3e9"});
  ASSERT_EQ(p.parameters.size(), 1u);
  EXPECT_EQ(p.parameters[0].path, "mechanism.contact.stiffness");
  EXPECT_DOUBLE_EQ(p.parameters[0].initial, 3e9);
  EXPECT_DOUBLE_EQ(p.parameters[0].lower, 1e7);
  EXPECT_TRUE(p.parameters[0].log_scale);
}

TEST(IdentifyConfig, ExperimentsGetTheirOwnScenes) {
  const IdentifyProblem p = load_problem(kDropStudy + "identify_drop.json");
  ASSERT_EQ(p.experiments.size(), 4u);
  EXPECT_DOUBLE_EQ(p.experiments[0].scene.mechanism.follower.initial.velocity, -0.313209);
  EXPECT_DOUBLE_EQ(p.experiments[3].scene.mechanism.follower.initial.velocity, -2.50567);
  EXPECT_EQ(p.parameters.size(), 3u);
  EXPECT_GT(p.residual_count(), 3000u);
}

// ---------------------------------------------------------------- data

struct BadRecord {
  std::string file, where, reason;
};

class IdentifyBadData : public ::testing::TestWithParam<BadRecord> {};

TEST_P(IdentifyBadData, IsAnInputErrorNamingFileAndLine) {
  const BadRecord& bad = GetParam();
  const InputError e =
      test::input_error_of([&] { load_problem(kIdentifyData + "single.json", {"reference.file=" + bad.file}); });
  EXPECT_NE(e.file().find(bad.file), std::string::npos) << e.what();
  EXPECT_EQ(e.path(), bad.where) << e.what();
  EXPECT_NE(e.reason().find(bad.reason), std::string::npos) << e.what();
}

INSTANTIATE_TEST_SUITE_P(
    IdentifyRecords, IdentifyBadData,
    ::testing::Values(BadRecord{"missing_column.csv", "column force_N", "not in the header (line 2"},
                      BadRecord{"non_monotone.csv", "line 12", "must increase"},
                      BadRecord{"nan.csv", "line 8", "not finite"}, BadRecord{"too_few.csv", "line 8", "at least 10"},
                      BadRecord{"beyond_run.csv", "line 6", "after the end of the simulated run"},
                      BadRecord{"no_such_file.csv", "reference.file", "cannot open"}),
    [](const ::testing::TestParamInfo<BadRecord>& record) {
      return record.param.file.substr(0, record.param.file.find('.'));
    });

TEST(IdentifyData, BadRecordOnTheCommandLineExitsWithTwoNamingFileAndLine) {
  const fs::path dir = temp_dir("cli_bad");
  std::string err;
  EXPECT_EQ(run_identify_cli(
                "run " + kIdentifyData + "single.json --set reference.file=nan.csv --out " + (dir / "out").string(),
                dir, &err),
            2);
  EXPECT_NE(err.find("nan.csv: line 8"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(dir / "out" / "identified.json"));
  fs::remove_all(dir);
}

TEST(IdentifyData, DefaultWeightIsOneOverTheSignalRms) {
  const IdentifyProblem p = load_problem(kIdentifyData + "single.json");
  const MeasuredRecord& rec = p.experiments[0].record;
  const CsvColumns csv = read_csv(kIdentifyData + "good.csv", {"force_N"});
  double sum2 = 0.0;
  for (double f : csv.values[0]) sum2 += f * f;
  EXPECT_NEAR(rec.weights[0], 1.0 / std::sqrt(sum2 / static_cast<double>(csv.rows())), test::kAmplifiedRoundoff);
}

TEST(IdentifyData, NoiseEstimateOfWhiteNoiseOnASmoothSignal) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::vector<double> y(4000);
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = 100.0 * std::sin(1e-3 * static_cast<double>(i)) + noise(rng);
  // Robust scale estimate from 4000 samples: a few per cent (standard error
  // ≈ 2.5 %), allowed four times over.
  constexpr double kScaleEstimate = 0.1;  // relative
  EXPECT_NEAR(estimate_noise(y), 0.5, kScaleEstimate * 0.5);
}

// ---------------------------------------------------------------- fits

TEST(IdentifyFit, NoiseFreeRecordIsRecoveredToTheSolverTolerance) {
  // A record simulated here with known values, without noise: the fit must
  // return them to far better than any statistical tolerance, which checks
  // the residuals, the finite-difference Jacobian and the parameter transforms.
  const fs::path dir = temp_dir("noise_free");
  SceneConfig truth = load_scene(kDropStudy + "rig.json");
  truth.mechanism.contact.stiffness = 3e9;
  truth.mechanism.contact.exponent = 1.4;
  write_clean_identify_record(truth, dir / "clean.csv");
  const IdentifyProblem p =
      load_problem(kIdentifyData + "single.json",
                   {"reference.file=" + (dir / "clean.csv").string(),
                    "parameters.contact.exponent={\"initial\": 1.5, \"lower\": 1.0, \"upper\": 2.5}"});
  IdentifyOptions opt;
  opt.threads = 2;
  const IdentifyResult r = identify(p, opt);
  // Noise-free data: the fit lands on the truth up to the optimizer's stopping
  // tolerance (the stiffness, with the weaker gradient, the less sharply).
  constexpr double kCleanStiffness = 1e-4, kCleanExponent = 1e-5;  // relative, absolute
  EXPECT_NEAR(estimate(r, "contact.stiffness").value / 3e9 - 1.0, 0.0, kCleanStiffness);
  EXPECT_NEAR(estimate(r, "contact.exponent").value, 1.4, kCleanExponent);
  EXPECT_LT(r.rms_residual, 1e-5);
  fs::remove_all(dir);
}

// solver.differences: the iterations' Jacobian by central differences (2p + 1
// simulations a point) instead of forward (p + 1) lands on the same optimum
// to the solver's tolerance, with fewer simulations forward. The record has a
// small fixed scatter (1 mN on a peak force of 945 N): on a record the fit
// reproduces to the last bit, the standard errors would measure only how
// near each fit stopped to the truth.
TEST(IdentifyFit, ForwardAndCentralDifferencesLandOnTheSameOptimum) {
  const fs::path dir = temp_dir("differences");
  SceneConfig truth = load_scene(kDropStudy + "rig.json");
  truth.mechanism.contact.stiffness = 3e9;
  write_clean_identify_record(truth, dir / "clean.csv", 1e-3);
  const std::string record = "reference.file=" + (dir / "clean.csv").string();
  IdentifyOptions opt;
  opt.threads = 2;
  const IdentifyResult forward = identify(load_problem(kIdentifyData + "single.json", {record}), opt);
  const IdentifyResult central =
      identify(load_problem(kIdentifyData + "single.json", {record, "solver.differences=central"}), opt);
  EXPECT_NEAR(estimate(forward, "contact.stiffness").value / 3e9 - 1.0, 0.0, 1e-4);
  EXPECT_NEAR(estimate(central, "contact.stiffness").value / 3e9 - 1.0, 0.0, 1e-4);
  // The covariance is by central differences in both.
  EXPECT_NEAR(*estimate(forward, "contact.stiffness").std_error / *estimate(central, "contact.stiffness").std_error,
              1.0, 1e-2);
  EXPECT_LT(forward.simulations, central.simulations);
  fs::remove_all(dir);
}

// A continuation stage starts where the last one stopped, so its first
// residuals and Jacobian (the centre and 2p difference points) were simulated
// already; the optimum's covariance and final check are there too. Those runs
// are reused, not simulated again, and the fit is the same fit.
TEST(IdentifyFit, PointsSimulatedBeforeAreReusedAcrossStages) {
  const fs::path dir = temp_dir("reuse");
  SceneConfig truth = load_scene(kDropStudy + "rig.json");
  truth.mechanism.contact.stiffness = 3e9;
  write_clean_identify_record(truth, dir / "clean.csv");
  const IdentifyProblem p = load_problem(kIdentifyData + "single.json",
                                         {"reference.file=" + (dir / "clean.csv").string(), "solver.smoothing=[2e-5]"});
  const IdentifyResult r = identify(p, IdentifyOptions{});
  const long points_per_jacobian = 2 * static_cast<long>(p.parameters.size()) + 1;
  EXPECT_GE(r.reused_points, points_per_jacobian);  // at least the second stage's start
  // Noise-free data: the truth up to the optimizer's stopping tolerance, as in the fit above.
  constexpr double kCleanStiffness = 1e-4;  // relative
  EXPECT_NEAR(estimate(r, "contact.stiffness").value / 3e9 - 1.0, 0.0, kCleanStiffness);
  fs::remove_all(dir);
}

/// The four-drop study, run once through the command line as a user would.
class IdentifyDropStudy : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = temp_dir("drop_study");
    exit_code_ =
        run_identify_cli("run " + kDropStudy + "identify_drop.json --quiet --out " + (dir_ / "out").string(), dir_);
    if (exit_code_ == 0) identified_ = read_json_file((dir_ / "out" / "identified.json").string());
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static double value(const std::string& name) { return identified_["parameters"][name]["value"].get<double>(); }
  static double std_error(const std::string& name) {
    return identified_["parameters"][name]["std_error"].get<double>();
  }

  static inline fs::path dir_;
  static inline int exit_code_ = -1;
  static inline Json identified_;
};

TEST_F(IdentifyDropStudy, RecoversStiffnessExponentAndRestitutionWithinTwoPercent) {
  ASSERT_EQ(exit_code_, 0);
  const std::vector<std::pair<std::string, double>> truth = {{"contact.stiffness", kTrueStiffness},
                                                             {"contact.exponent", kTrueExponent},
                                                             {"contact.restitution", kTrueRestitution}};
  constexpr double kTwoPercent = 0.02;  // the acceptance of the drop-test identification
  for (const auto& [name, true_value] : truth) {
    SCOPED_TRACE(name);
    EXPECT_NEAR(value(name) / true_value - 1.0, 0.0, kTwoPercent);
    // The reported uncertainty is honest: the truth lies within three standard errors.
    EXPECT_LT(std::abs(value(name) - true_value), 3.0 * std_error(name));
  }
  EXPECT_TRUE(identified_["identifiable"].get<bool>()) << identified_["warnings"].dump();
  EXPECT_EQ(identified_["termination"], "CONVERGENCE");
}

TEST_F(IdentifyDropStudy, WritesTheContractOutputs) {
  ASSERT_EQ(exit_code_, 0);
  const fs::path out = dir_ / "out";
  for (const char* key : {"final_cost", "rms_residual", "iterations", "termination", "run_time_s", "identifiable",
                          "warnings", "correlation"})
    EXPECT_TRUE(identified_.contains(key)) << key;
  for (const auto& [name, p] : identified_["parameters"].items())
    for (const char* key : {"value", "std_error", "lower", "upper"}) EXPECT_TRUE(p.contains(key)) << name << "." << key;
  const Json& corr = identified_["correlation"]["matrix"];
  ASSERT_EQ(corr.size(), 3u);
  EXPECT_DOUBLE_EQ(corr[0][0].get<double>(), 1.0);
  EXPECT_LT(std::abs(corr[0][1].get<double>()), 1.0);

  // fit.csv: time, experiment, measured and fitted signal, every row numeric.
  const CsvColumns fit =
      read_csv((out / "fit.csv").string(), {"time", "contact_force_measured", "contact_force_fitted"});
  EXPECT_GT(fit.rows(), 3000u);
  EXPECT_TRUE(fs::exists(out / "report.html"));
  std::ifstream report(out / "report.html");
  const std::string html((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("Identified parameters"), std::string::npos);
  EXPECT_NE(html.find("<svg"), std::string::npos);

  // identified_scene.json is a simulate config with the identified values that `camdyn run` accepts.
  const SceneConfig scene = load_scene((out / "identified_scene.json").string());
  EXPECT_DOUBLE_EQ(*scene.mechanism.contact.stiffness, value("contact.stiffness"));
  EXPECT_DOUBLE_EQ(scene.mechanism.contact.exponent, value("contact.exponent"));
  EXPECT_EQ(
      run_identify_cli(
          "run " + (out / "identified_scene.json").string() + " --quiet --out " + (dir_ / "rerun").string(), dir_),
      0);
}

TEST_F(IdentifyDropStudy, ConvergesToTheSameAnswerFromTenfoldStiffnessAndLowRestitution) {
  ASSERT_EQ(exit_code_, 0);
  IdentifyOptions opt;
  opt.threads = 2;
  const IdentifyResult far = identify(load_problem(kDropStudy + "identify_drop.json",
                                                   {"parameters.contact.stiffness.initial=2.5e10",   // 10 × the truth
                                                    "parameters.contact.restitution.initial=0.4"}),  // 0.3 below it
                                      opt);
  for (const char* name : {"contact.stiffness", "contact.exponent", "contact.restitution"}) {
    SCOPED_TRACE(name);
    // The same optimum as from the study's start (1e9, 1.5, 0.8): they differ by
    // the solver tolerance, far less than one standard error.
    EXPECT_LT(std::abs(estimate(far, name).value - value(name)), 0.05 * std_error(name));
  }
  EXPECT_EQ(far.termination, "CONVERGENCE");
}

TEST(IdentifyFit, StiffnessAndExponentFromOneCoarseLowSpeedDropAreNotIdentifiable) {
  const IdentifyResult r = identify(load_problem(kDropStudy + "identify_single_drop.json"), {2, {}});
  EXPECT_FALSE(r.identifiable);
  const std::string warnings = joined(r.warnings);
  EXPECT_NE(warnings.find("not identifiable"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("contact.stiffness"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("contact.exponent"), std::string::npos) << warnings;
  const ParameterEstimate& k = estimate(r, "contact.stiffness");
  EXPECT_FALSE(k.identifiable);
  // Not a confident wrong answer: the uncertainty covers the truth.
  ASSERT_TRUE(k.std_error);
  EXPECT_GT(*k.std_error / k.value, 0.1);
  EXPECT_LT(std::abs(k.value - kTrueStiffness), 3.0 * *k.std_error);
}

TEST(IdentifyFit, ParameterWithoutEffectIsNotIdentifiableAndHasNoStdError) {
  // The restitution damping uses the approach speed (0.31 m/s), not the
  // 0.01 m/s floor: reference_velocity has no effect on this drop.
  const IdentifyProblem p =
      load_problem(kIdentifyData + "single.json",
                   {"reference.file=" + kDropStudy + "drop_h005.csv", "mechanism.follower.initial.velocity=-0.313209",
                    "mechanism.contact.exponent=1.45", "mechanism.contact.restitution=0.7",
                    "parameters.contact.reference_velocity={\"initial\": 0.01, \"lower\": 0.001, \"upper\": 0.1}"});
  const IdentifyResult r = identify(p, {2, {}});
  EXPECT_FALSE(r.identifiable);
  const ParameterEstimate& v = estimate(r, "contact.reference_velocity");
  EXPECT_FALSE(v.identifiable);
  EXPECT_FALSE(v.std_error.has_value());
  EXPECT_NE(joined(r.warnings).find("contact.reference_velocity has no effect"), std::string::npos)
      << joined(r.warnings);
  EXPECT_TRUE(estimate(r, "contact.stiffness").std_error.has_value());
  // No NaN reaches identified.json: the undefined standard error and its correlations are null.
  const Json j = identified_json(p, r, Json::object());
  EXPECT_TRUE(j["parameters"]["contact.reference_velocity"]["std_error"].is_null());
  EXPECT_TRUE(j["correlation"]["matrix"][0][1].is_null());
}

TEST(IdentifyFit, RobustLossResistsOutliers) {
  // The 20 mm record with gross outliers in the impact (sensor glitches of
  // 40 % of the peak force on every 8th sample above 200 N).
  const fs::path dir = temp_dir("outliers");
  {
    std::ifstream in(kDropStudy + "drop_h020.csv");
    std::ofstream out(dir / "glitchy.csv");
    std::string line;
    int row = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#' || line[0] == 't') {
        out << line << "\n";
        continue;
      }
      const std::size_t comma = line.find(',');
      const double force = std::stod(line.substr(comma + 1));
      if (force > 200.0 && ++row % 8 == 0) {
        out << line.substr(0, comma) << "," << force - 400.0 << "\n";
      } else {
        out << line << "\n";
      }
    }
  }
  const std::vector<std::string> base = {"reference.file=" + (dir / "glitchy.csv").string(),
                                         "mechanism.follower.initial.velocity=-0.626418",
                                         "mechanism.contact.exponent=1.45", "mechanism.contact.restitution=0.7"};
  std::vector<std::string> robust = base;
  robust.push_back("solver.loss=cauchy");
  const IdentifyResult plain = identify(load_problem(kIdentifyData + "single.json", base), {2, {}});
  const IdentifyResult cauchy = identify(load_problem(kIdentifyData + "single.json", robust), {2, {}});
  const double plain_error = std::abs(estimate(plain, "contact.stiffness").value / kTrueStiffness - 1.0);
  const double cauchy_error = std::abs(estimate(cauchy, "contact.stiffness").value / kTrueStiffness - 1.0);
  EXPECT_LT(cauchy_error, 0.5 * plain_error);
  EXPECT_LT(cauchy_error, 0.01);
  EXPECT_GT(cauchy.loss_scale, 0.0);
  fs::remove_all(dir);
}

TEST(IdentifyFit, IntegratorFailureIsANumericalError) {
  const IdentifyProblem p = load_problem(kIdentifyData + "single.json", {"integrator.max_steps=20"});
  EXPECT_THROW(identify(p, {1, {}}), NumericalError);
}

TEST(IdentifyStudy, ValidateChecksRecordsAndPrintsTheResolvedConfig) {
  const fs::path dir = temp_dir("validate");
  EXPECT_EQ(run_identify_cli("validate " + kDropStudy + "identify_drop.json", dir), 0);
  const Json resolved = read_json_file((dir / "camdyn.out").string());
  EXPECT_EQ(resolved["study"], "identify");
  EXPECT_EQ(resolved["experiments"].size(), 4u);
  EXPECT_DOUBLE_EQ(resolved["solver"]["fd_relative_step"].get<double>(), 1e-4);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace camdyn::optim
