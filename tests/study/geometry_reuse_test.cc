// A design's geometry (dynamics/cam_geometry.h) is built once and shared by
// every speed a study runs: a 200-speed jump map and a speed_limit scan build
// it once each; a model assembled on a shared geometry, or with its speed set
// in place, is the one build_model makes from the scene, to the bit.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "dynamics/cam_geometry.h"
#include "dynamics/contact_stress.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "study/jump_map.h"
#include "study/speed_limit.h"
#include "study/study.h"
#include "study_paths.h"

namespace camdyn {
namespace {

StudyContext context() {
  StudyContext ctx;
  ctx.config_file = kQuickstart;
  ctx.source = config_source(kQuickstart);
  ctx.jobs = 1;
  return ctx;
}

/// The runs of two models agree to the last bit: every step, event and metric.
void expect_same_run(const SceneConfig& scene, const Model& a, const Model& b) {
  SimulationOptions options;
  options.record_series = true;
  Workspace wa, wb;
  const SimulationResult ra = simulate(scene, a, wa, options), rb = simulate(scene, b, wb, options);
  ASSERT_TRUE(ra.solver.converged()) << ra.solver.message;
  EXPECT_EQ(ra.solver.counters.steps, rb.solver.counters.steps);
  EXPECT_EQ(ra.metrics.peak_contact_force, rb.metrics.peak_contact_force);
  EXPECT_EQ(ra.metrics.min_contact_force, rb.metrics.min_contact_force);
  EXPECT_EQ(ra.metrics.separation_fraction, rb.metrics.separation_fraction);
  EXPECT_EQ(ra.metrics.energy_residual, rb.metrics.energy_residual);
  EXPECT_EQ(ra.series.follower_position, rb.series.follower_position);
  EXPECT_EQ(ra.series.contact_force, rb.series.contact_force);
}

TEST(CamGeometry, AModelOnASharedGeometryIsTheModelBuiltFromTheScene) {
  SceneConfig scene = load_scene(kQuickstart);
  scene.simulation.cycles = 2.0;
  const std::shared_ptr<const CamGeometry> geometry = build_cam_geometry(scene, kQuickstart);
  for (const double rpm : {700.0, 1300.0, 1900.0}) {
    scene.mechanism.cam.rpm = rpm;
    const Model fresh = build_model(scene, kQuickstart);
    const Model shared = build_model(*geometry, scene, kQuickstart);
    EXPECT_EQ(shared.law, geometry->law);  // the same curves, not copies
    EXPECT_EQ(shared.omega, fresh.omega);
    EXPECT_EQ(shared.tracking_gain, fresh.tracking_gain);
    expect_same_run(scene, fresh, shared);
  }
}

TEST(CamGeometry, SettingTheSpeedInPlaceIsTheModelBuiltAtThatSpeed) {
  SceneConfig scene = load_scene(kQuickstart);
  scene.simulation.cycles = 2.0;
  Model model = build_model(scene, kQuickstart);
  const long builds = cam_geometry_builds();
  for (const double rpm : {900.0, 1500.0}) {
    scene.mechanism.cam.rpm = rpm;
    set_cam_speed(model, scene, kQuickstart);
    const Model fresh = build_model(scene, kQuickstart);
    EXPECT_EQ(model.omega, fresh.omega);
    EXPECT_EQ(model.tracking_gain, fresh.tracking_gain);
    expect_same_run(scene, fresh, model);
  }
  EXPECT_EQ(cam_geometry_builds() - builds, 2) << "only the two fresh models build a geometry";
}

TEST(CamGeometry, ASpeedThatBreaksASpeedDependentCheckIsRefusedInPlaceToo) {
  // A contact stress limit between the rigid-model peak pressures at two
  // speeds: set_cam_speed refuses the speed that breaks it, as build_model does.
  SceneConfig scene = load_scene(kQuickstart);
  scene.mechanism.contact.stiffness.reset();
  scene.mechanism.contact.exponent = 1.0;
  scene.mechanism.contact.from_materials = MaterialsConfig{2.1e11, 0.3, 2.1e11, 0.3, 0.01};
  const LineContact contact = *line_contact(scene.mechanism.contact);
  Model model = build_model(scene, kQuickstart);
  constexpr double kRadPerRpm = 2.0 * 3.141592653589793 / 60.0;
  const double p_slow = peak_rigid_contact_pressure(model, contact, 300.0 * kRadPerRpm).pressure;  // [Pa]
  const double p_fast = peak_rigid_contact_pressure(model, contact, 1600.0 * kRadPerRpm).pressure;
  ASSERT_NE(p_slow, p_fast);
  scene.mechanism.cam.limits.max_contact_stress = 0.5 * (p_slow + p_fast);
  const double breaks = p_fast > p_slow ? 1600.0 : 300.0, holds = p_fast > p_slow ? 300.0 : 1600.0;  // [rpm]
  scene.mechanism.cam.rpm = holds;
  model = build_model(scene, kQuickstart);
  scene.mechanism.cam.rpm = breaks;
  EXPECT_THROW(build_model(scene, kQuickstart), InputError);
  try {
    set_cam_speed(model, scene, kQuickstart);
    ADD_FAILURE() << "set_cam_speed accepted " << breaks << " rpm";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.cam.limits.max_contact_stress");
  }
}

// Two hundred speeds; forty in the sanitised build (six times slower there,
// and the count of builds does not depend on the number of speeds).
TEST(CamGeometry, AJumpMapOverManySpeedsBuildsItsGeometryOnce) {
  const StudyContext ctx = context();
  const int speeds = CAMDYN_SANITIZED ? 40 : 200;
  Json doc = load_config_json(kQuickstart, {});
  doc["study"] = "jump_map";
  doc["jump_map"] = Json::parse(R"({"low_rpm": 600, "high_rpm": 1000, "ranges": 1, "transient_revolutions": 1,
                                     "samples": 1})");
  doc["jump_map"]["speeds"] = speeds;
  doc["periodic"] = Json::parse(R"({"max_period": 1, "lyapunov_revolutions": 10})");
  const long before = cam_geometry_builds();
  const JumpMapStudy study = read_jump_map_study(doc, ctx);
  const std::vector<JumpMapPoint> points = run_jump_map_range(study, 0, ctx.config_file);
  ASSERT_EQ(std::ssize(points), speeds);
  for (const JumpMapPoint& p : points) EXPECT_TRUE(p.ok) << p.rpm << ": " << p.error;
  EXPECT_EQ(cam_geometry_builds() - before, 1);
}

TEST(CamGeometry, ASpeedLimitScanBuildsItsGeometryOnce) {
  const StudyContext ctx = context();
  Json doc = load_config_json(kQuickstart, {});
  doc["study"] = "speed_limit";
  doc["simulation"]["cycles"] = 2;
  doc["speed_limit"] = Json::parse(R"({"low_rpm": 800, "high_rpm": 2000, "scan": 12, "tolerance_rpm": 20})");
  const long before = cam_geometry_builds();
  const SpeedLimitStudy study = read_speed_limit_study(doc, ctx);
  const SpeedLimitResult r = run_speed_limit(study, ctx);
  EXPECT_TRUE(r.limited);
  EXPECT_GT(r.checks.size(), 12u - r.scan_skipped) << "the scan (up to its first failure) and the bisection";
  EXPECT_EQ(cam_geometry_builds() - before, 1);
}

}  // namespace
}  // namespace camdyn
