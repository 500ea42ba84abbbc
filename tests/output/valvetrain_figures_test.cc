// `outputs.valvetrain` (output/valvetrain_figures.h): the config block read
// and checked with dotted paths, and summary.json's `valvetrain` object in cam
// and crank degrees and at the run's speed, on a cycloidal rise and return
// whose crossings are known in closed form.
#include "output/valvetrain_figures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "cli_run.h"
#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/model.h"
#include "io/config.h"

namespace camdyn {
namespace {

constexpr double kAngleDeg = 1e-8;  // [deg]: crossings are bisected to rounding (geometry/valve_timing.h)
constexpr double kPeakDeg = 1e-5;   // [deg]: a cycloid's flat end hides the root of ds/dθ over ~5e-9 rad

/// Cycloidal rise 30–130° and return 130–250° of 10 mm at 1200 rpm, with the given outputs.
Json scene_json(const std::string& outputs, const std::string& follower = "") {
  return Json::parse(R"({"name": "valve", "mechanism": {
      "cam": {"base_radius": 0.03, "rpm": 1200, "motion_law": {"segments": [
        {"type": "dwell", "end_deg": 30}, {"type": "rise", "law": "cycloidal", "end_deg": 130, "lift": 0.01},
        {"type": "return", "law": "cycloidal", "end_deg": 250, "lift": 0.01}, {"type": "dwell", "end_deg": 360}]}},
      "follower": )" +
                     (follower.empty() ? std::string(R"({"shape": {"type": "roller", "radius": 0.008}, "mass": 0.3,
                     "spring": {"stiffness": 5000, "preload": 40}})")
                                       : follower) +
                     R"(, "contact": {"stiffness": 1e10}}, "outputs": )" + outputs + "}");
}

SceneConfig read(const Json& doc) { return scene_from_json(doc, ConfigSource{"test.json", "."}); }

std::string error_path(const Json& doc) {
  try {
    read(doc);
  } catch (const InputError& e) {
    return e.path();
  }
  return "no error";
}

TEST(ValvetrainConfig, IsReadWithDefaultsAndRoundTrips) {
  EXPECT_FALSE(read(scene_json("{}")).outputs.valvetrain.has_value());
  const SceneConfig defaults = read(scene_json(R"({"valvetrain": {}})"));
  ASSERT_TRUE(defaults.outputs.valvetrain.has_value());
  EXPECT_EQ(defaults.outputs.valvetrain->crank_ratio, 2.0);
  EXPECT_EQ(defaults.outputs.valvetrain->checking_heights, std::vector<double>{0.001});
  const SceneConfig given =
      read(scene_json(R"({"valvetrain": {"crank_ratio": 2, "checking_heights": [0.0002, 0.001]}})"));
  EXPECT_EQ(given.outputs.valvetrain->checking_heights, (std::vector<double>{0.0002, 0.001}));
  EXPECT_TRUE(read(to_json(given)) == given);
}

TEST(ValvetrainConfig, BadValuesNameTheirDottedPath) {
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"crank_ratio": 0}})")), "outputs.valvetrain.crank_ratio");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"checking_heights": []}})")),
            "outputs.valvetrain.checking_heights");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"checking_heights": [0.001, -0.001]}})")),
            "outputs.valvetrain.checking_heights[1]");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"ramp_end_deg": [10]}})")), "outputs.valvetrain.ramp_end_deg");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"checking_height": [0.001]}})")),
            "outputs.valvetrain.checking_height");
  const std::string arm = R"({"motion": "oscillating", "pivot": [0.1, 0.06], "arm_length": 0.11,
      "shape": {"type": "roller", "radius": 0.008}, "inertia": 0.002, "spring": {"stiffness": 50, "preload": 5}})";
  Json oscillating = scene_json(R"({"valvetrain": {}})", arm);
  for (auto& segment : oscillating["mechanism"]["cam"]["motion_law"]["segments"])
    if (segment.contains("lift")) {
      segment.erase("lift");
      segment["lift_deg"] = 12;
    }
  EXPECT_EQ(error_path(oscillating), "outputs.valvetrain");
}

/// The closed-form cycloidal rise of 10 mm over 100° from 30°: where it reaches h [deg], by bisection.
double opening_deg(double h) {
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 200; ++i) {
    const double x = 0.5 * (lo + hi);
    (0.01 * (x - std::sin(2 * kPi * x) / (2 * kPi)) < h ? lo : hi) = x;
  }
  return 30.0 + 100.0 * 0.5 * (lo + hi);
}

