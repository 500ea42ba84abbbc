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
#include <vector>

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
  EXPECT_EQ(defaults.outputs.valvetrain->at, ValvetrainAt::valve);
  EXPECT_EQ(defaults.outputs.valvetrain->tdc_deg, 0.0);
  EXPECT_FALSE(defaults.outputs.valvetrain->valve.has_value());
  const SceneConfig cam = read(scene_json(R"({"valvetrain": {"at": "cam", "tdc_deg": 90, "valve": "exhaust"}})"));
  EXPECT_EQ(cam.outputs.valvetrain->at, ValvetrainAt::cam);
  EXPECT_EQ(cam.outputs.valvetrain->tdc_deg, 90.0);
  EXPECT_EQ(cam.outputs.valvetrain->valve, ValveKind::exhaust);
  EXPECT_TRUE(read(to_json(cam)) == cam);
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
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"at": "crank"}})")), "outputs.valvetrain.at");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"tdc_deg": 360}})")), "outputs.valvetrain.tdc_deg");
  EXPECT_EQ(error_path(scene_json(R"({"valvetrain": {"valve": "inlet"}})")), "outputs.valvetrain.valve");
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
  EXPECT_EQ(report.plots.front().series.size(), 3u);  // the lift and the two checking heights (no run: no simulated)
  EXPECT_NEAR(report.plots.front().series.front().x.back(), 720.0, 1e-9);
}

/// The cycloid's flat bucket tappet (0.09 kg) whose valve rests on its seat 0.2 mm above base-circle contact.
const std::string kBucket = R"({"shape": {"type": "flat", "face_width": 0.03}, "mass": 0.09,
    "spring": {"stiffness": 35000, "preload": 250},
    "seat": {"position": 0.0002, "model": "hunt_crossley", "stiffness": 1e9, "exponent": 1.0, "restitution": 0.3}})";
constexpr double kLash = 0.0002;  // [m]

// At the valve, 0.2 mm of lash comes off the lift: the valve lifts L − λ from
// its seat, and reaches a checking height h where the cam reaches h + λ.
TEST(ValvetrainAtValve, LashComesOffTheLiftAndTheCheckingHeights) {
  const SceneConfig scene = read(scene_json(R"({"valvetrain": {"checking_heights": [0.001, 0.005]}})", kBucket));
  const Model model = build_model(scene, "test.json");
  const Json j = valvetrain_json(scene, model);
  EXPECT_EQ(j["at"], "valve");
  EXPECT_EQ(j["body"], "follower");
  EXPECT_EQ(j["lift_datum"], "seat");
  EXPECT_EQ(j["datum"].get<double>(), kLash);
  EXPECT_NEAR(j["max_valve_lift"].get<double>(), 0.01 - kLash, 1e-15);
  EXPECT_NEAR(j["max_lift"].get<double>(), 0.01 - kLash, 1e-15);
  EXPECT_TRUE(j["max_simulated_valve_lift"].is_null());  // no run
  for (const Json& h : j["checking_heights"]) {
    const double open = opening_deg(h["height"].get<double>() + kLash), close = 250.0 - 1.2 * (open - 30.0);
    EXPECT_NEAR(h["opening_cam_deg"].get<double>(), open, kAngleDeg);
    EXPECT_NEAR(h["closing_cam_deg"].get<double>(), close, kAngleDeg);
  }
}

// `at: "cam"` keeps the law's figures (lift from the base circle), with the valve's lift beside them.
TEST(ValvetrainAtValve, AtTheCamTheFiguresAreTheLaws) {
  const SceneConfig scene = read(
      scene_json(R"({"valvetrain": {"at": "cam", "checking_heights": [0.001], "ramp_end_deg": [40, 240]}})", kBucket));
  const Model model = build_model(scene, "test.json");
  const Json j = valvetrain_json(scene, model);
  EXPECT_EQ(j["at"], "cam");
  EXPECT_EQ(j["lift_datum"], "base circle");
  EXPECT_NEAR(j["max_lift"].get<double>(), 0.01, 1e-15);
  EXPECT_NEAR(j["max_valve_lift"].get<double>(), 0.01 - kLash, 1e-15);
  const double open = opening_deg(0.001);
  EXPECT_NEAR(j["checking_heights"][0]["opening_cam_deg"].get<double>(), open, kAngleDeg);
  EXPECT_NEAR(j["checking_heights"][0]["closing_cam_deg"].get<double>(), 250.0 - 1.2 * (open - 30.0), kAngleDeg);
  // The ramp at 40° (x = 0.1 of the rise): the law's height and ds/dθ; at the valve 0.2 mm of it is lash.
  const double height = 0.01 * (0.1 - std::sin(0.2 * kPi) / (2 * kPi));
  const double velocity = 0.01 / (100.0 * kPi / 180.0) * (1.0 - std::cos(0.2 * kPi));
  EXPECT_NEAR(j["opening_ramp"]["height"].get<double>(), height, 1e-15);
  EXPECT_NEAR(j["opening_ramp"]["velocity_per_cam_rad"].get<double>(), velocity, 1e-14);
  ASSERT_LT(height, kLash);  // the valve is still on its seat there
  Json valve_doc = scene_json(R"({"valvetrain": {"checking_heights": [0.001], "ramp_end_deg": [40, 240]}})", kBucket);
  const SceneConfig at_valve = read(valve_doc);
  const Json v = valvetrain_json(at_valve, build_model(at_valve, "test.json"));
  EXPECT_EQ(v["opening_ramp"]["height"].get<double>(), 0.0);
  EXPECT_EQ(v["opening_ramp"]["velocity_per_cam_rad"].get<double>(), 0.0);
}

