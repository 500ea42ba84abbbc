// The rigid-model contact pressure (dynamics/contact_stress.h) on the
// cycloidal roller cam, against an independent computation from the law
// alone: the pitch curve r_p(θ) = y₀ + s(θ) as a polar curve (curvature
// (r_p² + 2 r_p'² − r_p r_p'') / (r_p² + r_p'²)^{3/2}), the contour's radius
// ρ_p − r, the normal force P / cos φ with tan φ = s' / r_p, and Johnson's
// half-width route to p₀. And the scene limit `mechanism.cam.limits.max_contact_stress`.
#include "dynamics/contact_stress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/constants.h"
#include "common/errors.h"
#include "scenes.h"

namespace camdyn {
namespace {

constexpr double kE = 210e9, kNu = 0.3, kWidth = 0.012;  // steel on steel, 12 mm wide [Pa, -, m]
// The independent 0.005° grid misses a peak by ½ |p''/p| Δθ² (Δθ² ≈ 8e-9 rad²,
// |p''/p| below 100 /rad² here); golden section finds it to ~1e-10.
constexpr double kGridPeak = 1e-6;  // relative

SceneConfig steel_roller_scene(double rpm) {
  SceneConfig s = test::cycloidal_cam_scene(rpm);
  ContactConfig& c = s.mechanism.contact;
  c.stiffness.reset();
  c.from_materials = MaterialsConfig{kE, kNu, kE, kNu, kWidth};
  c.exponent = 1.0;  // line contact
  return s;
}

/// The peak over a 0.005° grid, from the law and the follower's data only.
double independent_peak(const SceneConfig& scene, const MotionLaw& law, double omega) {
  const double r = scene.mechanism.follower.shape.radius, y0 = scene.mechanism.cam.base_radius + r;
  const FollowerConfig& f = scene.mechanism.follower;
  const double e_star = 1.0 / (2.0 * (1.0 - kNu * kNu) / kE);
  double best = 0.0;
  for (int i = 0; i < 72000; ++i) {
    const LawSample s = law.eval(2.0 * kPi * i / 72000.0);
    const double force = f.mass * omega * omega * s.d2s + f.spring.stiffness * s.s + f.spring.preload;
    const double rp = y0 + s.s;
    const double rho_pitch = std::pow(rp * rp + s.ds * s.ds, 1.5) / (rp * rp + 2.0 * s.ds * s.ds - rp * s.d2s);
    const double radius = 1.0 / (1.0 / (rho_pitch - r) + 1.0 / r);  // 1/R = κ_cam + κ_roller
    const double normal = force * std::sqrt(rp * rp + s.ds * s.ds) / rp;
    if (!(normal > 0.0) || !(radius > 0.0)) continue;
    const double b = std::sqrt(4.0 * normal * radius / (kPi * kWidth * e_star));
    best = std::max(best, 2.0 * normal / (kPi * b * kWidth));
  }
  return best;
}

TEST(ContactStress, PeakMatchesTheIndependentPolarCurveComputation) {
  for (const double rpm : {0.0, 600.0, 1100.0}) {
    SCOPED_TRACE(rpm);
    const SceneConfig scene = steel_roller_scene(rpm);
    const Model model = build_model(scene, "test");
    const double omega = rpm * 2.0 * kPi / 60.0;
    const PressurePeak peak = peak_rigid_contact_pressure(model, *line_contact(scene.mechanism.contact), omega);
    EXPECT_NEAR(peak.pressure / independent_peak(scene, *model.law, omega), 1.0, kGridPeak);
    EXPECT_GE(peak.at_deg, 0.0);
    EXPECT_LT(peak.at_deg, 360.0);
  }
}

TEST(ContactStress, SceneLimitIsCheckedWhenTheModelIsBuilt) {
  SceneConfig scene = steel_roller_scene(1000.0);
  const Model model = build_model(scene, "test");
  const double peak = peak_rigid_contact_pressure(model, *line_contact(scene.mechanism.contact), model.omega).pressure;
  scene.mechanism.cam.limits.max_contact_stress = 1.01 * peak;
  EXPECT_NO_THROW(build_model(scene, "test"));
  scene.mechanism.cam.limits.max_contact_stress = 0.99 * peak;
  try {
    build_model(scene, "cam.json");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.cam.limits.max_contact_stress"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Hertz contact pressure reaches"), std::string::npos) << e.what();
  }
}

TEST(ContactStress, SceneLimitWithoutLineContactMaterialsIsAnInputError) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0);  // stiffness given, no materials
  scene.mechanism.cam.limits.max_contact_stress = 1e9;
  try {
    build_model(scene, "cam.json");
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("from_materials"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camdyn
