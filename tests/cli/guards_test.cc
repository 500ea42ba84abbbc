// Guards of the command line (docs/warnings.md): configs that used to run
// without end are refused quickly naming the field; unit slips are warned
// about or refused naming the real cause; untrustworthy results carry
// warnings in summary.json and on stdout, and --strict makes them exit 3.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;

using camdyn::test::Outcome;
using camdyn::test::read_text;

fs::path guards_dir(const std::string& name) { return camdyn::test::scratch_dir("guards_test", name); }

/// The interface's promise for a runaway config: it ends in under this [s].
constexpr double kRunawayDeadline = 10.0;

// Issue 19 items 5, 6 and 12: each ends in well under 10 s, exit 2, naming
// the field and the reason.
TEST(Guards, RunawayConfigsEndQuicklyNamingTheField) {
  const auto expected = nlohmann::json::parse(read_text(kTestData + "/runaway/expected.json"));
  int count = 0;
  for (const auto& [file, want] : expected["files"].items()) {
    const fs::path out = guards_dir("runaway") / file;
    const auto start = std::chrono::steady_clock::now();
    const Outcome o = camdyn::test::run_camdyn(
        {"run", kTestData + "/runaway/" + file, "--quiet", "--out", out.string()}, guards_dir("runaway_io"));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, kRunawayDeadline) << file;
    EXPECT_EQ(o.code, want["code"].get<int>()) << file << ": " << o.err;
    EXPECT_TRUE(contains(o.err, want["path"].get<std::string>())) << file << ": " << o.err;
    EXPECT_TRUE(contains(o.err, want["message"].get<std::string>())) << file << ": " << o.err;
    ++count;
  }
  EXPECT_GE(count, 6);
}

// Issue 17 item 4: each slip gives the warning (exit 0) or the error (exit 2)
// that names the field really at fault.
TEST(Guards, UnitSlipsNameTheRealCause) {
  const auto expected = nlohmann::json::parse(read_text(kTestData + "/unit_slip/expected.json"));
  int count = 0;
  for (const auto& [file, want] : expected["files"].items()) {
    const Outcome o = camdyn::test::run_camdyn({"validate", kTestData + "/unit_slip/" + file}, guards_dir("slip_io"));
    const std::string path = want["path"].get<std::string>();
    const std::string message = want["message"].get<std::string>();
    ASSERT_EQ(o.code, want["code"].get<int>()) << file << ": " << o.err;
    if (o.code == 2) {
      EXPECT_TRUE(contains(o.err, "camdyn: error: ")) << file << ": " << o.err;
      EXPECT_TRUE(contains(o.err, path + ": ")) << file << ": " << o.err;
      EXPECT_TRUE(contains(o.err, message)) << file << ": " << o.err;
    } else {
      const std::size_t at = o.err.find("warning: " + path + ": ");
      ASSERT_NE(at, std::string::npos) << file << ": " << o.err;
      const std::string line = o.err.substr(at, o.err.find('\n', at) - at);
      EXPECT_TRUE(contains(line, message)) << file << ": " << line;
    }
    ++count;
  }
  EXPECT_GE(count, 5);
}

TEST(Guards, ValidatePrintsTheDesignCheck) {
  const Outcome o = camdyn::test::run_camdyn({"validate", kStudies + "quickstart.json"}, guards_dir("design"));
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(contains(o.err, "design check: rigid-model jump speed 1174 rpm")) << o.err;
  EXPECT_TRUE(contains(o.err, "max pressure angle")) << o.err;
  EXPECT_TRUE(contains(o.err, "min radius of curvature")) << o.err;
  EXPECT_FALSE(contains(o.err, "warning:")) << o.err;
}

struct RunWithWarnings {
  Outcome outcome;
  nlohmann::json summary;
};

