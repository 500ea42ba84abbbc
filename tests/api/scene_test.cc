// camdyn::Scene (<camdyn/scene.h>): loading checks as much as `camdyn
// validate` does, and an error names the file and the dotted path; overrides
// work as --set does; the resolved config reads back to the same scene.
#include <camdyn/scene.h>
#include <camdyn/simulate.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/errors.h"
#include "dynamics/cam_geometry.h"
#include "dynamics/cam_outline.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "input_error_of.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "study/simulation_output.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpusDir = fs::path(CAMDYN_TEST_DATA_DIR) / "bad_configs";

TEST(Scene, LoadsWhatTheCliLoads) {
  const Scene scene = Scene::load(kQuickstart);
  const SceneConfig internal = load_scene(kQuickstart);
  EXPECT_EQ(scene.name(), internal.name);
  EXPECT_EQ(scene.rpm(), internal.mechanism.cam.rpm);
  EXPECT_EQ(scene.resolved_json(), dump_json(to_json(internal)));
  EXPECT_EQ(scene.jump_speed_rpm(), jump_speed_rpm(build_model(internal, kQuickstart)));
}

TEST(Scene, OverridesWorkAsSetDoes) {
  const std::vector<std::string> overrides = {"cam.rpm=1000", "mechanism.follower.mass=0.25", "name=slower"};
  const Scene scene = Scene::load(kQuickstart, overrides);
  EXPECT_EQ(scene.rpm(), 1000.0);
  EXPECT_EQ(scene.name(), "slower");
  EXPECT_EQ(scene.resolved_json(), dump_json(to_json(load_scene(kQuickstart, overrides))));
  // A lighter follower jumps at a higher speed (the same spring force on less inertia).
  EXPECT_GT(scene.jump_speed_rpm(), Scene::load(kQuickstart).jump_speed_rpm());
}

// Scene::set changes the model in place: a speed sweep builds no geometry and
// runs to the bit as scenes loaded with the override; a change of geometry
// (the base radius) builds it again; copies keep the old values.
TEST(Scene, SetRunsAsAReloadToTheBitAndKeepsTheGeometryWhenItCan) {
  Scene scene = Scene::load(kQuickstart, {"simulation.cycles=2"});
  const Scene before = scene;
  SimulateOptions options;
  options.record_series = false;
  const long builds = cam_geometry_builds();
  for (const double rpm : {800.0, 1500.0}) {
    scene.set("cam.rpm", rpm);
    const Result swept = simulate(scene, options);
    const long after_sweep = cam_geometry_builds();
    const Result loaded =
        simulate(Scene::load(kQuickstart, {"simulation.cycles=2", "cam.rpm=" + std::to_string(rpm)}), options);
    EXPECT_EQ(after_sweep, cam_geometry_builds() - 1) << "only the reload builds a geometry";
    EXPECT_EQ(swept.metrics.at("peak_contact_force"), loaded.metrics.at("peak_contact_force"));
    EXPECT_EQ(swept.metrics.at("min_contact_force"), loaded.metrics.at("min_contact_force"));
    EXPECT_EQ(swept.metrics.at("energy_residual"), loaded.metrics.at("energy_residual"));
    EXPECT_EQ(swept.solver.steps, loaded.solver.steps);
  }
  EXPECT_EQ(cam_geometry_builds() - builds, 2);
  EXPECT_EQ(before.rpm(), 1300.0);
  scene.set("mechanism.contact.stiffness", 2e9);
  scene.set("follower.mass", 0.25);
  EXPECT_EQ(scene.resolved_json(), Scene::load(kQuickstart, {"simulation.cycles=2", "cam.rpm=1500",
                                                             "mechanism.contact.stiffness=2e9", "follower.mass=0.25"})
                                       .resolved_json());
  const long geometry_before = cam_geometry_builds();
  scene.set("cam.base_radius", 0.045);
  EXPECT_EQ(cam_geometry_builds() - geometry_before, 1);
  EXPECT_GT(scene.jump_speed_rpm(), 0.0);
}

