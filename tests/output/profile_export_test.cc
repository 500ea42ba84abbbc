// The cam profile for manufacturing (output/profile_export.h): exact geometry on
// a cam whose contour is known in closed form, the DXF read back with
// dxflib, the tool path's distance from the contour, the chord tolerance.
#include "output/profile_export.h"

#include <dxflib/dl_creationadapter.h>
#include <dxflib/dl_dxf.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "common/errors.h"
#include "dynamics/model.h"
#include "input_error_of.h"
#include "io/config.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

// Tolerance levels.
// Points computed from the closed-form synthesis: only rounding (|r| ≈ 0.05 m, ~1e-17 m per operation).
constexpr double kExactGeometry = 1e-9;  // [m], the acceptance level of the issue
// A number written by the CSV writer reads back exactly; dxflib prints 16 decimals of a millimetre.
constexpr double kDxfDigits = 1e-12;  // [mm]

fs::path scratch(const std::string& name) { return test::scratch_dir("profile_test", name); }

/// A scene from the mechanism JSON given (the rest defaulted).
Model model_of(const std::string& mechanism, SceneConfig* scene_out = nullptr) {
  const Json doc = Json::parse(R"({"name": "profile-test", "mechanism": )" + mechanism + "}");
  const SceneConfig scene = scene_from_json(doc, ConfigSource{"test.json", "."});
  if (scene_out != nullptr) *scene_out = scene;
  return build_model(scene, "test.json");
}

/// s(θ) = e (1 − cos θ): a harmonic rise of 2e over 180° and a harmonic return.
std::string harmonic_eccentric(double e, const std::string& direction, const std::string& follower_shape) {
  const std::string lift = std::to_string(2.0 * e);
  return R"({"cam": {"base_radius": 0.04, "rpm": 600, "direction": ")" + direction +
         R"(", "motion_law": {"segments": [
              {"type": "rise", "law": "harmonic", "end_deg": 180, "lift": )" +
         lift + R"(},
              {"type": "return", "law": "harmonic", "end_deg": 360, "lift": )" +
         lift + R"(}]}},
          "follower": {"shape": )" +
         follower_shape + R"(, "mass": 0.3, "spring": {"stiffness": 5000, "preload": 40}},
          "contact": {"stiffness": 1e10}})";
}

constexpr const char* kFlatFace = R"({"type": "flat", "face_width": 0.05})";
constexpr const char* kRoller = R"({"type": "roller", "radius": 0.01})";

/// A steep rise on a small base circle: the roller's cam contour has concave flanks.
std::string concave_roller_cam() {
  return R"({"cam": {"base_radius": 0.02, "rpm": 600, "motion_law": {"segments": [
              {"type": "rise", "law": "cycloidal", "end_deg": 70, "lift": 0.02},
              {"type": "dwell", "end_deg": 180},
              {"type": "return", "law": "cycloidal", "end_deg": 250, "lift": 0.02},
              {"type": "dwell", "end_deg": 360}]}},
          "follower": {"shape": {"type": "roller", "radius": 0.005}, "mass": 0.3,
                       "spring": {"stiffness": 5000, "preload": 40}},
          "contact": {"stiffness": 1e10}})";
}

/// The data rows of profile.csv, by column name (comment lines skipped).
std::map<std::string, std::vector<double>> read_profile_csv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> columns;
  std::map<std::string, std::vector<double>> data;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream row(line);
    std::string cell;
    if (columns.empty()) {
      while (std::getline(row, cell, ',')) columns.push_back(cell);
      continue;
    }
    for (std::size_t c = 0; std::getline(row, cell, ','); ++c) data[columns.at(c)].push_back(std::stod(cell));
  }
  return data;
}

