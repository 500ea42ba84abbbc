// The camdyn command line end to end: exit codes, messages naming file and
// field, outputs written (docs/config.md).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "scene/study_kind.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;

using camdyn::test::Outcome;
using camdyn::test::read_text;

fs::path cli_dir(const std::string& name) { return camdyn::test::scratch_dir("cli_test", name); }

Outcome run_cli(const std::string& args) {
  return camdyn::test::run_camdyn(camdyn::test::split_args(args), cli_dir("io"));
}

TEST(Cli, VersionAndHelpSucceed) {
  EXPECT_EQ(run_cli("--version").code, 0);
  EXPECT_NE(run_cli("--version").out.find("camdyn"), std::string::npos);
  EXPECT_EQ(run_cli("--help").code, 0);
  EXPECT_EQ(run_cli("run --help").code, 0);
}

TEST(Cli, UsageErrorIsExitTwo) {
  EXPECT_EQ(run_cli("").code, 2);
  EXPECT_EQ(run_cli("run").code, 2);
  EXPECT_EQ(run_cli("frobnicate x.json").code, 2);
  // An empty --out used to write into the default folder silently.
  const Outcome empty_out = camdyn::test::run_camdyn({"run", kQuickstart, "--out", ""}, cli_dir("empty_out"));
  EXPECT_EQ(empty_out.code, 2);
  EXPECT_NE(empty_out.err.find("--out: the folder name is empty"), std::string::npos) << empty_out.err;
}

// Every bad config of the corpus: exit 2, the file and the field named.
TEST(Cli, BadConfigCorpusGivesExitTwoNamingFileAndField) {
  const auto expected = nlohmann::json::parse(read_text(kTestData + "/bad_configs/expected.json"));
  int count = 0;
  for (const auto& [file, want] : expected["files"].items()) {
    const std::string path = kTestData + "/bad_configs/" + file;
    const Outcome o = run_cli("validate " + path);
    EXPECT_EQ(o.code, 2) << file << ": " << o.err;
    EXPECT_NE(o.err.find(want["path"].get<std::string>()), std::string::npos) << file << ": " << o.err;
    EXPECT_NE(o.err.find(".json"), std::string::npos) << file << " (file not named): " << o.err;
    if (want.contains("message")) {
      EXPECT_NE(o.err.find(want["message"].get<std::string>()), std::string::npos) << file << ": " << o.err;
    }
    ++count;
  }
  EXPECT_GE(count, 15);
}

TEST(Cli, GeometryErrorsNameTheCamAngle) {
  const Outcome o = run_cli("validate " + kTestData + "/bad_configs/undercut.json");
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("at cam angle"), std::string::npos) << o.err;
}

TEST(Cli, MissingConfigFileIsExitTwo) {
  const Outcome o = run_cli("run /nonexistent/scene.json");
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("/nonexistent/scene.json"), std::string::npos) << o.err;
}

TEST(Cli, ValidatePrintsTheResolvedConfig) {
  const Outcome o = run_cli("validate " + kQuickstart + " --set mechanism.cam.rpm=900");
  ASSERT_EQ(o.code, 0) << o.err;
  const auto resolved = nlohmann::json::parse(o.out);
  EXPECT_EQ(resolved["mechanism"]["cam"]["rpm"].get<double>(), 900.0);
  EXPECT_TRUE(resolved["mechanism"]["cam"]["motion_law"].contains("segments"));  // profile inlined
  EXPECT_TRUE(resolved["integrator"].contains("max_steps"));                     // defaults filled in
}