// The pushrod scene with lash in both links: the valve lifts r₂ (r₁ h − λ₁) − λ₂
// from its seat (each link's ratio times the lift of the body before it, less
// its lash), and reaches a checking height H where the cam reaches
// ((H + λ₂) / r₂ + λ₁) / r₁.
TEST(ValvetrainAtValve, PushrodValveLiftIsTheChainsRatioTimesTheLiftLessTheLashes) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/pushrod_rocker.json";
  const std::vector<std::string> lashes = {"mechanism.train[0].link.lash=0.0001",
                                           "mechanism.train[1].link.lash=0.00005"};
  std::vector<std::string> valve = lashes, cam = lashes;
  valve.push_back(R"(outputs.valvetrain={"checking_heights": [0.001, 0.005]})");
  const SceneConfig scene = load_scene(file, valve);
  const Model model = build_model(scene, file);
  const Json j = valvetrain_json(scene, model);
  const LinkConfig& pushrod = scene.mechanism.train[0].link;
  const LinkConfig& rocker = scene.mechanism.train[1].link;
  ASSERT_EQ(rocker.ratio, 1.5);
  EXPECT_EQ(j["body"], "valve");
  EXPECT_EQ(j["ratio"].get<double>(), pushrod.ratio * rocker.ratio);
  // The same crossings at the cam's equivalent heights (from the base circle, min s), by `at: "cam"`.
  const double min_s = model.law->min_s();  // the table's lowest point: −9 nm, not 0 [m]
  std::vector<double> equivalent;
  for (const Json& c : j["checking_heights"])
    equivalent.push_back(((c["height"].get<double>() + rocker.lash) / rocker.ratio + pushrod.lash) / pushrod.ratio -
                         min_s);
  cam.push_back("outputs.valvetrain={\"at\": \"cam\", \"checking_heights\": " + Json(equivalent).dump() + "}");
  const SceneConfig law_scene = load_scene(file, cam);
  const Json c = valvetrain_json(law_scene, build_model(law_scene, file));
  // The follower's highest position h: the cam's lift from its base circle, plus min s [m].
  const double h = c["max_lift"].get<double>() + min_s;
  EXPECT_NEAR(j["max_valve_lift"].get<double>(), rocker.ratio * (pushrod.ratio * h - pushrod.lash) - rocker.lash,
              1e-15);
  EXPECT_EQ(j["max_lift"], j["max_valve_lift"]);
  EXPECT_EQ(c["max_valve_lift"], j["max_valve_lift"]);
  for (std::size_t i = 0; i < equivalent.size(); ++i) {
    EXPECT_NEAR(j["checking_heights"][i]["opening_cam_deg"].get<double>(),
                c["checking_heights"][i]["opening_cam_deg"].get<double>(), kAngleDeg);
    EXPECT_NEAR(j["checking_heights"][i]["closing_cam_deg"].get<double>(),
                c["checking_heights"][i]["closing_cam_deg"].get<double>(), kAngleDeg);
  }
}