/// Collects what dxflib reads back: the vertices of each polyline by layer, header variables, comments.
class Collector : public DL_CreationAdapter {
 public:
  struct Polyline {
    int flags = 0;
    std::vector<Eigen::Vector2d> vertices;
  };
  void addPolyline(const DL_PolylineData& data) override {
    current_ = &polylines[attributes.getLayer()];
    current_->flags = data.flags;
  }
  void addVertex(const DL_VertexData& data) override {
    if (current_ != nullptr) current_->vertices.emplace_back(data.x, data.y);
  }
  void addComment(const std::string& comment) override { comments += comment + "\n"; }
  void addText(const DL_TextData& data) override { texts += data.text + "\n"; }
  void setVariableInt(const std::string& key, int value, int /*code*/) override { ints[key] = value; }

  std::map<std::string, Polyline> polylines;
  std::map<std::string, int> ints;
  std::string comments, texts;

 private:
  Polyline* current_ = nullptr;
};

class EccentricDisc : public ::testing::TestWithParam<const char*> {};

// A flat face on s = e (1 − cos θ) is driven by a circular disc: the envelope
// r(θ) = R(−σθ)(σ s', r_b + s) = (σ (r_b + e) sin θ, (r_b + e) cos θ − e), for
// either σ the circle of radius r_b + e about (0, −e).
TEST_P(EccentricDisc, FlatFaceContourPointsLieOnTheDisc) {
  constexpr double e = 0.005, rb = 0.04;
  const Model model = model_of(harmonic_eccentric(e, GetParam(), kFlatFace));
  const double sigma = std::string(GetParam()) == "cw" ? -1.0 : 1.0;
  ProfileOptions options;
  options.chord_tolerance = 1e-6;
  const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{"test.json"});
  ASSERT_GT(profile.points.size(), 100u);
  EXPECT_FALSE(profile.has_pitch);
  const fs::path dir = scratch(std::string("disc_") + GetParam());
  write_profile_csv(dir / "profile.csv", profile, "disc");
  const auto csv = read_profile_csv(dir / "profile.csv");
  ASSERT_EQ(csv.at("contour_x_mm").size(), profile.points.size());
  EXPECT_EQ(csv.count("pitch_x_mm"), 0u);
  double worst = 0.0;
  for (std::size_t i = 0; i < profile.points.size(); ++i) {
    const Eigen::Vector2d p(csv.at("contour_x_mm")[i] * 1e-3, csv.at("contour_y_mm")[i] * 1e-3);
    worst = std::max(worst, std::abs((p - Eigen::Vector2d(0.0, -e)).norm() - (rb + e)));
    const double theta = csv.at("cam_angle_deg")[i] * std::numbers::pi / 180.0;
    EXPECT_NEAR(csv.at("lift_mm")[i] * 1e-3, e * (1.0 - std::cos(theta)), kExactGeometry);
    // The point at cam angle θ: (σ (r_b + e) sin θ, (r_b + e) cos θ − e).
    EXPECT_NEAR(p.x(), sigma * (rb + e) * std::sin(theta), kExactGeometry);
  }
  EXPECT_LT(worst, kExactGeometry);
  EXPECT_FALSE(std::isfinite(profile.min_concave_radius));  // a disc is convex
}

INSTANTIATE_TEST_SUITE_P(BothDirections, EccentricDisc, ::testing::Values("ccw", "cw"));

// A roller's contour is its centre path offset inwards by its radius; a tool of
// the roller's radius runs on the pitch curve.
TEST(ProfileExport, RollerPitchCurveIsTheContourOffsetByTheRollerRadius) {
  constexpr double e = 0.005, rb = 0.04, rr = 0.01;
  const Model model = model_of(harmonic_eccentric(e, "ccw", kRoller));
  ProfileOptions options;
  options.points = 720;
  options.cutter_radius = rr;
  const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{"test.json"});
  ASSERT_EQ(profile.points.size(), 720u);
  ASSERT_TRUE(profile.has_pitch);
  for (const ProfilePoint& p : profile.points) {
    // The roller centre at cam angle θ: R(−θ)·(0, r_b + r_r + s(θ)).
    const double y = rb + rr + e * (1.0 - std::cos(p.theta));
    const Eigen::Vector2d centre(std::sin(p.theta) * y, std::cos(p.theta) * y);
    EXPECT_LT((p.pitch - centre).norm(), kExactGeometry);
    EXPECT_NEAR((p.pitch - p.contour).norm(), rr, kExactGeometry);
    EXPECT_LT((p.cutter - p.pitch).norm(), kExactGeometry);
  }
}

