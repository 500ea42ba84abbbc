// An identification's inner loop (optim/identify/fit_scene.h, optim/identify/fit_residuals.h):
// values set in place give the runs the old route (the scene's JSON with the
// values, read and built again: FitScene's from_json) gives, bit for bit; no JSON is read and no
// model is built for the fields the model is assembled from (set in place); setting them and
// assembling the residuals allocates nothing.
#include "optim/identify/fit_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "allocation_counter.h"
#include "common/errors.h"
#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "optim/identify/fit_residuals.h"
#include "optim/identify/identify.h"
#include "tests/dynamics/scenes.h"

namespace camdyn::optim {
namespace {

const std::string kCamRig = std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_cam_rig/identify_cam_rig.json";
const std::string kDrop = std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_drop/identify_drop.json";

IdentifyProblem load_fit_problem(const std::string& file, const std::vector<std::string>& overrides = {}) {
  return load_identify_problem(load_config_json(file, overrides), config_source(file));
}

/// Values in the bounds of the problem's parameters, away from the initial ones.
std::vector<std::vector<double>> trial_values(const IdentifyProblem& problem) {
  std::vector<std::vector<double>> trials;
  for (const double factor : {1.0, 0.7, 1.2, 0.9}) {
    std::vector<double> v;
    for (const FitParameter& p : problem.parameters) v.push_back(std::clamp(p.initial * factor, p.lower, p.upper));
    trials.push_back(v);
  }
  return trials;
}

TEST(FitScene, ValuesSetInPlaceGiveTheRunsOfTheRebuiltSceneBitForBit) {
  for (const std::string& file : {kCamRig, kDrop}) {
    const IdentifyProblem problem = load_fit_problem(file);
    for (const FitExperiment& e : problem.experiments) {
      FitScene scene(e, problem.parameters, problem.source);
      FitScene rebuilt(e, problem.parameters, problem.source, /*from_json=*/true);
      for (const std::vector<double>& values : trial_values(problem)) {
        const FitRun run = scene.run(values);
        ASSERT_TRUE(run.ok) << run.error;
        const std::vector<std::vector<double>> expected = rebuilt.run(values).signals;
        ASSERT_EQ(run.signals.size(), expected.size());
        for (std::size_t s = 0; s < expected.size(); ++s) {
          ASSERT_EQ(run.signals[s].size(), expected[s].size());
          for (std::size_t i = 0; i < expected[s].size(); ++i)
            ASSERT_EQ(run.signals[s][i], expected[s][i]) << file << " " << e.name << " sample " << i;
        }
      }
      EXPECT_EQ(scene.model_builds(), 0) << file;
      EXPECT_EQ(scene.json_reads(), 0) << file;
      EXPECT_EQ(rebuilt.json_reads(), 4) << file;
    }
  }
}

TEST(FitScene, TypedPathsAreBoundOthersFallBack) {
  SceneConfig scene = load_fit_problem(kCamRig).experiments[0].scene;
  for (const char* path : {"mechanism.contact.stiffness", "mechanism.contact.restitution", "mechanism.contact.exponent",
                           "mechanism.follower.damping", "mechanism.follower.spring.stiffness",
                           "mechanism.follower.mass", "mechanism.contact.friction.mu"}) {
    const std::optional<FieldBinding> b = bind_field(path, scene);
    ASSERT_TRUE(b) << path;
    EXPECT_EQ(b->kind, FieldKind::parameter) << path;
  }
  EXPECT_EQ(bind_field("mechanism.cam.base_radius", scene)->kind, FieldKind::geometry);
  EXPECT_EQ(bind_field("mechanism.follower.shape.radius", scene)->kind, FieldKind::geometry);
  EXPECT_EQ(bind_field("mechanism.follower.offset", scene)->kind, FieldKind::geometry);
  EXPECT_EQ(bind_field("mechanism.cam.rpm", scene)->kind, FieldKind::parameter);
  // The roller's inertia is the model's (its spin), not the cam's: set in place.
  ASSERT_TRUE(bind_field("mechanism.follower.shape.inertia", scene));
  EXPECT_EQ(bind_field("mechanism.follower.shape.inertia", scene)->kind, FieldKind::parameter);
  EXPECT_EQ(bind_field("mechanism.cam.initial_angle_deg", scene)->kind, FieldKind::parameter);
  EXPECT_EQ(bind_field("mechanism.follower.initial.velocity", scene)->kind, FieldKind::scene);
  // An array's element has its typed field too; the cam is built from it.
  EXPECT_EQ(bind_field("mechanism.cam.motion_law.segments[0].lift", scene)->kind, FieldKind::geometry);
  EXPECT_FALSE(bind_field("mechanism.follower.guide_friction.mu", scene));  // no guide friction in the scene
}

/// The reason the config loader gives for `key=value` on `scene`.
std::string loader_reason(const SceneConfig& scene, const std::string& key, const std::string& value) {
  Json doc = to_json(scene);
  set_config_value(doc, key, Json::parse(value));
  try {
    scene_from_json(doc, ConfigSource{"test", "."});
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), key);
    return e.reason();
  }
  ADD_FAILURE() << key << " = " << value << " was accepted";
  return "";
}

