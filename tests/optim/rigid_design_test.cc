// The rigid-model stage of an optimize study (optim/optimize/rigid_design.h) on the
// study studies/optimize_jump.json: its certificate against independent
// computations (the cycloidal law's jump speed from its closed-form
// acceleration, the any-law bound's closed form), its design against its
// own claims, and a target above the bound reported infeasible.
#include "optim/optimize/rigid_design.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "geometry/motion_law.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/jump_bound.h"
#include "optim/optimize/optimize.h"

namespace camdyn::optim {
namespace {

// Bisection stops at a bracket 1e-4 wide; dense sampling of a built law finds
// its minimum to ~1e-6 relative.
constexpr double kBisection = 2e-4;

OptimizeStudy rigid_jump_study(const std::vector<std::string>& overrides = {}) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_jump.json";
  return read_optimize_study(load_config_json(file, overrides), ConfigSource{file, CAMDYN_SOURCE_DIR "/studies"});
}

/// Jump speed of the quickstart's cycloidal rise with P_min, from
/// s = h (x − sin 2πx / 2π), s'' = 2π h / β² sin 2πx, sampled finely [rpm].
double cycloidal_jump_rpm(double min_force) {
  const double h = 0.02, beta = 2.0 * kPi / 3.0, m = 0.3, k = 5000.0, f0 = 40.0;
  double best = INFINITY;
  for (int i = 1; i < 200000; ++i) {
    const double x = i / 200000.0;
    const double a = 2.0 * kPi * h / (beta * beta) * std::sin(2.0 * kPi * x);
    if (a >= 0.0) continue;
    const double s = h * (x - std::sin(2.0 * kPi * x) / (2.0 * kPi));
    best = std::min(best, std::sqrt((k * s + f0 - min_force) / (-m * a)));
  }
  return best * 30.0 / kPi;
}

TEST(RigidStage, CertificateOfTheJumpStudy) {
  const OptimizeStudy study = rigid_jump_study();
  const DesignSpace space(study.baseline, study.config.design, "optimize_jump.json");
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, "optimize_jump.json");
  const Certificate& c = r.certificate;
  ASSERT_TRUE(c.available) << c.reason;
  EXPECT_EQ(c.min_contact_force, 10.0);  // the study's min_contact_force constraint
  EXPECT_NEAR(c.baseline_rpm / cycloidal_jump_rpm(10.0), 1.0, kBisection);

  RigidFollower f;
  f.mass = 0.3;
  f.stiffness = 5000.0;
  f.preload = 40.0;
  f.min_force = 10.0;
  const double any_law = any_law_jump_speed_closed_form(f, 0.0, 0.02, 2.0 * kPi / 3.0) * 30.0 / kPi;
  EXPECT_NEAR(c.any_law_rpm / any_law, 1.0, 2.0 / study.config.rigid.certificate_grid);
  // The family lies between the baseline (which it nearly contains) and any law.
  EXPECT_GT(c.family_rpm, c.baseline_rpm);
  EXPECT_LE(c.family_rpm, c.any_law_rpm * (1.0 + kBisection));
  ASSERT_EQ(c.speeds.size(), 3u);
  for (const SpeedCertificate& s : c.speeds) EXPECT_EQ(s.feasible, s.rpm <= c.family_rpm) << s.rpm;
  EXPECT_TRUE(c.all_feasible());

  const RigidDesign& d = r.design;
  ASSERT_TRUE(d.have);
  EXPECT_GE(d.lp_margin, 0.0);
  // The study weighs the peak force: the design keeps contact up to
  // speed_factor × 1300 rpm with the least peak force. Between the LP's
  // samples the margin may dip by a sliver, so the built law's own speed is
  // checked with a little room.
  for (std::size_t i = 0; i < d.verified_margin.size(); ++i)
    EXPECT_GT(d.verified_margin[i], 0.0) << study.config.operating_rpm[i];
  EXPECT_GT(d.jump_free_rpm, 0.99 * study.config.rigid.speed_factor * 1300.0);
  std::printf(
      "baseline %.1f rpm, any law %.1f rpm (%s), family %.1f rpm, design %.1f rpm, margin %.3f N, %d LPs, %.3f s\n",
      c.baseline_rpm, c.any_law_rpm, c.any_law_binding.c_str(), c.family_rpm, d.jump_free_rpm, d.lp_margin, r.lp_solves,
      r.run_time_s);
  EXPECT_TRUE(c.family_binding.empty());  // every speed is feasible and explain_bound is off
}