// The DXF, read back with dxflib, holds the same points (mm), closed, in millimetre units.
TEST(ProfileExport, DxfReadBackWithDxflibReproducesThePoints) {
  const Model model = model_of(harmonic_eccentric(0.005, "ccw", kRoller));
  ProfileOptions options;
  options.chord_tolerance = 1e-5;
  options.cutter_radius = 0.004;
  const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{"test.json"});
  const fs::path dir = scratch("dxf");
  const auto written = write_profile_files(dir, profile, "disc", {ProfileFormat::dxf});
  ASSERT_EQ(written.size(), 1u);
  EXPECT_FALSE(fs::exists(dir / "profile.csv"));
  // Nothing but the file itself is left in the folder (no scratch or temporary file).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);

  Collector collector;
  DL_Dxf dxf;
  ASSERT_TRUE(dxf.in((dir / "profile.dxf").string(), &collector));
  EXPECT_EQ(collector.ints["$INSUNITS"], 4);  // millimetres
  EXPECT_NE(collector.comments.find("units: millimetres"), std::string::npos) << collector.comments;
  EXPECT_NE(collector.comments.find("counterclockwise"), std::string::npos);
  EXPECT_NE(collector.texts.find("angle origin"), std::string::npos) << collector.texts;
  const std::pair<const char*, Eigen::Vector2d ProfilePoint::*> curves[] = {{"CAM_CONTOUR", &ProfilePoint::contour},
                                                                            {"PITCH_CURVE", &ProfilePoint::pitch},
                                                                            {"CUTTER_PATH", &ProfilePoint::cutter}};
  for (const auto& [layer, member] : curves) {
    ASSERT_EQ(collector.polylines.count(layer), 1u) << layer;
    const Collector::Polyline& line = collector.polylines[layer];
    EXPECT_EQ(line.flags & 1, 1) << layer << " is not closed";
    ASSERT_EQ(line.vertices.size(), profile.points.size()) << layer;
    for (std::size_t i = 0; i < line.vertices.size(); ++i) {
      const Eigen::Vector2d want = profile.points[i].*member * 1e3;
      EXPECT_NEAR(line.vertices[i].x(), want.x(), kDxfDigits) << layer << " vertex " << i;
      EXPECT_NEAR(line.vertices[i].y(), want.y(), kDxfDigits) << layer << " vertex " << i;
    }
  }
}

/// Distance from q to a closed polyline [m].
double distance_to_polyline(const Eigen::Vector2d& q, const std::vector<Eigen::Vector2d>& line) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < line.size(); ++i) {
    const Eigen::Vector2d& a = line[i];
    const Eigen::Vector2d& b = line[(i + 1) % line.size()];
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (q - (a + t * ab)).norm());
  }
  return best;
}

// The tool centre stays at the tool radius from the contour everywhere, on
// convex and on concave flanks (a radius below the smallest concave one).
TEST(ProfileExport, CutterPathIsAtTheToolRadiusFromTheContourEverywhere) {
  const Model model = model_of(concave_roller_cam());
  // The fine contour: a polyline within 1e-9 m of the curve.
  ProfileOptions fine;
  fine.chord_tolerance = 1e-9;
  const SampledCamProfile reference = sample_cam_profile(model, fine, ProfileOptionNames{"test.json"});
  ASSERT_TRUE(std::isfinite(reference.min_concave_radius)) << "the test cam should have concave flanks";
  std::vector<Eigen::Vector2d> contour;
  for (const ProfilePoint& p : reference.points) contour.push_back(p.contour);

  ProfileOptions options;
  options.points = 1500;
  options.cutter_radius = 0.5 * reference.min_concave_radius;
  const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{"test.json"});
  double worst = 0.0;
  for (const ProfilePoint& p : profile.points)
    worst = std::max(worst, std::abs(distance_to_polyline(p.cutter, contour) - *options.cutter_radius));
  // The polyline lies within its chord tolerance of the curve.
  EXPECT_LT(worst, 2.0 * fine.chord_tolerance);
}

