// An identification's inner loop (optim/identify/fit_scene.h, optim/identify/fit_residuals.h):
// values set in place give the runs the old route (the scene's JSON with the
// values, read and built again: FitScene's from_json) gives, bit for bit; no JSON is read and no
// model is built for parameters of the parameter block; setting them and
// assembling the residuals allocates nothing.
#include "optim/identify/fit_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "allocation_counter.h"
#include "common/errors.h"
#include "io/config.h"
#include "optim/identify/fit_residuals.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {
namespace {

const std::string kCamRig = std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_cam_rig/identify_cam_rig.json";
const std::string kDrop = std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_drop/identify_drop.json";

IdentifyProblem load(const std::string& file, const std::vector<std::string>& overrides = {}) {
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
    const IdentifyProblem problem = load(file);
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

TEST(FitScene, ParameterBlockPathsAreBoundToTypedFieldsOthersFallBack) {
  SceneConfig scene = load(kCamRig).experiments[0].scene;
  for (const char* path : {"mechanism.contact.stiffness", "mechanism.contact.restitution", "mechanism.contact.exponent",
                           "mechanism.follower.damping", "mechanism.follower.spring.stiffness",
                           "mechanism.follower.mass", "mechanism.contact.friction.mu"}) {
    const std::optional<FieldBinding> b = bind_field(path, scene);
    ASSERT_TRUE(b) << path;
    EXPECT_EQ(b->kind, FieldKind::parameter) << path;
  }
  EXPECT_EQ(bind_field("mechanism.cam.base_radius", scene)->kind, FieldKind::geometry);
  EXPECT_EQ(bind_field("mechanism.follower.initial.velocity", scene)->kind, FieldKind::scene);
  EXPECT_FALSE(bind_field("mechanism.cam.motion_law.segments[0].lift", scene));
  EXPECT_FALSE(bind_field("mechanism.follower.guide_friction.mu", scene));  // no guide friction in the scene
}

TEST(FitScene, GeometryIsRebuiltFromTheTypedSceneAndOtherPathsFromJson) {
  const IdentifyProblem geometry = load(kCamRig, {"parameters.cam.base_radius={\"lower\": 0.035, \"upper\": 0.045}"});
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

  Json doc = load_config_json(kCamRig);
  doc["parameters"]["cam.initial_angle_deg"] = Json{{"lower", -1.0}, {"upper", 1.0}};  // no typed field
  const IdentifyProblem untyped = load_identify_problem(doc, config_source(kCamRig));
  FitScene fallback(untyped.experiments[0], untyped.parameters, untyped.source);
  fallback.set({1e10, 15.0, 0.5});
  EXPECT_EQ(fallback.json_reads(), 1);
}

TEST(FitScene, SettingParametersAndAssemblingResidualsAllocatesNothing) {
  const IdentifyProblem problem = load(kCamRig);
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