// A fitted value is checked with the loader's own checks of its field, so a
// value no config may give is refused with the loader's words.
TEST(FitScene, ABadValueIsRefusedWithTheConfigLoadersReason) {
  SceneConfig scene = test::cycloidal_cam_scene(1000.0, ContactModel::lankarani_nikravesh);
  const std::pair<const char*, double> cases[] = {
      {"mechanism.contact.restitution", 1.5},
      {"mechanism.contact.exponent", 0.0},
      // In the range (0, 5] but below the loader's minimum (a condition of its visit, not a range).
      {"mechanism.contact.exponent", 0.4},
      {"mechanism.contact.friction.mu", -0.1},
      {"mechanism.contact.stiffness", -1.0},
      {"mechanism.contact.reference_velocity", 0.0},
      {"mechanism.follower.mass", 0.0},
      {"mechanism.follower.damping", -2.0},
      {"mechanism.follower.spring.stiffness", -1.0},
      {"mechanism.cam.base_radius", -0.04},
  };
  for (const auto& [path, value] : cases) {
    const std::optional<FieldBinding> b = bind_field(path, scene);
    ASSERT_TRUE(b) << path;
    EXPECT_EQ(b->checked.reason(value), loader_reason(scene, path, format_shortest(value))) << path;
  }
}

TEST(FitScene, GeometryIsRebuiltFromTheTypedScene) {
  const IdentifyProblem geometry =
      load_fit_problem(kCamRig, {"parameters.cam.base_radius={\"lower\": 0.035, \"upper\": 0.045}"});
  FitScene typed(geometry.experiments[0], geometry.parameters, geometry.source);
  std::vector<double> values{1e10, 15.0, 0.04};  // unchanged: nothing is rebuilt
  typed.set(values);
  EXPECT_EQ(typed.model_builds(), 0);
  values[2] = 0.041;
  typed.set(values);
  EXPECT_EQ(typed.model_builds(), 1);
  EXPECT_EQ(typed.json_reads(), 0);
  EXPECT_EQ(typed.model().follower.base_radius, 0.041);
  values[2] = -0.04;
  EXPECT_THROW(typed.set(values), InputError);

  // A motion-law constant is a typed field of the geometry: no JSON is read for it either.
  Json doc = load_config_json(kCamRig);
  doc["parameters"]["cam.motion_law.segments[0].end_deg"] = Json{{"lower", 115.0}, {"upper", 125.0}};
  const IdentifyProblem lift = load_identify_problem(doc, config_source(kCamRig));
  FitScene law(lift.experiments[0], lift.parameters, lift.source);
  law.set({1e10, 15.0, 121.0});
  EXPECT_EQ(law.model_builds(), 1);
  EXPECT_EQ(law.json_reads(), 0);
  EXPECT_EQ(law.scene().mechanism.cam.motion_law.segments[0].end_deg, 121.0);
}

TEST(FitScene, SettingParametersAndAssemblingResidualsAllocatesNothing) {
  const IdentifyProblem problem = load_fit_problem(kCamRig);
  std::vector<FitScene> scenes;
  scenes.reserve(problem.experiments.size());
  std::vector<FitRun> runs;
  for (const FitExperiment& e : problem.experiments) {
    scenes.emplace_back(e, problem.parameters, problem.source);
    runs.push_back(scenes.back().run(trial_values(problem)[1]));
    ASSERT_TRUE(runs.back().ok) << runs.back().error;
  }
  ResidualAssembler assembler(problem);
  std::vector<double> r(problem.residual_count());
  const std::vector<std::vector<double>> trials = trial_values(problem);
  const long before = test::allocation_count();
  for (const std::vector<double>& values : trials)
    for (FitScene& scene : scenes) scene.set(values);
  assembler.assemble(runs, 0.0, r.data());
  assembler.assemble(runs, 2e-3, r.data());  // a smoothed continuation stage
  EXPECT_EQ(test::allocation_count() - before, 0);
}

}  // namespace
}  // namespace camdyn::optim