TEST(ProfileExport, ToolRadiusAboveTheSmallestConcaveRadiusIsAnErrorNamingTheOption) {
  const Model model = model_of(concave_roller_cam());
  const SampledCamProfile plain = sample_cam_profile(model, ProfileOptions{}, ProfileOptionNames{"test.json"});
  ASSERT_TRUE(std::isfinite(plain.min_concave_radius));
  ProfileOptions options;
  options.cutter_radius = 1.01 * plain.min_concave_radius;
  try {
    sample_cam_profile(model, options, ProfileOptionNames{"", "--cutter-radius"});
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "--cutter-radius");
    EXPECT_NE(e.reason().find("concave radius of curvature"), std::string::npos) << e.what();
  }
}

// The flat-face eccentric disc is a circle of radius r_b + e about (0, −e):
// its largest radius is r_b + 2e = 0.05 m, so a tool may be up to 1000 × that.
TEST(ProfileExport, ToolRadiusIsBoundedByAThousandTimesTheCamsLargestRadius) {
  constexpr double e = 0.005, rb = 0.04, largest = rb + 2.0 * e;
  const Model model = model_of(harmonic_eccentric(e, "ccw", kFlatFace));
  const ProfileOptionNames names{"", "--cutter-radius"};
  ProfileOptions options;
  options.points = 360;
  options.cutter_radius = 0.99 * 1000.0 * largest;
  EXPECT_EQ(sample_cam_profile(model, options, names).points.size(), 360u);
  for (const double radius : {1.01 * 1000.0 * largest, 1e297}) {
    options.cutter_radius = radius;
    const InputError error = test::input_error_of([&] { sample_cam_profile(model, options, names); });
    EXPECT_EQ(error.path(), "--cutter-radius");
    EXPECT_NE(error.reason().find("more than 1000 times the cam's largest radius, 50 mm"), std::string::npos)
        << error.what();
  }
}

TEST(ProfileExport, ToolRadiusNotAFiniteNumberIsAnErrorNamingTheField) {
  const Model model = model_of(harmonic_eccentric(0.005, "ccw", kFlatFace));
  for (const double radius : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    ProfileOptions options;
    options.cutter_radius = radius;
    const InputError error = test::input_error_of([&] {
      sample_cam_profile(model, options, ProfileOptionNames{"a.json", "outputs.profile.cutter_radius_mm"});
    });
    EXPECT_EQ(error.file(), "a.json");
    EXPECT_EQ(error.path(), "outputs.profile.cutter_radius_mm");
    EXPECT_NE(error.reason().find("finite number > 0"), std::string::npos) << error.what();
  }
}

// Between consecutive points no curve strays from its chord by more than the
// tolerance: measured on a 100 000-point sampling of the same cam.
TEST(ProfileExport, ChordToleranceHoldsBetweenConsecutivePoints) {
  const Model model = model_of(concave_roller_cam());
  for (const double tolerance : {1e-4, 1e-5, 1e-6}) {
    ProfileOptions options;
    options.chord_tolerance = tolerance;
    options.cutter_radius = 0.002;
    const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{"test.json"});
    EXPECT_LE(profile.max_chord_error, tolerance);
    ProfileOptions dense;
    dense.points = 100000;
    dense.cutter_radius = options.cutter_radius;
    const SampledCamProfile truth = sample_cam_profile(model, dense, ProfileOptionNames{"test.json"});
    std::vector<double> thetas;
    for (const ProfilePoint& p : profile.points) thetas.push_back(p.theta);
    double worst = 0.0;
    for (const ProfilePoint& q : truth.points) {
      const std::size_t i =
          static_cast<std::size_t>(std::upper_bound(thetas.begin(), thetas.end(), q.theta) - thetas.begin()) - 1;
      const ProfilePoint& a = profile.points[i];
      const ProfilePoint& b = profile.points[(i + 1) % profile.points.size()];
      for (auto member : {&ProfilePoint::contour, &ProfilePoint::pitch, &ProfilePoint::cutter}) {
        const Eigen::Vector2d ab = b.*member - a.*member;
        const double t = std::clamp((q.*member - a.*member).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        worst = std::max(worst, (q.*member - (a.*member + t * ab)).norm());
      }
    }
    EXPECT_LE(worst, tolerance) << "tolerance " << tolerance << ", " << profile.points.size() << " points";
  }
}

