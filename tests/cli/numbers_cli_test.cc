// Every number validated for what the run will do with it (issue 36, item 5):
// derived sizes held to --max-memory, limits and speeds past any cam refused
// at validation naming the dotted path (exit 2), a solver's refusal never
// exit 1 or a signal, and no NaN or inf in any output file.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "study_paths.h"

namespace {

namespace fs = std::filesystem;

using camdyn::test::Outcome;
using camdyn::test::read_text;

fs::path numbers_dir(const std::string& name) { return camdyn::test::scratch_dir("numbers_cli_test", name); }

/// `camdyn validate CONFIG --set S...`.
Outcome validate(const std::string& config, const std::vector<std::string>& sets, const std::string& tag) {
  std::vector<std::string> args = {"validate", config};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  return camdyn::test::run_camdyn(args, numbers_dir(tag));
}

/// Exit 2 with "camdyn: error: ", the dotted path and the reason's words.
void expect_refused(const Outcome& o, const std::string& path, const std::string& words) {
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_TRUE(contains(o.err, "camdyn: error: ")) << o.err;
  EXPECT_TRUE(contains(o.err, path + ": ")) << o.err;
  EXPECT_TRUE(contains(o.err, words)) << o.err;
}

/// The files under `dir` (recursively) that hold a non-finite number as
/// JSON, CSV or text writes one: nan, inf (not inside a word such as "info").
/// (A scan by hand: <regex> under GCC 12's sanitizers warns, an error there.)
bool names_non_finite(const std::string& text) {
  auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; };
  std::string lower = text;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const std::string word : {"nan", "inf", "infinity"})
    for (std::size_t at = lower.find(word); at != std::string::npos; at = lower.find(word, at + 1))
      if ((at == 0 || !letter(lower[at - 1])) && (at + word.size() == lower.size() || !letter(lower[at + word.size()])))
        return true;
  return false;
}

std::vector<std::string> files_with_non_finite(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file() || entry.path().extension() == ".html") continue;
    if (names_non_finite(read_text(entry.path()))) found.push_back(entry.path().string());
  }
  return found;
}

const std::string kOptimize = kStudies + "optimize_force.json";

TEST(Numbers, OptimizeDerivedSizesAreHeldToTheMemoryBudget) {
  expect_refused(validate(kOptimize, {"rigid.certificate_grid=1e9"}, "grid"), "rigid.certificate_grid", "--max-memory");
  expect_refused(validate(kOptimize, {"rigid.samples=1e9"}, "samples"), "rigid.samples", "--max-memory");
  // A large but affordable size still passes: the estimate refuses only what the budget cannot hold.
  const Outcome small = validate(kOptimize, {"rigid.samples=2000"}, "samples_ok");
  EXPECT_EQ(small.code, 0) << small.err;
}

TEST(Numbers, OptimizeLimitsAndWeightsPastAnyCamAreRefused) {
  expect_refused(validate(kOptimize, {"constraints.min_contact_force=1e308"}, "floor"), "constraints.min_contact_force",
                 "must be in (0, 1e+09]");
  expect_refused(validate(kOptimize, {"objective.peak_contact_force=1e308"}, "weight"), "objective.peak_contact_force",
                 "must be 0 or in [1e-06, 1e+06]");
  expect_refused(validate(kOptimize, {"operating_rpm=[900, 1e308]"}, "rpm"), "operating_rpm[1]", "1e+06");
  expect_refused(validate(kOptimize, {"rigid.min_contact_force=1e300"}, "rigid_floor"), "rigid.min_contact_force",
                 "1e+09");
}

/// An optimize run of one evaluation at one speed whose rigid-stage programme
/// has no design at all (`limit`): a physical answer, exit 0, no NaN or inf.
void expect_infeasible_family_reported(const std::string& limit, const std::string& tag) {
  const fs::path out = numbers_dir(tag) / "out";
  const Outcome o = camdyn::test::run_camdyn(
      {"run", kOptimize, "--quiet", "--out", out.string(), "--set", "optimizer.max_evaluations=1", "--set",
       "operating_rpm=[900]", "--set", "design.end_deg_range={}", "--set", limit},
      numbers_dir(tag + "_io"));
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_FALSE(contains(o.err, "internal error")) << o.err;
  EXPECT_TRUE(files_with_non_finite(out).empty()) << files_with_non_finite(out).front();
  const auto result = nlohmann::json::parse(read_text(out / "result.json"));
  const auto& speed = result["rigid_stage"]["certificate"]["speeds"][0];
  EXPECT_FALSE(speed["feasible"].get<bool>());
  EXPECT_FALSE(speed["design_exists"].get<bool>());
  EXPECT_TRUE(speed["best_margin"].is_null());
}

TEST(Numbers, PressureAngleLimitNoDesignMeetsIsInfeasibleNotABug) {
  expect_infeasible_family_reported("constraints.max_pressure_angle_deg=8", "angle");
}

TEST(Numbers, JerkLimitNoDesignMeetsIsInfeasibleNotABug) {
  expect_infeasible_family_reported("constraints.max_peak_jerk=1e-9", "jerk");
}

const std::string kIdentify = kStudies + "identify_drop/identify_single_drop.json";

