// The valve-lobe problem by LP (objective.lift_area with design.event) on
// studies/optimize_valve_lobe.json: the lash ramps and the base circle of
// profiles/flat_tappet_valve_lift.json are unchanged to the bit; the design,
// re-checked on a fine grid of angles and speeds by the law alone (not by
// the programme's rows), keeps every constraint; its area is within 1 % of
// the any-law certificate and above every classical law of the same lift
// and duration that is jump-free at the red line; and the compliant
// simulation at every 250 rpm up to the red line stays in contact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "dynamics/contact_stress.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/optimize/design.h"
#include "optim/optimize/lobe_bound.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "optim/optimize/train_rows.h"

namespace camdyn::optim {
namespace {

const std::string kValveLobe = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_valve_lobe.json";

OptimizeStudy valve_study() {
  return read_optimize_study(load_config_json(kValveLobe, {}), ConfigSource{kValveLobe, CAMDYN_SOURCE_DIR "/studies"});
}

/// The study, its design space and its rigid stage, run once for all tests.
struct Stage {
  OptimizeStudy study = valve_study();
  DesignSpace space{study.baseline, study.config.design, kValveLobe};
  RigidStageResult result = run_rigid_stage(study.baseline, study.config, space, kValveLobe);
  SceneConfig design_scene() const { return space.scene(result.design.x); }
};

const Stage& stage() {
  static const Stage s;
  return s;
}

MotionLaw law_of(const SceneConfig& scene) { return build_motion_law(scene.mechanism.cam.motion_law, kValveLobe); }

TEST(LiftAreaDesign, KeepsTheRampsAndTheBaseCircleBitForBit) {
  const Stage& s = stage();
  ASSERT_TRUE(s.result.design.have);
  const MotionLaw base = law_of(s.study.baseline), design = law_of(s.design_scene());
  int kept = 0;
  for (int i = 0; i < 360 * 200; ++i) {
    const double theta = i * 0.005 * kDegToRad;
    if (theta >= 10.0 * kDegToRad && theta < 140.0 * kDegToRad) continue;
    const LawSample a = base.eval(theta), b = design.eval(theta);
    ASSERT_EQ(a.s, b.s) << theta / kDegToRad << " deg";
    ASSERT_EQ(a.ds, b.ds) << theta / kDegToRad << " deg";
    ASSERT_EQ(a.d2s, b.d2s) << theta / kDegToRad << " deg";
    ASSERT_EQ(a.d3s, b.d3s) << theta / kDegToRad << " deg";
    ++kept;
  }
  EXPECT_GT(kept, 40000);
  // The ramps are there: lift over [0, 10] deg rises from the base circle.
  EXPECT_GT(design.eval(9.9 * kDegToRad).s, 0.0);
}

// Every constraint from the law itself, on 0.01° and 41 speeds from 0 to the
// red line (the programme held them at 241 angles and, by the ω² argument of
// docs/optimize.md, at two speeds). Tolerances: the force margin within
// 1e-6 of the spring force scale, geometric limits to 1e-6 relative.
TEST(LiftAreaDesign, HonoursEveryConstraintOnAFineGridIndependentlyOfTheProgramme) {
  const Stage& s = stage();
  ASSERT_TRUE(s.result.design.have);
  const OptimizeStudyConfig& c = s.study.config;
  const SceneConfig scene = s.design_scene();
  const MotionLaw law = law_of(scene);
  const auto& follower = scene.mechanism.follower;
  const double m = follower.mass, k = follower.spring.stiffness, f0 = follower.spring.preload;
  const double p_min = *c.constraints.min_contact_force, rb = scene.mechanism.cam.base_radius;
  const double face = 0.5 * follower.shape.face_width - *c.constraints.face_edge_margin;
  const double top = 3500.0 * std::numbers::pi / 30.0;
  double worst_margin = 1e300, worst_rho = 1e300, worst_face = 0.0, worst_jerk = 0.0, highest = 0.0;
  for (int i = 0; i <= 13000; ++i) {
    const LawSample l = law.eval((10.0 + 0.01 * i) * kDegToRad);
    for (int j = 0; j <= 40; ++j) {
      const double w = top * j / 40.0;
      worst_margin = std::min(worst_margin, m * w * w * l.d2s + k * l.s + f0 - p_min);
    }
    worst_rho = std::min(worst_rho, rb + l.s + l.d2s);
    worst_face = std::max(worst_face, std::abs(l.ds));
    worst_jerk = std::max(worst_jerk, std::abs(l.d3s));
    highest = std::max(highest, l.s);
  }
  std::printf(
      "worst margin %.4g N, smallest radius %.5g m, largest |s'| %.5g m/rad (limit %.5g), |s'''| %.4g, lift %.6g\n",
      worst_margin, worst_rho, worst_face, face, worst_jerk, highest);
  EXPECT_GE(worst_margin, -1e-6 * f0);
  EXPECT_GE(worst_rho, *c.constraints.min_radius_of_curvature * (1 - 1e-6));
  EXPECT_LE(worst_face, face * (1 + 1e-6));
  EXPECT_LE(worst_jerk, *c.constraints.max_peak_jerk * (1 + 1e-6));
  EXPECT_LE(highest, *c.constraints.max_lift * (1 + 1e-6));
  // Hertz pressure by the dynamics code (every 0.1°, refined), at each operating speed.
  const Model model = build_model(scene, kValveLobe);
  const LineContact contact = *line_contact(scene.mechanism.contact);
  for (const double rpm : c.operating_rpm)
    EXPECT_LE(peak_rigid_contact_pressure(model, contact, rpm * std::numbers::pi / 30.0).pressure,
              *c.constraints.max_contact_stress * (1 + 1e-6))
        << rpm << " rpm";
}

TEST(LiftAreaDesign, IsWithinOnePercentOfTheCertificate) {
  const Stage& s = stage();
  const LiftAreaCertificate& a = s.result.certificate.lift_area;
  ASSERT_TRUE(a.available) << a.reason;
  const double area = lift_area(law_of(s.design_scene()), 10.0 * kDegToRad, 140.0 * kDegToRad);
  EXPECT_NEAR(area, a.design, 1e-9 * area);
  EXPECT_LE(area, a.bound * (1 + 1e-3));  // the bound is above any law, to its grid's O(h²)
  EXPECT_GE(area, 0.99 * a.bound);
  std::printf("lift area %.6g m rad, certificate %.6g m rad (%.2f %%), baseline %.6g m rad; rigid stage %.3g s\n", area,
              a.bound, 100 * area / a.bound, a.baseline, s.result.run_time_s);
}

/// A classical rise-return lobe of the valve's lift and duration (0-150 deg,
/// rise to 75 deg), no ramps.
MotionLaw classical_lobe(SegmentLaw law) {
  std::vector<SegmentConfig> segs(3);
  segs[0].type = SegmentType::rise;
  segs[0].law = law;
  segs[0].end_deg = 75.0;
  segs[0].lift = 0.009;
  segs[1].type = SegmentType::return_;
  segs[1].law = law;
  segs[1].end_deg = 150.0;
  segs[2].type = SegmentType::dwell;
  segs[2].end_deg = 360.0;
  MotionLawConfig config;
  config.segments = segs;
  return build_motion_law(config, "classical");
}

TEST(LiftAreaDesign, BeatsEveryClassicalLawThatIsJumpFreeAtTheRedLine) {
  const Stage& s = stage();
  const double area = lift_area(law_of(s.design_scene()), 0.0, 150.0 * kDegToRad);
  const auto& follower = s.study.baseline.mechanism.follower;
  const double top = 3500.0 * std::numbers::pi / 30.0, rb = s.study.baseline.mechanism.cam.base_radius;
  int jump_free = 0;
  std::printf("| law | lift area [mm rad] | min P at 3500 rpm [N] | min radius [mm] | max |s'| [mm/rad] |\n");
  for (const SegmentLaw law : classic_rise_laws()) {
    const MotionLaw lobe = classical_lobe(law);
    double low = 1e300, rho = 1e300, v = 0.0;
    for (int i = 0; i <= 15000; ++i) {
      const LawSample l = lobe.eval(0.01 * i * kDegToRad);
      low =
          std::min(low, follower.mass * top * top * l.d2s + follower.spring.stiffness * l.s + follower.spring.preload);
      rho = std::min(rho, rb + l.s + l.d2s);
      v = std::max(v, std::abs(l.ds));
    }
    const double a = lift_area(lobe, 0.0, 150.0 * kDegToRad);
    std::printf("| %s | %.4f | %.1f | %.2f | %.2f |\n", to_string(law).c_str(), 1e3 * a, low, 1e3 * rho, 1e3 * v);
    if (low < 50.0) continue;
    ++jump_free;
    EXPECT_GT(area, a) << to_string(law);
  }
  std::printf("| optimised (with the ramps) | %.4f | | | |\n", 1e3 * area);
  EXPECT_GT(jump_free, 0);
}

// The compliant model at every 250 rpm up to the red line, each run from the
// design's own start: in contact all the time, with the contact force no
// lower than P_min less the contact's own vibration (1 % of P_min).
TEST(LiftAreaDesign, StaysInContactWhenSimulatedUpToTheRedLine) {
  const Stage& s = stage();
  SceneConfig scene = s.design_scene();
  scene.study = "simulate";
  scene.simulation.cycles = 3.0;
  scene.simulation.discard_cycles = 1.0;
  double lowest = 1e300;
  for (int rpm = 250; rpm <= 3500; rpm += 250) {
    scene.mechanism.cam.rpm = rpm;
    const SimulationResult r = simulate_scene(scene, kValveLobe);
    EXPECT_EQ(r.metrics.separation_fraction, 0.0) << rpm << " rpm";
    EXPECT_EQ(r.metrics.impact_count, 0) << rpm << " rpm";
    EXPECT_GE(r.metrics.min_contact_force, 0.99 * 50.0) << rpm << " rpm";
    lowest = std::min(lowest, r.metrics.min_contact_force);
  }
  std::printf("250 to 3500 rpm: lowest contact force %.4g N\n", lowest);
}

}  // namespace
}  // namespace camdyn::optim