TEST(ProfileExport, CsvHeaderNamesUnitsDirectionAndAngleOrigin) {
  const Model model = model_of(harmonic_eccentric(0.005, "cw", kRoller));
  const SampledCamProfile profile = sample_cam_profile(model, ProfileOptions{}, ProfileOptionNames{"test.json"});
  const fs::path dir = scratch("header");
  write_profile_csv(dir / "profile.csv", profile, "disc");
  std::ifstream in(dir / "profile.csv");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const char* want : {"# units: millimetres", "clockwise (cw)", "# angle origin: cam angle 0",
                           "cam_angle_deg,lift_mm,contour_x_mm,contour_y_mm,pitch_x_mm,pitch_y_mm\n"})
    EXPECT_NE(text.find(want), std::string::npos) << want << "\n" << text.substr(0, 2000);
  EXPECT_EQ(text.find("nan"), std::string::npos);
}

// outputs.profile in a config: read, defaults filled in, printed back; its errors name the field.
TEST(ProfileExport, OutputsProfileConfigIsReadWithDefaultsAndChecked) {
  SceneConfig scene;
  model_of(harmonic_eccentric(0.005, "ccw", kRoller), &scene);
  EXPECT_FALSE(scene.outputs.profile.has_value());
  auto read = [](const std::string& profile) {
    const Json doc = Json::parse(R"({"name": "p", "mechanism": )" + harmonic_eccentric(0.005, "ccw", kRoller) +
                                 R"(, "outputs": {"profile": )" + profile + "}}");
    return scene_from_json(doc, ConfigSource{"test.json", "."});
  };
  const SceneConfig defaults = read("{}");
  ASSERT_TRUE(defaults.outputs.profile.has_value());
  EXPECT_EQ(defaults.outputs.profile->chord_tolerance_mm, ProfileOutputConfig::kDefaultChordToleranceMm);
  EXPECT_EQ(to_json(defaults)["outputs"]["profile"]["formats"], Json::parse(R"(["csv", "dxf"])"));
  EXPECT_EQ(read(R"({"points": 100})").outputs.profile->chord_tolerance_mm, std::nullopt);
  // The resolved config reads back to the same scene.
  for (const char* profile : {"{}", R"({"points": 100, "formats": ["dxf"], "cutter_radius_mm": 8})"}) {
    const SceneConfig first = read(profile);
    EXPECT_TRUE(scene_from_json(to_json(first), ConfigSource{"again.json", "."}) == first) << profile;
  }
  auto error_path = [&](const std::string& profile) {
    try {
      read(profile);
    } catch (const InputError& e) {
      return e.path();
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_path(R"({"formats": ["svg"]})"), "outputs.profile.formats[0]");
  EXPECT_EQ(error_path(R"({"points": 100, "chord_tolerance_mm": 0.01})"), "outputs.profile.chord_tolerance_mm");
  EXPECT_EQ(error_path(R"({"cutter_radius_mm": -1})"), "outputs.profile.cutter_radius_mm");
  EXPECT_EQ(error_path(R"({"point": 100})"), "outputs.profile.point");
}

}  // namespace
}  // namespace camdyn