TEST(Cli, RunWritesEveryOutputWithoutNaN) {
  const fs::path out = cli_dir("run");
  const Outcome o = run_cli("run " + kQuickstart + " --quiet --out " + out.string() +
                            " --set simulation.cycles=2 --set mechanism.contact.tracking=newton");
  ASSERT_EQ(o.code, 0) << o.err;
  for (const char* f : {"summary.json", "timeseries.csv", "events.csv", "report.html"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << "temporary file left: " << entry.path();

  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  for (const char* key : {"separation_fraction", "max_separation_gap", "impact_count", "max_impact_velocity",
                          "peak_contact_force", "min_contact_force", "max_penetration", "max_kinematic_error",
                          "energy_residual", "max_pressure_angle_deg", "min_radius_of_curvature", "jump_speed_rpm"})
    EXPECT_TRUE(summary["metrics"].contains(key)) << key;
  for (const char* key :
       {"method", "rtol", "atol", "steps", "rhs_evaluations", "events", "tracking_resets", "run_time_s"})
    EXPECT_TRUE(summary["solver"].contains(key)) << key;
  EXPECT_EQ(summary["model"]["state_size"].get<int>(), 2);  // newton tracking, frictionless: y, ẏ only
  EXPECT_GT(summary["metrics"]["separation_fraction"].get<double>(), 0.0);  // quickstart runs above jump speed

  std::ifstream csv(out / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "time,cam_angle_deg,follower_position,follower_velocity,follower_acceleration,kinematic_position,gap,"
            "contact_force,friction_force,energy_residual,contact_offset,cam_speed_rpm");
  std::string line;
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
    EXPECT_EQ(line.find("inf"), std::string::npos) << line;
  }
  EXPECT_EQ(rows, 2 * 360 * 4 + 1);  // 2 cycles at 0.25°, both ends included

  const std::string html = read_text(out / "report.html");
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("peak_contact_force"), std::string::npos);
}

TEST(Cli, StepBudgetExceededIsExitThreeWithTimeAndAngle) {
  const fs::path out = cli_dir("budget");
  const Outcome o = run_cli("run " + kQuickstart + " --quiet --out " + out.string() + " --set integrator.max_steps=50");
  EXPECT_EQ(o.code, 3) << o.err;
  EXPECT_NE(o.err.find("step budget"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("cam angle"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(out / "summary.json"));
}

TEST(Cli, UnknownOverrideKeyIsExitTwoWithSuggestion) {
  const Outcome o = run_cli("validate " + kQuickstart + " --set mechanism.cam.rmp=900");
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("rpm"), std::string::npos) << o.err;
}

// A bad value given with --set is not in the file: the message names the argument.
TEST(Cli, BadOverrideValueNamesTheSetArgumentNotTheFile) {
  const Outcome o = run_cli("validate " + kQuickstart + " --set mechanism.follower.mass=-1");
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("--set mechanism.follower.mass=-1: mechanism.follower.mass: "), std::string::npos) << o.err;
  EXPECT_EQ(o.err.find("quickstart.json"), std::string::npos) << o.err;
  // A short path and a value inside an object set whole are traced back too.
  const Outcome nested = camdyn::test::run_camdyn(
      {"validate", kQuickstart, "--set", R"(follower.spring={"stiffness": -5, "preload": 40})"}, cli_dir("nested"));
  EXPECT_EQ(nested.code, 2);
  EXPECT_NE(nested.err.find("--set follower.spring={"), std::string::npos) << nested.err;
  EXPECT_NE(nested.err.find("mechanism.follower.spring.stiffness"), std::string::npos) << nested.err;
  // A good override still passes.
  EXPECT_EQ(run_cli("validate " + kQuickstart + " --set mechanism.follower.mass=0.4").code, 0);
}

// The full simulate example (docs/config.md, "Top level (every study)": a return without a lift) runs as written.
TEST(Cli, InterfaceSpecExampleRuns) {
  const fs::path out = cli_dir("interface_example") / "out";
  const Outcome o = camdyn::test::run_camdyn({"run", kTestData + "/spec/interface_simulate.json", "--quiet", "--out",
                                              out.string(), "--set", "simulation.cycles=2"},
                                             cli_dir("interface_example"));
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
}

TEST(Cli, RunHelpListsEveryStudyTypeWithAnExampleAndTheExitCodes) {
  const Outcome o = run_cli("run --help");
  EXPECT_EQ(o.code, 0);
  for (const camdyn::StudyInfo& study : camdyn::kStudies) {
    const std::string name(study.name);
    const std::size_t line = o.out.find("  " + name + " ");
    ASSERT_NE(line, std::string::npos) << name << "\n" << o.out;
    EXPECT_NE(o.out.find(std::string(study.help), line), std::string::npos) << name << "\n" << o.out;
    std::string example = "camdyn run " + std::string(study.example);
    if (!study.example_args.empty()) example += " " + std::string(study.example_args);
    EXPECT_NE(o.out.find(example + "\n", line), std::string::npos) << name << ": " << example << "\n" << o.out;
  }
  for (const char* code : {"  0  success", "  2  invalid input", "  3  numerical failure", "  1  anything else"})
    EXPECT_NE(o.out.find(code), std::string::npos) << code << "\n" << o.out;
}

