// The periodic study from the command line: its outputs (periodic.json with
// the orbit, its multipliers and impacts, the orbit as a simulate run's
// outputs, the report), what it prints while it searches, `validate`, and the
// errors of its own fields.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "cli_run.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

TEST(PeriodicStudy, WritesTheOrbitItsMultipliersAndAReport) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "run");
  const test::Outcome r = test::run_camdyn({"run", kBouncingBall, "--out", (dir / "out").string(), "--quiet"}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("period 1: Newton iteration 0, residual"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("period-1 orbit, stable"), std::string::npos) << r.out;
  const Json j = Json::parse(test::read_text(dir / "out" / "periodic.json"));
  EXPECT_EQ(j["motion"], "periodic");
  EXPECT_EQ(j["orbit"]["period"], 1);
  EXPECT_TRUE(j["orbit"]["stable"].get<bool>());
  EXPECT_EQ(j["orbit"]["floquet_multipliers"].size(), 2u);
  EXPECT_EQ(j["impacts"].size(), 1u);
  EXPECT_EQ(j["metrics_on"], "orbit");
  EXPECT_EQ(j["metrics"]["impact_count"], 1);
  EXPECT_TRUE(j["lyapunov"].is_null());
  for (const char* file : {"report.html", "orbit/summary.json", "orbit/timeseries.csv", "orbit/events.csv"})
    EXPECT_TRUE(fs::exists(dir / "out" / file)) << file;
}

TEST(PeriodicStudy, ValidatePrintsTheResolvedFields) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "validate");
  const test::Outcome r = test::run_camdyn({"validate", kBouncingBall}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(r.out);
  EXPECT_EQ(j["study"], "periodic");
  EXPECT_EQ(j["periodic"]["max_period"], 4);
  EXPECT_EQ(j["periodic"]["transient_revolutions"], 4);
}

TEST(PeriodicStudy, BadFieldsAreNamed) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "bad");
  const test::Outcome zero = test::run_camdyn({"validate", kBouncingBall, "--set", "periodic.max_period=0"}, dir);
  EXPECT_EQ(zero.code, 2);
  EXPECT_NE(zero.err.find("periodic.max_period"), std::string::npos) << zero.err;
  const test::Outcome typo = test::run_camdyn({"validate", kBouncingBall, "--set", "periodic.max_perod=3"}, dir);
  EXPECT_EQ(typo.code, 2);
  EXPECT_NE(typo.err.find("max_period"), std::string::npos) << typo.err;
}

// Each of these validated and asked for more work than the study could
// finish (2e9 periods tried, 2e9 revolutions): refused, naming the field.
TEST(PeriodicStudy, WorkBeyondTheBoundsIsRefusedByValidate) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "work");
  for (const char* set : {"periodic.max_period=65", "periodic.max_newton_iterations=2000000000",
                          "periodic.transient_revolutions=2000000000", "periodic.lyapunov_revolutions=100001"}) {
    const test::Outcome r = test::run_camdyn({"validate", kBouncingBall, "--set", set}, dir);
    EXPECT_EQ(r.code, 2) << set;
    const std::string field = std::string(set).substr(0, std::string(set).find('='));
    EXPECT_NE(r.err.find(field + ": "), std::string::npos) << r.err;
  }
  EXPECT_EQ(test::run_camdyn({"validate", kBouncingBall, "--set", "periodic.max_period=64"}, dir).code, 0);
}

TEST(PeriodicStudy, SimulateWithSteadyStateSaysWhatItsMetricsAreOver) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "steady_state");
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  const test::Outcome r = test::run_camdyn(
      {"run", quickstart, "--out", (dir / "out").string(), "--quiet", "--set", "simulation.steady_state=true"}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  // Found by shooting ("the stable period-1 orbit") or, when the run had
  // settled already, by one more revolution ("the period-1 orbit the run had settled on").
  EXPECT_NE(r.out.find("steady state: metrics over one period of the"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("period-1 orbit"), std::string::npos) << r.out;
  const Json j = Json::parse(test::read_text(dir / "out" / "summary.json"));
  EXPECT_EQ(j["metrics_over"], "periodic_orbit");
  EXPECT_EQ(j["config"]["simulation"]["steady_state"], true);
}

TEST(PeriodicStudy, SteadyStateOfAStillCamIsAnInputError) {
  const fs::path dir = test::scratch_dir("periodic_study_test", "still");
  const std::string quickstart = std::string(CAMDYN_SOURCE_DIR) + "/studies/quickstart.json";
  const test::Outcome r =
      test::run_camdyn({"validate", quickstart, "--set", "mechanism.cam.rpm=0", "--set",
                        R"(simulation={"duration": 0.1, "output_step": 0.001, "steady_state": true})"},
                       dir);
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("simulation.steady_state"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace camdyn
