// What the export gives the shop besides the curves (output/profile_export.h,
// docs/export.md): the drawing's base circle, timing mark and design data,
// read back with dxflib, and the lift table another follower reads on the
// cam as made, against closed forms on an eccentric-disc cam.
#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "output/profile_export.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

// Tolerance levels.
constexpr double kExactGeometry = 1e-9;  // [m], the issue's acceptance level for the lift a follower reads
constexpr double kDxfDigits = 1e-9;      // [mm], dxflib prints 16 decimals

fs::path scratch(const std::string& name) { return test::scratch_dir("manufacturing_export_test", name); }

/// s(θ) = e (1 − cos θ) on a base circle r_b = 40 mm, turning `direction`, for the follower given.
std::string eccentric_mechanism(double e, const std::string& direction, const std::string& follower_shape) {
  const std::string lift = std::to_string(2.0 * e);
  return R"({"cam": {"base_radius": 0.04, "rpm": 600, "direction": ")" + direction +
         R"(", "motion_law": {"segments": [
              {"type": "rise", "law": "harmonic", "end_deg": 180, "lift": )" +
         lift + R"(}, {"type": "return", "law": "harmonic", "end_deg": 360, "lift": )" + lift + R"(}]}},
          "follower": {"shape": )" +
         follower_shape + R"(, "mass": 0.3, "spring": {"stiffness": 5000, "preload": 40}},
          "contact": {"stiffness": 1e10}})";
}

constexpr const char* kFlatFace = R"({"type": "flat", "face_width": 0.05})";
constexpr const char* kRoller = R"({"type": "roller", "radius": 0.01})";
constexpr double kE = 0.005, kRb = 0.04;

Model model_of(const std::string& mechanism) {
  const Json doc = Json::parse(R"({"name": "export-test", "mechanism": )" + mechanism + "}");
  return build_model(scene_from_json(doc, ConfigSource{"test.json", "."}), "test.json");
}

/// What dxflib reads back: circles, lines and texts by layer.
class Collector : public DL_CreationAdapter {
 public:
  void addCircle(const DL_CircleData& data) override { circles[attributes.getLayer()].push_back(data); }
  void addLine(const DL_LineData& data) override { lines[attributes.getLayer()].push_back(data); }
  void addText(const DL_TextData& data) override { texts[attributes.getLayer()] += data.text + "\n"; }

  std::map<std::string, std::vector<DL_CircleData>> circles;
  std::map<std::string, std::vector<DL_LineData>> lines;
  std::map<std::string, std::string> texts;
};

class DrawingAids : public ::testing::TestWithParam<const char*> {};

// The base circle about the centre, a cross at the centre, the timing mark
// through the contour point at cam angle 0 (on +y for a follower without
// offset: the point under the follower) and the design data as text.
TEST_P(DrawingAids, DxfReadBackHasBaseCircleTimingMarkAndDesignData) {
  const Model model = model_of(eccentric_mechanism(kE, GetParam(), kRoller));
  const SampledCamProfile profile = sample_cam_profile(model, ProfileOptions{}, ProfileOptionNames{"test.json"});
  const fs::path dir = scratch(std::string("aids_") + GetParam());
  write_profile_files(dir, profile, "disc", {ProfileFormat::dxf});
  Collector c;
  DL_Dxf dxf;
  ASSERT_TRUE(dxf.in((dir / "profile.dxf").string(), &c));

  ASSERT_EQ(c.circles["BASE_CIRCLE"].size(), 1u);
  const DL_CircleData& base = c.circles["BASE_CIRCLE"].front();
  EXPECT_NEAR(base.radius, kRb * 1e3, kDxfDigits);
  EXPECT_NEAR(base.cx, 0.0, kDxfDigits);
  EXPECT_NEAR(base.cy, 0.0, kDxfDigits);
  EXPECT_EQ(c.lines["CAM_CENTRE"].size(), 2u);  // the cross

  ASSERT_EQ(c.lines["TIMING_MARK"].size(), 1u);
  const DL_LineData& mark = c.lines["TIMING_MARK"].front();
  // Along +y, from inside the base circle to beyond the cam.
  EXPECT_NEAR(mark.x1, 0.0, kDxfDigits);
  EXPECT_NEAR(mark.x2, 0.0, kDxfDigits);
  EXPECT_LT(mark.y1, kRb * 1e3);
  EXPECT_GT(mark.y2, profile.max_radius * 1e3);
  EXPECT_NE(c.texts["TIMING_MARK"].find("cam angle 0"), std::string::npos) << c.texts["TIMING_MARK"];

  const std::string& data = c.texts["DESIGN_DATA"];
  const bool ccw = std::string(GetParam()) == "ccw";
  for (const std::string& want : {std::string("DESIGN DATA"), std::string("base circle radius: 40 mm"),
                                  std::string("lift: 10 mm"), std::string("translating roller, radius 10 mm"),
                                  std::string(ccw ? "rotation: counterclockwise" : "rotation: clockwise")})
    EXPECT_NE(data.find(want), std::string::npos) << want << "\n" << data;
}

INSTANTIATE_TEST_SUITE_P(BothDirections, DrawingAids, ::testing::Values("ccw", "cw"));