// Every registered study has a runner that reads its example config: `camdyn
// validate` on the help's example (its --set arguments kept) passes and prints
// the resolved config of that study.
TEST(Cli, EveryRegisteredStudyValidatesItsExample) {
  for (const camdyn::StudyInfo& study : camdyn::kStudies) {
    std::vector<std::string> args = {"validate", std::string(CAMDYN_SOURCE_DIR) + "/" + std::string(study.example)};
    const std::vector<std::string> example_args = camdyn::test::split_args(std::string(study.example_args));
    for (std::size_t i = 0; i + 1 < example_args.size(); ++i)
      if (example_args[i] == "--set") args.insert(args.end(), {"--set", example_args[i + 1]});
    const Outcome o = camdyn::test::run_camdyn(args, cli_dir("registry"), std::string(study.name));
    ASSERT_EQ(o.code, 0) << study.name << ": " << o.err;
    const auto resolved = nlohmann::json::parse(o.out, nullptr, false);
    ASSERT_TRUE(resolved.is_object()) << study.name << ": " << o.out;
    EXPECT_EQ(resolved.value("study", ""), study.name) << o.out;
  }
}

// ---------------------------------------------------------------- export

TEST(Cli, ExportWritesTheProfileAsCsvAndDxf) {
  const fs::path out = cli_dir("export");
  const Outcome o =
      run_cli("export " + kQuickstart + " --out " + out.string() + " --chord-tolerance 0.01 --cutter-radius 4");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.out.find("profile.dxf"), std::string::npos) << o.out;
  const std::string csv = read_text(out / "profile.csv");
  EXPECT_NE(csv.find("# units: millimetres"), std::string::npos);
  EXPECT_NE(csv.find("cam_angle_deg,lift_mm,contour_x_mm,contour_y_mm,pitch_x_mm,pitch_y_mm,cutter_x_mm,cutter_y_mm"),
            std::string::npos);
  EXPECT_EQ(csv.find("nan"), std::string::npos);
  EXPECT_NE(read_text(out / "profile.dxf").find("LWPOLYLINE"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << "temporary file left: " << entry.path();
}

TEST(Cli, ExportBadFormatIsExitTwoNamingTheOption) {
  const Outcome o = run_cli("export " + kQuickstart + " --format svg --out " + cli_dir("format").string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("--format"), std::string::npos) << o.err;
}

TEST(Cli, ExportPointsWithChordToleranceIsExitTwo) {
  const Outcome o =
      run_cli("export " + kQuickstart + " --points 100 --chord-tolerance 0.01 --out " + cli_dir("both").string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("--points"), std::string::npos) << o.err;
}

// A tool that cannot reach into the hollow flank of a steep cam: exit 2, the option named.
TEST(Cli, ExportToolRadiusAboveTheConcaveRadiusIsExitTwoNamingTheOption) {
  const fs::path dir = cli_dir("concave");
  const fs::path config = dir / "steep.json";
  std::ofstream(config) << R"({"name": "steep", "mechanism": {
      "cam": {"base_radius": 0.02, "rpm": 600, "motion_law": {"segments": [
        {"type": "rise", "law": "cycloidal", "end_deg": 70, "lift": 0.02}, {"type": "dwell", "end_deg": 180},
        {"type": "return", "law": "cycloidal", "end_deg": 250, "lift": 0.02}, {"type": "dwell", "end_deg": 360}]}},
      "follower": {"shape": {"type": "roller", "radius": 0.005}, "mass": 0.3,
                   "spring": {"stiffness": 5000, "preload": 40}},
      "contact": {"stiffness": 1e10}}})";
  const Outcome o = run_cli("export " + config.string() + " --cutter-radius 200 --out " + dir.string());
  EXPECT_EQ(o.code, 2);
  EXPECT_NE(o.err.find("--cutter-radius"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("concave"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(dir / "profile.csv"));
}

TEST(Cli, RunWritesTheProfileWhenTheConfigAsksForIt) {
  const fs::path out = cli_dir("run_profile");
  const Outcome o = run_cli("run " + kQuickstart + " --quiet --out " + out.string() +
                            " --set simulation.cycles=2 --set outputs.profile.formats=[\"csv\"]");
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(fs::exists(out / "profile.csv"));
  EXPECT_FALSE(fs::exists(out / "profile.dxf"));
  const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
  EXPECT_EQ(summary["config"]["outputs"]["profile"]["chord_tolerance_mm"].get<double>(), 0.001);
}

}  // namespace