TEST(Numbers, IdentifyCeresOptionsOutsideCeresRangesAreRefused) {
  for (const char* radius : {"1e19", "1e-310"})
    expect_refused(validate(kIdentify, {std::string("solver.initial_trust_region_radius=") + radius}, "radius"),
                   "solver.initial_trust_region_radius", "Ceres' own trust-region limits");
  expect_refused(validate(kIdentify, {"solver.loss_scale=1e300"}, "loss"), "solver.loss_scale", "1e+100");
}

TEST(Numbers, IdentifyRecordSampleBeyondSquaringIsRefusedNamingItsLine) {
  const fs::path dir = numbers_dir("record");
  const std::string csv_in = read_text(kStudies + "identify_drop/drop_h005_50khz.csv");
  // The 5th data row's force becomes 1e300 N.
  std::istringstream in(csv_in);
  std::string text, line, column_name;
  int number = 0, corrupt_line = 0, data_rows = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line[0] != '#' && line.find("time") == std::string::npos && ++data_rows == 5) {
      line = line.substr(0, line.find(',')) + ",1e300";
      corrupt_line = number;
    }
    text += line + "\n";
  }
  ASSERT_GT(corrupt_line, 0);
  std::ofstream(dir / "record.csv") << text;
  std::ofstream(dir / "study.json")
      << nlohmann::json{{"extends", kIdentify}, {"reference", {{"file", (dir / "record.csv").string()}}}}.dump();
  const Outcome o = camdyn::test::run_camdyn({"validate", (dir / "study.json").string()}, dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_TRUE(contains(o.err, "record.csv: line " + std::to_string(corrupt_line) + ", column force_N: ")) << o.err;
  EXPECT_TRUE(contains(o.err, "1e+300")) << o.err;
}

TEST(Numbers, StudySpeedsAndStepsPastAnyCamAreRefused) {
  const std::string jump_map = kStudies + "periodic/bouncing_ball_jump_map.json";
  expect_refused(validate(jump_map, {"jump_map.high_rpm=1e308"}, "map_high"), "jump_map.high_rpm", "1e+06");
  expect_refused(validate(jump_map, {"jump_map.low_rpm=1e308"}, "map_low"), "jump_map.low_rpm", "1e+06");
  const std::string quickstart = kStudies + "quickstart.json";
  expect_refused(validate(quickstart, {"study=speed_limit", "speed_limit.low_rpm=1e308"}, "limit_low"),
                 "speed_limit.low_rpm", "1e+06");
  expect_refused(validate(quickstart, {"mechanism.cam.rpm=1e308"}, "cam_rpm"), "mechanism.cam.rpm", "1e+06");
  expect_refused(validate(kStudies + "work_precision.json", {"rk4_steps_deg=[1e308]"}, "rk4"), "rk4_steps_deg[0]",
                 "(0, 360]");
}

TEST(Numbers, NanCutterRadiusIsRefused) {
  const fs::path dir = numbers_dir("cutter");
  const Outcome o = camdyn::test::run_camdyn(
      {"export", kStudies + "quickstart.json", "--cutter-radius", "nan", "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_TRUE(contains(o.err, "--cutter-radius: must be a finite number")) << o.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "profile.csv"));
}

TEST(Numbers, ExtendsNameWithNulIsRefused) {
  const fs::path dir = numbers_dir("nul");
  std::ofstream(dir / "study.json") << R"({"extends": ")" << kStudies << R"(quickstart.json\u0000junk", "name": "x"})";
  const Outcome o = camdyn::test::run_camdyn({"validate", (dir / "study.json").string()}, dir);
  expect_refused(o, "extends", "NUL character");
}

TEST(Numbers, HugeLiftIsBlamedOnTheLiftWithoutNonFiniteNumbers) {
  const Outcome o = validate(kStudies + "quickstart.json",
                             {R"(mechanism.cam.motion_law={"segments":[{"type":"rise","law":"cycloidal","end_deg":120,)"
                              R"("lift":1e308},{"type":"dwell","end_deg":180},{"type":"return","law":"cycloidal",)"
                              R"("end_deg":300,"lift":1e308},{"type":"dwell","end_deg":360}]})"},
                             "lift");
  expect_refused(o, "mechanism.cam.motion_law.segments[0].lift", "did you give millimetres");
  EXPECT_FALSE(contains(o.err, "inf ")) << o.err;
  EXPECT_FALSE(contains(o.err, "contact.stiffness")) << o.err;
}

TEST(Numbers, CompareStudyNoneOfWhoseRunsBuildsIsRefusedAtValidation) {
  const std::string compare = kStudies + "compare_contact_models.json";
  // Every case's contact too soft to carry the preload: none of the 20 runs can be built.
  std::vector<std::string> sets;
  for (int c = 0; c < 5; ++c)
    sets.push_back("cases[" + std::to_string(c) + "].set=[\"mechanism.contact.stiffness=1\"]");
  expect_refused(validate(compare, sets, "compare"), "cases[0]", "none of the study's 20 runs can be built");
  // One case that builds is enough: the others are kept as failed runs (tests/study/compare_test.cc).
  sets.pop_back();
  const Outcome some = validate(compare, sets, "compare_some");
  EXPECT_EQ(some.code, 0) << some.err;
}

}  // namespace