TEST(Scene, SetRefusesWhatTheLoaderRefusesAndLeavesTheSceneAsItWas) {
  Scene scene = Scene::load(kQuickstart);
  const std::string resolved = scene.resolved_json();
  try {
    scene.set("follower.mass", -1.0);
    ADD_FAILURE() << "a negative mass was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), "mechanism.follower.mass");
    EXPECT_NE(std::string(e.what()).find("must be > 0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene.set("cam.rpmm", 1000.0), InputError);
  // NaN has no JSON form (it arrived as null): named as what it is.
  const InputError nan = test::input_error_of([&] { scene.set("cam.rpm", std::numeric_limits<double>::quiet_NaN()); });
  EXPECT_EQ(nan.path(), "cam.rpm");
  EXPECT_EQ(nan.reason(), "expected a finite number, got nan");
  EXPECT_EQ(scene.resolved_json(), resolved);
  scene.set("contact.model", std::string("hertz"));
  EXPECT_NE(scene.resolved_json().find("\"hertz\""), std::string::npos);
}

TEST(Scene, FromJsonReadsTheResolvedConfigBack) {
  const Scene scene = Scene::load(kQuickstart, {"cam.rpm=1100"});
  const Scene again = Scene::from_json(scene.resolved_json(), kStudiesDir);
  EXPECT_EQ(again.resolved_json(), scene.resolved_json());
  EXPECT_EQ(again.jump_speed_rpm(), scene.jump_speed_rpm());
  EXPECT_EQ(Scene::from_json(scene.resolved_json(), kStudiesDir, {"cam.rpm=900"}).rpm(), 900.0);
}

TEST(Scene, FromJsonResolvesRelativeFilesAgainstBaseDir) {
  // quickstart.json's motion_law names "profiles/...", relative to the repository.
  const std::string text = read_json_file(kQuickstart).dump();
  EXPECT_EQ(Scene::from_json(text, CAMDYN_SOURCE_DIR).resolved_json(), Scene::load(kQuickstart).resolved_json());
}

TEST(Scene, ModelIsSummaryJsonsModel) {
  const Scene scene = Scene::load(kQuickstart);
  const Model model = build_model(load_scene(kQuickstart), kQuickstart);
  const ModelInfo info = scene.model();
  EXPECT_EQ(info.states, model.layout.names);
  EXPECT_EQ(info.elements, model.elements);
  EXPECT_EQ(info.cam, drive_name(model));
  EXPECT_EQ(info.follower, "translating_roller");
  EXPECT_EQ(info.contact_pair, contact_pair_name(model));
}

TEST(Scene, ProfileIsTheModelsOutline) {
  const Scene scene = Scene::load(kQuickstart);
  const CamOutline outline = cam_outline(build_model(load_scene(kQuickstart), kQuickstart), 100);
  const CamProfile profile = scene.profile(100);
  EXPECT_EQ(profile.u, outline.u);
  EXPECT_EQ(profile.contour_x, outline.contour_x);
  EXPECT_EQ(profile.contour_y, outline.contour_y);
  EXPECT_EQ(profile.pitch_x, outline.pitch_x);
  EXPECT_EQ(profile.pitch_y, outline.pitch_y);
  for (const int points : {2, kMaxPointsPerCall + 1}) {
    const InputError e = test::input_error_of([&] { scene.profile(points); });
    EXPECT_EQ(e.path(), "points");
    EXPECT_EQ(e.file(), "");
    EXPECT_NE(e.reason().find(std::to_string(points)), std::string::npos) << e.reason();
  }
}

TEST(Scene, LawIsTheModelsLawAtAnglesInDegrees) {
  const Scene scene = Scene::load(kQuickstart);
  const Model model = build_model(load_scene(kQuickstart), kQuickstart);
  const std::vector<double> angles = {0.0, 45.0, 60.0, 150.0, 250.0, 420.0, -30.0};
  const LawValues v = scene.law(angles);
  ASSERT_EQ(v.s.size(), angles.size());
  for (std::size_t i = 0; i < angles.size(); ++i) {
    const LawSample l = model.law->eval(angles[i] * std::numbers::pi / 180.0);
    EXPECT_EQ(v.s[i], l.s);
    EXPECT_EQ(v.ds[i], l.ds);
    EXPECT_EQ(v.d2s[i], l.d2s);
    EXPECT_EQ(v.d3s[i], l.d3s);
  }
  // The cycloidal rise of 20 mm over 120°: half the lift at 60°, all of it
  // on the dwell to 180°, none on the dwell from 300°; periodic in 360°
  // (to the rounding of the angle reduced modulo 2π).
  EXPECT_NEAR(v.s[2], 0.01, 1e-15);
  EXPECT_NEAR(v.s[3], 0.02, 1e-15);
  EXPECT_NEAR(v.s[5], v.s[2], 1e-15);
  EXPECT_NEAR(v.s[6], 0.0, 1e-15);
  // An angle that is not finite has no place on the cam (its law was zero).
  const InputError e = test::input_error_of([&] { scene.law({0.0, std::numeric_limits<double>::quiet_NaN()}); });
  EXPECT_EQ(e.path(), "angles_deg");
  EXPECT_EQ(e.reason(), "angles_deg[1] is nan: must be a finite number [deg]");
  EXPECT_EQ(test::input_error_of([&] { scene.law(std::vector<double>(kMaxPointsPerCall + 1, 0.0)); }).path(),
            "angles_deg");
}

TEST(Scene, BadConfigNamesFileAndDottedPath) {
  const InputError e = test::input_error_of([] { (void)Scene::load(kQuickstart, {"cam.rpmm=3"}); });
  EXPECT_EQ(e.file(), kQuickstart);
  EXPECT_EQ(e.path(), "mechanism.cam.rpmm");
  EXPECT_NE(std::string(e.what()).find("did you mean 'rpm'?"), std::string::npos) << e.what();

  const InputError negative = test::input_error_of([] { (void)Scene::load(kQuickstart, {"follower.mass=-1"}); });
  EXPECT_EQ(negative.path(), "mechanism.follower.mass");
}

TEST(Scene, BadJsonTextNamesThePath) {
  const InputError e =
      test::input_error_of([] { (void)Scene::from_json(R"({"mechanism": {"cam": {"rpm": "fast"}}})"); });
  EXPECT_EQ(e.file(), "");
  EXPECT_EQ(e.path(), "mechanism.cam.rpm");
  const InputError syntax = test::input_error_of([] { (void)Scene::from_json("{\"name\": }"); });
  EXPECT_NE(syntax.path().find("line 1"), std::string::npos) << syntax.what();
}

// Every file of the bad-config corpus, config and geometry stage alike, is
// rejected by Scene::load (which builds the cam, as `camdyn validate` does)
// with an InputError naming the file and the expected dotted path.
TEST(Scene, RejectsEveryBadConfigOfTheCorpus) {
  const Json expected = read_json_file((kCorpusDir / "expected.json").string());
  int checked = 0;
  for (const auto& item : expected.at("files").items()) {
    const std::string file = (kCorpusDir / item.key()).string();
    const std::string path = item.value().at("path").get<std::string>();
    const InputError e = test::input_error_of([&] { (void)Scene::load(file); });
    EXPECT_NE(e.path().find(path), std::string::npos) << item.key() << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(item.key()), std::string::npos) << item.key() << ": " << e.what();
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

}  // namespace
}  // namespace camdyn