namespace camdyn::optim {
namespace {

// The lift-area programme on a train (studies/valvetrain/optimize_dohc_lash.json,
// red line 3700 rpm, designed up to 1.1 x that): the held train's forces are
// no parabola in ω, and its surging spring dips them in a band about 80 rpm
// wide near 3540 rpm, between the sampled speeds. The speeds are generated as
// the angles are, so the design, checked on its own held train's 2048-angle
// grid (not the programme's rows) every 10 rpm up to 4070 rpm, keeps 10 N at
// the cam and the link to within 1 % of that floor: what is left are dips
// between the programme's 1024 angles and bands a few rpm wide at a nearly
// undamped mode's resonances, which the design's own jump-free figure reports.
// (With the one-mass rows at 0 and 1.1 × the red line, on a 4200 rpm red
// line, it broke the floor by 14 N at 3540 rpm and 58 N at 4200 rpm.) It is
// faster than the baseline, and its flat face's radius of curvature, checked
// at 0.01 deg, keeps the limit the programme holds at its samples only.
TEST(LiftAreaDesignOnATrain, HoldsTheHeldTrainThroughItsResonanceBands) {
  const std::string path = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_dohc_lash.json";
  const OptimizeStudy study =
      read_optimize_study(load_config_json(path, {}), ConfigSource{path, std::filesystem::path(path).parent_path()});
  ASSERT_GT(study.config.objective.lift_area, 0.0);
  const DesignSpace space(study.baseline, study.config.design, path);
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, path);
  ASSERT_TRUE(r.design.have);
  const Model model = build_model(space.scene(r.design.x), path);
  TrainRowLimits limits;
  limits.contact_floor = limits.link_floor = 10.0;
  constexpr double kFloorShare = 0.01;                          // of the 10 N floor
  const double top = study.config.rigid.speed_factor * 3700.0;  // [rpm]
  double least = 1e300, least_rpm = 0.0;
  for (double rpm = 10.0; rpm <= top; rpm += 10.0) {
    const double m = check_held_train(model, *model.law, rpm * kRadPerSecondPerRpm, limits).margin;
    if (m < least) {
      least = m;
      least_rpm = rpm;
    }
  }
  EXPECT_GE(least, -kFloorShare * limits.contact_floor) << "at " << least_rpm << " rpm";
  ASSERT_EQ(study.config.operating_rpm.back(), 3700.0);
  ASSERT_EQ(r.design.verified_margin.size(), study.config.operating_rpm.size());
  for (const double m : r.design.verified_margin) EXPECT_GE(m, 0.0);  // every operating speed
  EXPECT_GT(r.design.jump_free_rpm, r.certificate.baseline_rpm);
  // The flat face's radius of curvature r_b + s + s'' at every 0.01 deg of
  // the event, from the law alone: the rows sit at the samples, and the
  // dense check widens them by any dip between.
  const double rb = study.baseline.mechanism.cam.base_radius;  // [m]
  double smallest = 1e300;
  for (double deg = 28.0; deg <= 152.0; deg += 0.01) {
    const LawSample a = model.law->eval(deg * std::numbers::pi / 180.0);
    smallest = std::min(smallest, rb + a.s + a.d2s);
  }
  EXPECT_GE(smallest, *study.config.constraints.min_radius_of_curvature);
}

}  // namespace
}  // namespace camdyn::optim