TEST(ValvetrainSummary, DurationsInCamAndCrankDegreesAndRampVelocityAtTheRunSpeed) {
  const SceneConfig scene = read(scene_json(
      R"({"valvetrain": {"crank_ratio": 2, "checking_heights": [0.0002, 0.001], "ramp_end_deg": [40, 240]}})"));
  const Model model = build_model(scene, "test.json");
  const Json j = valvetrain_json(scene, model);
  ASSERT_TRUE(j.is_object()) << j.dump();
  EXPECT_EQ(j["crank_ratio"], 2.0);
  EXPECT_NEAR(j["max_lift"].get<double>(), 0.01, 1e-15);
  EXPECT_NEAR(j["lobe_centre_cam_deg"].get<double>(), 130.0, kPeakDeg);
  EXPECT_NEAR(j["lobe_centre_crank_deg"].get<double>(), 260.0, 2 * kPeakDeg);
  ASSERT_EQ(j["checking_heights"].size(), 2u);
  for (const Json& h : j["checking_heights"]) {
    const double height = h["height"].get<double>();
    // The return is the rise mirrored over 120°: it comes down to h at 250° − 1.2 (opening − 30°).
    const double open = opening_deg(height), close = 250.0 - 1.2 * (open - 30.0);
    EXPECT_NEAR(h["opening_cam_deg"].get<double>(), open, kAngleDeg);
    EXPECT_NEAR(h["closing_cam_deg"].get<double>(), close, kAngleDeg);
    EXPECT_NEAR(h["duration_cam_deg"].get<double>(), close - open, 2 * kAngleDeg);
    EXPECT_NEAR(h["duration_crank_deg"].get<double>(), 2.0 * (close - open), 4 * kAngleDeg);
    EXPECT_NEAR(h["opening_crank_deg"].get<double>(), 2.0 * open, 2 * kAngleDeg);
  }
  // At 40° the rise is at x = 0.1: ds/dθ = L/β (1 − cos 2πx), and m/s at 1200 rpm.
  const double velocity = 0.01 / (100.0 * kPi / 180.0) * (1.0 - std::cos(0.2 * kPi));
  const Json& ramp = j["opening_ramp"];
  EXPECT_NEAR(ramp["velocity_per_cam_rad"].get<double>(), velocity, 1e-14);
  EXPECT_NEAR(ramp["velocity_m_s"].get<double>(), velocity * 1200.0 * 2.0 * kPi / 60.0, 1e-12);
  EXPECT_NEAR(ramp["velocity_per_crank_deg"].get<double>(), velocity * kPi / 180.0 / 2.0, 1e-16);
  EXPECT_NEAR(ramp["crank_deg"].get<double>(), 80.0, 1e-12);
  EXPECT_LT(j["closing_ramp"]["velocity_m_s"].get<double>(), 0.0);

  Report report;
  add_valvetrain_report(scene, model, report);
  ASSERT_EQ(report.plots.size(), 1u);
  EXPECT_EQ(report.plots.front().xlabel, "crank angle [°]");
  EXPECT_EQ(report.plots.front().series.size(), 3u);  // the lift and the two checking heights
  EXPECT_NEAR(report.plots.front().series.front().x.back(), 720.0, 1e-9);
}

TEST(ValvetrainSummary, NothingWithoutTheBlock) {
  const SceneConfig scene = read(scene_json("{}"));
  const Model model = build_model(scene, "test.json");
  EXPECT_TRUE(valvetrain_json(scene, model).is_null());
  Report report;
  add_valvetrain_report(scene, model, report);
  EXPECT_TRUE(report.tables.empty());
}

// `camdyn run` of a scene with the block: summary.json has the object, the report its table.
TEST(ValvetrainSummary, SimulateRunWritesItIntoSummaryAndReport) {
  const std::filesystem::path dir = test::scratch_dir("valvetrain_figures_test", "run");
  const std::filesystem::path config = dir / "valve.json";
  Json doc = scene_json(R"({"valvetrain": {"checking_heights": [0.001]}})");
  doc["simulation"] = Json{{"cycles", 2}};
  std::ofstream(config) << doc.dump();
  const test::Outcome o = test::run_camdyn({"run", config.string(), "--quiet", "--out", (dir / "out").string()}, dir);
  ASSERT_EQ(o.code, 0) << o.err;
  const Json summary = Json::parse(test::read_text(dir / "out" / "summary.json"));
  ASSERT_TRUE(summary.contains("valvetrain")) << summary.dump();
  EXPECT_NEAR(summary["valvetrain"]["checking_heights"][0]["opening_cam_deg"].get<double>(), opening_deg(0.001),
              kAngleDeg);
  EXPECT_NE(test::read_text(dir / "out" / "report.html").find("Valve lift against crank angle"), std::string::npos);
}

}  // namespace
}  // namespace camdyn