RunWithWarnings run_study(const std::string& name, const std::vector<std::string>& extra,
                          const std::string& study = "quickstart.json") {
  const fs::path out = guards_dir(name);
  std::vector<std::string> args = {"run", kStudies + study, "--quiet", "--out", out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  RunWithWarnings r;
  r.outcome = camdyn::test::run_camdyn(args, guards_dir(name + "_io"));
  const std::string text = read_text(out / "summary.json");
  if (!text.empty()) r.summary = nlohmann::json::parse(text);
  return r;
}

bool has_warning(const nlohmann::json& summary, const std::string& cause, const std::string& field) {
  for (const auto& w : summary["warnings"])
    if (w["cause"] == cause && w["field"] == field) return true;
  return false;
}

TEST(Guards, TrustworthyRunHasAnEmptyWarningList) {
  const RunWithWarnings r = run_study("clean", {"--strict"});
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.err;
  ASSERT_TRUE(r.summary.contains("warnings"));
  EXPECT_TRUE(r.summary["warnings"].is_array());
  EXPECT_TRUE(r.summary["warnings"].empty()) << r.summary["warnings"].dump(1);
  EXPECT_FALSE(contains(r.outcome.out, "warning:")) << r.outcome.out;
}

// Issue 19 item 11: the quickstart at rtol 1e-2, atol 1e-3 with its flights
// integrated (as the issue found it) chatters (about 17,000 impacts against
// 30) and its energy balance does not close. (Flights in closed form take
// the chatter away but not the energy error: the next test.)
TEST(Guards, LooseToleranceChatterIsWarnedAndStrictExitsThree) {
  const std::vector<std::string> loose = {
      "--set", "integrator.rtol=1e-2", "--set", "integrator.atol=1e-3", "--set", "integrator.flight=\"integrated\""};
  const RunWithWarnings r = run_study("loose", loose);
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.err;
  EXPECT_TRUE(has_warning(r.summary, "chatter", "integrator.rtol")) << r.summary["warnings"].dump(1);
  EXPECT_TRUE(has_warning(r.summary, "energy_residual", "integrator.rtol")) << r.summary["warnings"].dump(1);
  EXPECT_TRUE(has_warning(r.summary, "tolerance", "integrator.atol")) << r.summary["warnings"].dump(1);
  EXPECT_TRUE(contains(r.outcome.out, "warning: integrator.rtol: ")) << r.outcome.out;

  std::vector<std::string> strict = loose;
  strict.push_back("--strict");
  const RunWithWarnings s = run_study("loose_strict", strict);
  EXPECT_EQ(s.outcome.code, 3) << s.outcome.err;
  EXPECT_TRUE(contains(s.outcome.err, "--strict")) << s.outcome.err;
  EXPECT_FALSE(s.summary["warnings"].empty());  // the outputs are still written
}

// The same loose tolerances with the flights in closed form: no chatter, but
// the energy balance still does not close, and the run says so.
TEST(Guards, LooseToleranceWithClosedFormFlightsStillWarnsOfTheEnergy) {
  const RunWithWarnings r =
      run_study("loose_closed_form", {"--set", "integrator.rtol=1e-2", "--set", "integrator.atol=1e-3"});
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.err;
  EXPECT_TRUE(has_warning(r.summary, "energy_residual", "integrator.rtol")) << r.summary["warnings"].dump(1);
  EXPECT_TRUE(has_warning(r.summary, "tolerance", "integrator.atol")) << r.summary["warnings"].dump(1);
}

// Issue 19 item 11: the shaft drive at 1000 rpm, below its rigid-model jump
// speed, reports separation at rtol = atol = 1e-3 where the default gives none.
TEST(Guards, SeparationBelowTheJumpSpeedIsWarnedAsChatter) {
  const RunWithWarnings r = run_study("shaft", {"--set", "integrator.rtol=1e-3", "--set", "integrator.atol=1e-3"},
                                      "followers/shaft_drive.json");
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.err;
  ASSERT_GT(r.summary["metrics"]["impact_count"].get<long>(), 0);
  EXPECT_TRUE(has_warning(r.summary, "chatter", "integrator.rtol")) << r.summary["warnings"].dump(1);
  EXPECT_TRUE(contains(r.outcome.out, "below the rigid-model jump speed")) << r.outcome.out;
}

// Issue 19 item 11: K = 1e7 penetrates about 3 mm on a 20 mm lift.
TEST(Guards, SoftContactPenetrationIsWarnedNamingTheStiffness) {
  const RunWithWarnings r = run_study("soft", {"--set", "mechanism.contact.stiffness=1e7"});
  ASSERT_EQ(r.outcome.code, 0) << r.outcome.err;
  EXPECT_TRUE(has_warning(r.summary, "penetration", "mechanism.contact.stiffness")) << r.summary["warnings"].dump(1);
}

}  // namespace