TEST(RigidStage, WithoutAPeakTermTheDesignIsTheFamilysFastest) {
  const OptimizeStudy study = rigid_jump_study({"objective={\"separation\": 1}"});
  const DesignSpace space(study.baseline, study.config.design, "optimize_jump.json");
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, "optimize_jump.json");
  ASSERT_TRUE(r.design.have);
  // The family's bound is good to O(1/grid); the optimizer reaches it to about as much again.
  EXPECT_NEAR(r.design.jump_free_rpm / r.certificate.family_rpm, 1.0, 3.0 / study.config.rigid.certificate_grid);
}

TEST(RigidStage, AJerkBoundHoldsInTheDesignAndLowersTheFamilysSpeed) {
  // 1.5 × the cycloidal rise's peak jerk h (2π)² / β³.
  const double beta = 2.0 * kPi / 3.0, bound = 1.5 * 0.02 * 4.0 * kPi * kPi / (beta * beta * beta);
  const OptimizeStudy free = rigid_jump_study({"objective={\"separation\": 1}"});
  const OptimizeStudy limited =
      rigid_jump_study({"objective={\"separation\": 1}", "constraints.max_peak_jerk=" + std::to_string(bound),
                        "rigid.explain_bound=true"});
  const DesignSpace space(free.baseline, free.config.design, "optimize_jump.json");
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, "optimize_jump.json");
  const RigidStageResult b = run_rigid_stage(limited.baseline, limited.config, space, "optimize_jump.json");
  ASSERT_TRUE(b.design.have);
  EXPECT_LT(b.certificate.family_rpm, a.certificate.family_rpm);
  EXPECT_NE(std::find(b.certificate.family_binding.begin(), b.certificate.family_binding.end(), "max_peak_jerk"),
            b.certificate.family_binding.end());
  // The LP holds 98 % of the bound at its samples, so the law sampled
  // densely (as the dynamic stage and `validate` sample it) meets the bound.
  const MotionLaw law = build_motion_law(space.scene(b.design.x).mechanism.cam.motion_law, "test.json");
  double peak = 0.0;
  for (int i = 0; i <= 36000; ++i) peak = std::max(peak, std::abs(law.eval(2.0 * kPi * i / 36000).d3s));
  EXPECT_LE(peak, bound);
  EXPECT_LE(law_peaks(law).jerk, bound);
}

// The radius-of-curvature limit is not linear: the stage linearises it where
// the design breaks it and designs again. The family's fastest design dips
// just below the base circle's 40 mm at the top of the rise; a 39.9 mm limit
// must hold in it afterwards, checked by the geometry code's own sampling
// (what `validate` checks).
TEST(RigidStage, CurvatureLimitHoldsAfterTightening) {
  const double limit = 0.0399;
  const OptimizeStudy free =
      rigid_jump_study({"objective={\"separation\": 1}", "constraints.min_radius_of_curvature=null"});
  const OptimizeStudy limited = rigid_jump_study(
      {"objective={\"separation\": 1}", "constraints.min_radius_of_curvature=" + std::to_string(limit)});
  const DesignSpace space(free.baseline, free.config.design, "optimize_jump.json");
  auto radius = [&](const RigidDesign& d) {
    SceneConfig scene = space.scene(d.x);
    scene.mechanism.cam.rpm = 1300;
    return build_model(scene, "test.json").geometry.min_radius_of_curvature;
  };
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, "optimize_jump.json");
  ASSERT_TRUE(a.design.have);
  ASSERT_LT(radius(a.design), limit);  // the case is worth testing
  const RigidStageResult b = run_rigid_stage(limited.baseline, limited.config, space, "optimize_jump.json");
  ASSERT_TRUE(b.design.have);
  EXPECT_GE(radius(b.design), limit);
  EXPECT_GT(b.design.jump_free_rpm, 1300.0);
  std::printf("radius %.5g -> %.5g m, jump-free %.5g -> %.5g rpm, %d LPs\n", radius(a.design), radius(b.design),
              a.design.jump_free_rpm, b.design.jump_free_rpm, b.lp_solves);
}