// A roller of the design's radius on the design's axis reads the design's law.
TEST(FollowerLift, DesignRollerRadiusReproducesTheDesignLift) {
  const Model model = model_of(eccentric_mechanism(kE, "ccw", kRoller));
  const FollowerLiftTable table = follower_lift_table(model, 0.01, 1.0 * kDegToRad, "test.json");
  ASSERT_EQ(table.theta.size(), 360u);
  for (std::size_t i = 0; i < table.theta.size(); ++i) {
    EXPECT_NEAR(table.theta[i], static_cast<double>(i) * kDegToRad, 1e-12);
    EXPECT_NEAR(table.lift[i], model.law->eval(table.theta[i]).s, kExactGeometry) << "at " << i << "°";
  }
}

// A flat face on s = e (1 − cos θ) is driven by a disc of radius r_b + e about
// (0, −e) (cam frame). A roller of radius R on the axis x = 0 then reads
//   y(θ) = −e cos θ + sqrt((r_b + e + R)² − e² sin² θ),  lift = y − (r_b + R),
// which differs from the flat face's e (1 − cos θ): checked for both directions and two radii.
TEST(FollowerLift, RollerOnTheFlatFaceDiscReadsTheClosedFormLift) {
  for (const char* direction : {"ccw", "cw"}) {
    const Model model = model_of(eccentric_mechanism(kE, direction, kFlatFace));
    for (const double radius : {0.002, 0.015}) {
      const FollowerLiftTable table = follower_lift_table(model, radius, 2.5 * kDegToRad, "test.json");
      ASSERT_EQ(table.theta.size(), 144u);
      double largest_difference = 0.0;
      for (std::size_t i = 0; i < table.theta.size(); ++i) {
        const double th = table.theta[i];
        const double want = -kE * std::cos(th) +
                            std::sqrt(std::pow(kRb + kE + radius, 2) - std::pow(kE * std::sin(th), 2)) - (kRb + radius);
        EXPECT_NEAR(table.lift[i], want, kExactGeometry) << direction << " R " << radius << " at " << th / kDegToRad;
        largest_difference = std::max(largest_difference, std::abs(table.lift[i] - kE * (1.0 - std::cos(th))));
      }
      // e² R / (2 (r_b + e)(r_b + e + R))-sized at 90°: microns, far above the geometry's rounding.
      EXPECT_GT(largest_difference, 1e-6) << direction << " R " << radius;
    }
  }
}

TEST(FollowerLift, CsvHeaderNamesTheDatumAndTheRowsReadBack) {
  const Model model = model_of(eccentric_mechanism(kE, "cw", kRoller));
  const FollowerLiftTable table = follower_lift_table(model, 0.006, 5.0 * kDegToRad, "test.json");
  const fs::path path = scratch("csv") / "follower_lift.csv";
  write_follower_lift_csv(path, table, "disc");
  std::ifstream in(path);
  std::string line, header;
  std::vector<std::pair<double, double>> rows;
  bool columns_seen = false;
  while (std::getline(in, line)) {
    if (line.rfind("# ", 0) == 0) {
      header += line + "\n";
    } else if (!columns_seen) {
      EXPECT_EQ(line, "cam_angle_deg,lift_mm");
      columns_seen = true;
    } else {
      std::stringstream row(line);
      std::string a, b;
      std::getline(row, a, ',');
      std::getline(row, b, ',');
      rows.emplace_back(std::stod(a), std::stod(b));
    }
  }
  for (const char* want : {"datum: cam angle 0 = the start of the motion law", "lift 0 = the roller on the base circle",
                           "radius 6 mm", "clockwise (cw)", "units: millimetres"})
    EXPECT_NE(header.find(want), std::string::npos) << want << "\n" << header;
  ASSERT_EQ(rows.size(), 72u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].first, 5.0 * static_cast<double>(i));
    EXPECT_EQ(rows[i].second, table.lift[i] * 1e3);  // the CSV writer's shortest round-trip digits
  }
}

TEST(FollowerLift, BadRadiusOrStepIsAnInputErrorNamingTheOption) {
  const Model model = model_of(eccentric_mechanism(kE, "ccw", kRoller));
  auto path_of = [&](double radius, double step) {
    try {
      follower_lift_table(model, radius, step, "");
    } catch (const InputError& e) {
      return e.path();
    }
    return std::string("no error");
  };
  EXPECT_EQ(path_of(-0.001, kDegToRad), "--follower-radius");
  EXPECT_EQ(path_of(0.01, 0.0), "--angle-step-deg");
  EXPECT_EQ(path_of(0.01, 400 * kDegToRad), "--angle-step-deg");
}

TEST(FollowerLift, ExportCommandWritesTheTableAndRefusesABadStepWithExitTwo) {
  const fs::path dir = scratch("cli");
  const fs::path config = dir / "disc.json";
  std::ofstream(config) << R"({"name": "disc", "mechanism": )" << eccentric_mechanism(kE, "ccw", kRoller) << "}";
  const test::Outcome ok = test::run_camdyn(
      {"export", config.string(), "--out", (dir / "out").string(), "--follower-radius", "10", "--angle-step-deg", "2"},
      dir, "ok");
  ASSERT_EQ(ok.code, 0) << ok.err;
  EXPECT_NE(ok.out.find("follower_lift.csv"), std::string::npos) << ok.out;
  const std::string text = test::read_text(dir / "out" / "follower_lift.csv");
  EXPECT_NE(text.find("\n358,"), std::string::npos);
  EXPECT_EQ(text.find("\n360,"), std::string::npos);
  const test::Outcome bad = test::run_camdyn(
      {"export", config.string(), "--out", (dir / "bad").string(), "--follower-radius", "10", "--angle-step-deg", "0"},
      dir, "bad");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("--angle-step-deg"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace camdyn
