// A design's geometry (dynamics/cam_geometry.h) and its model are built once
// per study and shared by every speed it runs: a 100-speed jump map (in one
// range or two) and a speed_limit scan (on one thread or two) build each once;
// a model assembled on a shared geometry, or with its speed set in place, is
// the one build_model makes from the scene, to the bit, and so are the
// studies' answers.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "dynamics/cam_geometry.h"
#include "dynamics/contact_stress.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "study/jump_map.h"
#include "study/simulation_output.h"
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
  EXPECT_EQ(metrics_json(ra.metrics).dump(), metrics_json(rb.metrics).dump());  // every metric, the train's too
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

// What the studies do: a copy of the model read with the study, its speed set
// in place at each speed, on a follower and on a valve train with lash.
TEST(CamGeometry, ACopyWithItsSpeedSetInPlaceRunsAsTheModelBuiltAtThatSpeed) {
  const std::string dohc = kStudies + "valvetrain/dohc_bucket_lash.json";
  for (const auto& [path, speeds] : {std::pair{kQuickstart, std::vector<double>{800.0, 1250.0, 1800.0}},
                                     std::pair{dohc, std::vector<double>{2000.0, 3400.0, 4200.0}}}) {
    SceneConfig scene = load_scene(path);
    scene.simulation.cycles = 2.0;
    const Model study_model = build_model(scene, path);
    Model model = study_model;
    const long builds = model_builds();
    for (const double rpm : speeds) {
      SCOPED_TRACE(path + " at " + std::to_string(rpm) + " rpm");
      scene.mechanism.cam.rpm = rpm;
      set_cam_speed(model, scene, path);
      const Model fresh = build_model(scene, path);
      EXPECT_EQ(model.omega, fresh.omega);
      EXPECT_EQ(model.tracking_gain, fresh.tracking_gain);
      EXPECT_EQ(model.theta0, fresh.theta0);
      EXPECT_EQ(model.penetration_limit, fresh.penetration_limit);
      EXPECT_EQ(model.rigid_jump_speed_rpm, fresh.rigid_jump_speed_rpm);
      EXPECT_EQ(model.train_jump_speed_rpm, fresh.train_jump_speed_rpm);
      EXPECT_EQ(model.elements, fresh.elements);
      expect_same_run(scene, fresh, model);
    }
    EXPECT_EQ(model_builds() - builds, std::ssize(speeds)) << "only the fresh models are assembled";
  }
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

// A hundred speeds in two ranges; forty in the sanitised build (six times
// slower there, and the count of builds does not depend on the number of
// speeds, nor on the ranges: each copies the study's model).
TEST(CamGeometry, AJumpMapOverManySpeedsBuildsItsGeometryAndModelOnce) {
  const StudyContext ctx = context();
  const int speeds = CAMDYN_SANITIZED ? 40 : 100;
  Json doc = load_config_json(kQuickstart, {});
  doc["study"] = "jump_map";
  doc["jump_map"] = Json::parse(R"({"low_rpm": 600, "high_rpm": 1000, "ranges": 2, "transient_revolutions": 1,
                                     "samples": 1, "refine": 0, "check_coexistence": false})");
  doc["jump_map"]["speeds"] = speeds;
  doc["periodic"] = Json::parse(R"({"max_period": 1, "lyapunov_revolutions": 10})");
  const long geometries = cam_geometry_builds(), models = model_builds();
  const JumpMapStudy study = read_jump_map_study(doc, ctx);
  std::vector<JumpMapPoint> points = run_jump_map_range(study, 0, ctx.config_file);
  for (JumpMapPoint& p : run_jump_map_range(study, 1, ctx.config_file)) points.push_back(std::move(p));
  ASSERT_EQ(std::ssize(points), speeds);
  for (const JumpMapPoint& p : points) EXPECT_TRUE(p.ok) << p.rpm << ": " << p.error;
  EXPECT_EQ(cam_geometry_builds() - geometries, 1);
  EXPECT_EQ(model_builds() - models, 1);
}

TEST(CamGeometry, ASpeedLimitScanBuildsItsGeometryAndModelOnce) {
  for (const int jobs : {1, 2}) {
    StudyContext ctx = context();
    ctx.jobs = jobs;
    Json doc = load_config_json(kQuickstart, {});
    doc["study"] = "speed_limit";
    doc["simulation"]["cycles"] = 2;
    doc["speed_limit"] = Json::parse(R"({"low_rpm": 800, "high_rpm": 2000, "scan": 12, "tolerance_rpm": 20})");
    const long geometries = cam_geometry_builds(), models = model_builds();
    const SpeedLimitStudy study = read_speed_limit_study(doc, ctx);
    const SpeedLimitResult r = run_speed_limit(study, ctx);
    EXPECT_TRUE(r.limited);
    EXPECT_GT(r.checks.size(), 12u - r.scan_skipped) << "the scan (up to its first failure) and the bisection";
    EXPECT_EQ(cam_geometry_builds() - geometries, 1) << jobs << " threads";
    EXPECT_EQ(model_builds() - models, 1) << jobs << " threads";
  }
}

// The studies' answers with the model set in place are those of a model
// assembled at each speed (JumpMapStudy::model null), to the bit: a jump map
// across the quickstart's jump speed with its refinement and coexistence
// checks, and a speed_limit scan on two threads with its bisection.
TEST(CamGeometry, StudiesAnswerAsWithAModelAssembledAtEachSpeed) {
  const StudyContext ctx = context();
  Json doc = load_config_json(kQuickstart, {});
  doc["study"] = "jump_map";
  doc["jump_map"] = Json::parse(R"({"low_rpm": 1200, "speeds": 3, "ranges": 1, "transient_revolutions": 1,
                                     "samples": 1, "refine": 1})");
  // Periodic at 1200 and 1300 rpm, chaotic at 1400 (the sanitised build, six
  // times slower, stays below the change).
  doc["jump_map"]["high_rpm"] = CAMDYN_SANITIZED ? 1300 : 1400;
  doc["periodic"] = Json::parse(R"({"max_period": 1, "lyapunov_revolutions": 10})");
  JumpMapStudy map = read_jump_map_study(doc, ctx);
  map.periodic.options.settle_revolutions = 20;
  const std::vector<JumpMapPoint> in_place = run_jump_map_range(map, 0, ctx.config_file);
  map.model = nullptr;
  const std::vector<JumpMapPoint> assembled = run_jump_map_range(map, 0, ctx.config_file);
  ASSERT_EQ(in_place.size(), assembled.size());
  EXPECT_EQ(in_place.size(), CAMDYN_SANITIZED ? 3u : 4u) << "with the chaotic speed, a refined one";
  for (std::size_t i = 0; i < in_place.size(); ++i)
    EXPECT_EQ(jump_map_point_json(in_place[i]).dump(), jump_map_point_json(assembled[i]).dump());

  StudyContext two = context();
  two.jobs = 2;
  doc = load_config_json(kQuickstart, {});
  doc["study"] = "speed_limit";
  doc["simulation"]["cycles"] = 2;
  doc["speed_limit"] = Json::parse(R"({"low_rpm": 800, "high_rpm": 2000, "scan": 8, "tolerance_rpm": 20})");
  SpeedLimitStudy scan = read_speed_limit_study(doc, two);
  SpeedLimitResult a = run_speed_limit(scan, two);
  scan.model = nullptr;
  SpeedLimitResult b = run_speed_limit(scan, two);
  a.run_time_s = b.run_time_s = 0.0;
  EXPECT_EQ(speed_limit_json(scan, a).dump(), speed_limit_json(scan, b).dump());
}

}  // namespace
}  // namespace camdyn