// Crank degrees from the TDC at cam angle tdc_deg, crank = 2 (cam − tdc): the
// cycloid reaches half its lift at exactly 80° (x = ½ of the rise 30–130°) and
// comes down to it at 190°, its peak at 130°.
TEST(ValvetrainTiming, EventsInCrankDegreesFromTheDeadCentres) {
  constexpr double kCrankDeg = 4 * kAngleDeg;  // two crossings, times the crank ratio
  // Intake, TDC at cam 90°: opens 2 (80 − 90) = −20 (20° BTDC), closes 2 (190 − 90) = 200 (20° ABDC), peak 80 ATDC.
  SceneConfig scene =
      read(scene_json(R"({"valvetrain": {"tdc_deg": 90, "valve": "intake", "checking_heights": [0.005]}})"));
  Json j = valvetrain_json(scene, build_model(scene, "test.json"));
  Json h = j["checking_heights"][0];
  EXPECT_NEAR(h["opening_atdc_deg"].get<double>(), -20.0, kCrankDeg);
  EXPECT_NEAR(h["closing_atdc_deg"].get<double>(), 200.0, kCrankDeg);
  EXPECT_NEAR(h["IVO_btdc_deg"].get<double>(), 20.0, kCrankDeg);
  EXPECT_NEAR(h["IVC_abdc_deg"].get<double>(), 20.0, kCrankDeg);
  EXPECT_FALSE(h.contains("EVO_bbdc_deg"));
  EXPECT_NEAR(h["opening_crank_deg"].get<double>(), 700.0, kCrankDeg);  // on the 0–720° axis from TDC
  EXPECT_NEAR(h["closing_crank_deg"].get<double>(), 920.0, kCrankDeg);  // past the cycle, as the interval runs
  EXPECT_NEAR(j["lobe_centre_atdc_deg"].get<double>(), 80.0, 2 * kPeakDeg);
  // Exhaust, TDC at cam 180°: opens 2 (80 − 180) = −200 (20° BBDC), closes 2 (190 − 180) = 20 (20° ATDC).
  scene = read(scene_json(R"({"valvetrain": {"tdc_deg": 180, "valve": "exhaust", "checking_heights": [0.005]}})"));
  j = valvetrain_json(scene, build_model(scene, "test.json"));
  h = j["checking_heights"][0];
  EXPECT_NEAR(h["opening_atdc_deg"].get<double>(), -200.0, kCrankDeg);
  EXPECT_NEAR(h["closing_atdc_deg"].get<double>(), 20.0, kCrankDeg);
  EXPECT_NEAR(h["EVO_bbdc_deg"].get<double>(), 20.0, kCrankDeg);
  EXPECT_NEAR(h["EVC_atdc_deg"].get<double>(), 20.0, kCrankDeg);
  EXPECT_NEAR(j["lobe_centre_atdc_deg"].get<double>(), -100.0, 2 * kPeakDeg);  // 100° BTDC
  // The dead-centre figures wrap to the nearest one: (−P/2, P/2].
  EXPECT_EQ(crank_after(540.0, 360.0), 180.0);
  EXPECT_EQ(crank_after(-540.0, 360.0), 180.0);
  EXPECT_EQ(crank_after(-190.0, 360.0), 170.0);
  EXPECT_EQ(crank_after(700.0, 720.0), -20.0);
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
  // At 600 rpm the cam holds the follower: 0.3 kg × the cycloid's peak 81 m/s² against the spring's ≥ 85 N.
  doc["mechanism"]["cam"]["rpm"] = 600;
  std::ofstream(config) << doc.dump();
  const test::Outcome o = test::run_camdyn({"run", config.string(), "--quiet", "--out", (dir / "out").string()}, dir);
  ASSERT_EQ(o.code, 0) << o.err;
  const Json summary = Json::parse(test::read_text(dir / "out" / "summary.json"));
  ASSERT_TRUE(summary.contains("valvetrain")) << summary.dump();
  EXPECT_NEAR(summary["valvetrain"]["checking_heights"][0]["opening_cam_deg"].get<double>(), opening_deg(0.001),
              kAngleDeg);
  const std::string report = test::read_text(dir / "out" / "report.html");
  EXPECT_NE(report.find("Valve lift against crank angle"), std::string::npos);
  EXPECT_NE(report.find("simulated follower"), std::string::npos);
  // The simulated lift at the peak (130°, where the cycloid's acceleration is 0)
  // is the law's less the contact's penetration under the spring's 40 + 5000 × 0.01 N:
  // δ = (F / K)^(1/n), within δ (the output step's samples near the flat peak are off by < 1e-7 m).
  const double delta = std::pow(90.0 / 1e10, 1.0 / summary["config"]["mechanism"]["contact"]["exponent"].get<double>());
  EXPECT_NEAR(summary["valvetrain"]["max_simulated_valve_lift"].get<double>(), 0.01 - delta, delta + 1e-7);
  EXPECT_EQ(summary["valvetrain"]["max_simulated_lift"], summary["valvetrain"]["max_simulated_valve_lift"]);
}

}  // namespace
}  // namespace camdyn
