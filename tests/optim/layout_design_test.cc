// The cam layout (optim/optimize/layout_design.h) against closed forms: a
// translating roller follower without offset on the quickstart's cycloidal
// rise and return has pressure angle tan φ = |s'| / (r_b + r_r + s), so the
// smallest base radius that keeps φ ≤ α is max over θ of |s'| / tan α − s − r_r,
// and the cam's largest contour radius is then r_b + h.
#include "optim/optimize/layout_design.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "cli_run.h"
#include "common/constants.h"
#include "common/errors.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

TEST(LayoutDesign, SmallestBaseRadiusForAPressureAngleIsTheClosedForm) {
  const SceneConfig scene = load_scene(kQuickstart);
  const double h = 0.02, beta = 2.0 * kPi / 3.0, r_roller = scene.mechanism.follower.shape.radius;
  const double alpha = 25.0 * kPi / 180.0;
  // max over the cycloidal rise of s' / tan α − s (the return mirrors it).
  double needed = 0.0;
  for (int k = 0; k <= 200000; ++k) {
    const double x = beta * k / 200000.0;
    const double s = h * (x / beta - std::sin(2.0 * kPi * x / beta) / (2.0 * kPi));
    const double ds = h / beta * (1.0 - std::cos(2.0 * kPi * x / beta));
    needed = std::max(needed, ds / std::tan(alpha) - s);
  }
  const double expected = needed - r_roller;
  LayoutConfig layout;
  layout.base_radius = std::vector<double>{0.005, 0.1};
  const LayoutResult r = design_layout(scene, layout, {25.0, std::nullopt}, kQuickstart);
  ASSERT_TRUE(r.best.feasible()) << r.best.error;
  ASSERT_EQ(r.names.size(), 1u);
  // COBYLA's tolerance on x (1e-6 relative) and the pressure-angle sampling (3600 points, refined).
  EXPECT_NEAR(r.best.values[0] / expected, 1.0, 1e-4);
  EXPECT_LE(r.best.report.max_pressure_angle_deg, 25.0 * (1.0 + 1e-9));
  EXPECT_NEAR(r.best.cam_size / (r.best.values[0] + h), 1.0, 1e-4);
  EXPECT_LT(r.best.cam_size, r.baseline.cam_size);
}

TEST(LayoutDesign, RangesAreChecked) {
  const SceneConfig scene = load_scene(kQuickstart);
  LayoutConfig layout;
  layout.arm_length = std::vector<double>{0.05, 0.1};
  try {
    check_layout(scene, layout, "test.json");
    FAIL() << "an arm length for a translating follower";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "design.layout.arm_length");
  }
  EXPECT_THROW(check_layout(scene, LayoutConfig{}, "test.json"), InputError);
}

TEST(LayoutDesign, PackagingArmStudyIsSmallerMeetsItsLimitsAndItsConfigRuns) {
  const fs::path dir = test::scratch_dir("layout_design_test", "packaging_arm");
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/layout_packaging_arm.json";
  const test::Outcome r = test::run_camdyn({"run", file, "--out", (dir / "out").string(), "--quiet"}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(test::read_text(dir / "out" / "result.json"));
  EXPECT_EQ(j["verdict"], "good");
  const Json& best = j["optimized"];
  EXPECT_TRUE(best["feasible"].get<bool>());
  EXPECT_LT(best["cam_size"].get<double>(), j["baseline"]["cam_size"].get<double>());
  EXPECT_LE(best["max_pressure_angle_deg"].get<double>(), 30.0 * (1.0 + 1e-9));
  EXPECT_GE(best["min_radius_of_curvature"].get<double>(), 0.005 * (1.0 - 1e-9));
  // The optimised layout is a scene camdyn runs.
  const test::Outcome v = test::run_camdyn({"validate", (dir / "out" / "optimized.json").string()}, dir, "validate");
  EXPECT_EQ(v.code, 0) << v.err;
}

TEST(LayoutDesign, NoFeasibleLayoutIsARedVerdictNotASolverFailure) {
  const fs::path dir = test::scratch_dir("layout_design_test", "infeasible");
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/layout_packaging_arm.json";
  const test::Outcome r = test::run_camdyn(
      {"run", file, "--out", (dir / "out").string(), "--quiet", "--set", "constraints.max_pressure_angle_deg=1"}, dir);
  ASSERT_EQ(r.code, 0) << r.err;
  const Json j = Json::parse(test::read_text(dir / "out" / "result.json"));
  EXPECT_EQ(j["verdict"], "bad");
  EXPECT_FALSE(j["optimized"]["feasible"].get<bool>());
  EXPECT_NE(r.out.find("no layout in the ranges meets the limits"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace camdyn::optim