// An oscillating roller (studies/followers/oscillating_roller.json): the
// same programme in the arm angle, torque about the pivot as the margin.
TEST(RigidStage, OscillatingArmGetsACertificateAndADesign) {
  const std::string file = std::string(CAMDYN_SOURCE_DIR) + "/studies/followers/oscillating_roller.json";
  Json doc = load_config_json(file);
  doc["study"] = "optimize";
  doc["mechanism"]["cam"].erase("rpm");
  doc["mechanism"]["follower"]["damping"] = 0.0;  // so that the closed forms hold exactly
  doc["design"] = Json{{"segments", {"rise", "return"}}, {"control_points", 6}, {"degree", 5}};
  doc["operating_rpm"] = {1200, 1600};
  doc["objective"] = Json{{"separation", 1}};
  doc["constraints"] = Json{{"max_pressure_angle_deg", nullptr}};
  const OptimizeStudy study = read_optimize_study(doc, ConfigSource{file, CAMDYN_SOURCE_DIR "/studies/followers"});
  const DesignSpace space(study.baseline, study.config.design, file);
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, file);
  const Certificate& c = r.certificate;
  ASSERT_TRUE(c.available) << c.reason;
  EXPECT_EQ(c.margin_unit, "N m");
  // With P_min = 0 and no damper the condition is the model's own jump speed.
  SceneConfig at = study.baseline;
  at.mechanism.cam.rpm = 1600;
  // Bisection on the sampled arm margin, the lever sampled as well.
  EXPECT_NEAR(c.baseline_rpm / jump_speed_rpm(build_model(at, file)), 1.0, 5 * kBisection);
  // The rise: 12 deg over 120 deg, arm inertia 2e-3 kg m², 50 N m/rad, 5 N m.
  RigidFollower f;
  f.mass = 0.002;
  f.stiffness = 50.0;
  f.preload = 5.0;
  const double any_law = any_law_jump_speed_closed_form(f, 0.0, 12.0 * kPi / 180.0, 2.0 * kPi / 3.0) * 30.0 / kPi;
  EXPECT_NEAR(c.any_law_rpm / any_law, 1.0, 2.0 / study.config.rigid.certificate_grid);
  EXPECT_GT(c.family_rpm, c.baseline_rpm);
  EXPECT_LE(c.family_rpm, c.any_law_rpm * (1.0 + kBisection));
  EXPECT_TRUE(c.all_feasible());  // 1600 rpm is above the baseline's jump speed, not the family's
  ASSERT_TRUE(r.design.have);
  EXPECT_GT(r.design.jump_free_rpm, 1600.0);
}

TEST(RigidStage, TargetAboveTheBoundIsInfeasible) {
  const OptimizeStudy study = rigid_jump_study({"operating_rpm=[1000, 2500]"});
  const DesignSpace space(study.baseline, study.config.design, "optimize_jump.json");
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, "optimize_jump.json");
  const Certificate& c = r.certificate;
  ASSERT_TRUE(c.available);
  EXPECT_LT(c.any_law_rpm, 2500.0);
  ASSERT_EQ(c.speeds.size(), 2u);
  EXPECT_TRUE(c.speeds[0].feasible);
  EXPECT_FALSE(c.speeds[1].feasible);
  EXPECT_LT(c.speeds[1].best_margin, 0.0);
  EXPECT_FALSE(c.all_feasible());
  EXPECT_TRUE(r.design.have);              // the best design is still made
  ASSERT_FALSE(c.family_binding.empty());  // an infeasible speed: what holds the bound down is named
  EXPECT_NE(c.family_binding[0].find("spline family"), std::string::npos) << c.family_binding[0];
}

}  // namespace
}  // namespace camdyn::optim