namespace camdyn::optim {
namespace {

// A follower train's numbers are identifiable like the contact's (docs/model.md §12):
// a link stiffness set through its typed field gives the run of the scene read
// again with it, bit for bit, without building the model or the geometry
// again, and the train's columns are signals.
TEST(FitScene, TrainParametersAndColumnsFitLikeTheContacts) {
  const Json scene_json = Json::parse(R"({
    "name": "train-fit", "study": "simulate",
    "mechanism": {
      "cam": { "base_radius": 0.02, "rpm": 2000,
        "motion_law": { "segments": [
          { "type": "rise", "law": "harmonic", "end_deg": 180, "lift": 0.008 },
          { "type": "return", "law": "harmonic", "end_deg": 360, "lift": 0.008 } ] } },
      "follower": { "shape": { "type": "flat", "face_width": 0.06 }, "mass": 0.05,
        "spring": { "stiffness": 5000, "preload": 50 }, "damping": 1.0 },
      "contact": { "model": "kelvin_voigt", "stiffness": 1e8, "exponent": 1.0, "damping": 300 },
      "train": [ { "name": "valve", "mass": 0.08, "damping": 2.0,
        "link": { "ratio": 1.5, "stiffness": 2e7, "damping": 100 },
        "spring": { "stiffness": 30000, "preload": 300, "mass": 0.04, "coils": 4 } } ] },
    "simulation": { "cycles": 1, "discard_cycles": 0, "output_step_deg": 2 },
    "integrator": { "rtol": 1e-8, "atol": 1e-12 } })");
  const ConfigSource source = config_source("train-fit.json");
  FitExperiment e;
  e.name = "valve";
  e.scene_json = scene_json;
  e.scene = scene_from_json(scene_json, source);
  for (int i = 1; i <= 20; ++i) e.record.time.push_back(0.0015 * i);
  e.record.signals = {"valve_position", "valve_link_force"};
  FitParameter k;
  k.name = k.path = "mechanism.train[0].link.stiffness";
  k.initial = 2e7;
  k.lower = 1e6;
  k.upper = 1e9;
  FitParameter m;
  m.name = m.path = "mechanism.follower.mass";
  m.initial = 0.05;
  m.lower = 0.01;
  m.upper = 0.2;
  const std::vector<FitParameter> parameters = {k, m};  // FitScene keeps a reference
  FitScene scene(e, parameters, source);
  FitScene rebuilt(e, parameters, source, /*from_json=*/true);
  // The model and the geometry are built once, at construction: the link's
  // stiffness and the follower's mass are set in place (docs/architecture.md,
  // "Model, parameters and workspaces").
  const long geometries = cam_geometry_builds(), models = camdyn::model_builds();
  const FitRun stiff = scene.run({4e7, 0.06});
  const FitRun soft = scene.run({1e7, 0.06});
  EXPECT_EQ(cam_geometry_builds(), geometries);
  EXPECT_EQ(camdyn::model_builds(), models);
  EXPECT_EQ(scene.model_builds(), 0);
  ASSERT_TRUE(stiff.ok) << stiff.error;
  ASSERT_TRUE(soft.ok) << soft.error;
  const FitRun expected = rebuilt.run({4e7, 0.06});
  ASSERT_TRUE(expected.ok) << expected.error;
  ASSERT_EQ(stiff.signals.size(), 2u);
  EXPECT_EQ(stiff.signals, expected.signals);
  EXPECT_EQ(soft.signals, rebuilt.run({1e7, 0.06}).signals);
  EXPECT_NE(soft.signals[1], stiff.signals[1]);  // the link force feels its stiffness
  EXPECT_EQ(scene.json_reads(), 0);
  // A value no config may give is refused with the loader's reason, and the scene stays usable.
  const FitRun refused = scene.run({-1e7, 0.06});
  EXPECT_FALSE(refused.ok);
  EXPECT_TRUE(refused.input_error);
  EXPECT_NE(refused.error.find("mechanism.train[0].link.stiffness"), std::string::npos) << refused.error;
  EXPECT_EQ(scene.run({4e7, 0.06}).signals, stiff.signals);

  e.record.signals = {"cam_position"};  // no body 'cam' in this train
  try {
    FitScene wrong(e, parameters, source);
    FAIL() << "a column the train does not have was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("reference.signals.cam_position"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace camdyn::optim
