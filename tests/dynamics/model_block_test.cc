// summary.json's `model` block (interface.md): the bare scene has only the
// follower coordinate and its rate (plus the tracking parameter with
// differential tracking), and each feature adds exactly its own states and
// force elements.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/simulation_output.h"
#include "scenes.h"

namespace camdyn {
namespace {

using Names = std::vector<std::string>;

struct ModelCase {
  std::string name;
  std::string kind;  ///< test::follower_scene kind
  std::function<void(SceneConfig&)> change;
  Names states, elements;
};

void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.name; }

const Names kTranslating = {"follower_position", "follower_velocity"};
const Names kArm = {"arm_angle", "arm_angular_velocity"};

Names operator+(Names a, const Names& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::vector<ModelCase> cases() {
  auto newton = [](SceneConfig& s) { s.mechanism.contact.tracking = "newton"; };
  auto shaft = [](SceneConfig& s) {
    s.mechanism.cam.drive.type = "shaft";
    s.mechanism.cam.drive.inertia = 0.01;
    s.mechanism.cam.drive.torsional_stiffness = 1e4;
  };
  return {
      {"bare_translating_roller", "translating_roller", newton, kTranslating,
       {"follower_mass", "spring", "contact:hertz"}},
      {"differential_tracking", "translating_roller", [](SceneConfig&) {}, kTranslating + Names{"contact_parameter_u"},
       {"follower_mass", "spring", "contact:hertz"}},
      {"friction_without_roller_inertia_is_free_rolling", "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.2;
       },
       kTranslating, {"follower_mass", "spring", "contact:hertz"}},
      {"roller_inertia_with_friction", "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.2;
         s.mechanism.follower.shape.inertia = 1e-6;
       },
       kTranslating + Names{"roller_spin"}, {"follower_mass", "spring", "contact:hertz", "friction:coulomb_tanh"}},
      {"damper_gravity_guide_friction", "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.damping = 2.0;
         s.gravity = 9.81;
         s.mechanism.follower.guide_friction = GuideFrictionConfig{0.1, 1e-4};
       },
       kTranslating, {"follower_mass", "spring", "damper", "gravity", "contact:hertz", "guide_friction:coulomb_tanh"}},
      {"flat_face", "translating_flat", newton, kTranslating, {"follower_mass", "spring", "contact:hertz"}},
      {"flat_face_sliding_friction", "translating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.1;
       },
       kTranslating, {"follower_mass", "spring", "contact:hertz", "friction:coulomb_tanh"}},
      {"mushroom_differential", "translating_mushroom", [](SceneConfig&) {},
       kTranslating + Names{"contact_parameter_u"}, {"follower_mass", "spring", "contact:hertz"}},
      {"oscillating_roller", "oscillating_roller", newton, kArm, {"arm_inertia", "torsional_spring", "contact:hertz"}},
      {"oscillating_flat_pivot_friction_damper", "oscillating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.damping = 0.01;
         s.mechanism.follower.pivot_friction = PivotFrictionConfig{0.1, 0.005, 1e-4};
       },
       kArm, {"arm_inertia", "torsional_spring", "torsional_damper", "contact:hertz", "pivot_friction:coulomb_tanh"}},
      {"zero_mu_assembles_no_friction", "oscillating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.pivot_friction = PivotFrictionConfig{0.0, 0.005, 1e-4};
       },
       kArm, {"arm_inertia", "torsional_spring", "contact:hertz"}},
      {"shaft_constant_speed_motor", "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         shaft(s);
       },
       kTranslating + Names{"cam_angle", "cam_speed"},
       {"follower_mass", "spring", "contact:hertz", "cam_inertia", "shaft_spring", "motor:constant_speed"}},
      {"shaft_torque_speed_motor_damped_differential", "oscillating_roller",
       [&](SceneConfig& s) {
         shaft(s);
         s.mechanism.cam.drive.torsional_damping = 0.1;
         s.mechanism.cam.drive.motor = MotorConfig{"torque_speed", 10.0, 2000.0, 1e-3};
       },
       kArm + Names{"contact_parameter_u", "cam_angle", "cam_speed", "motor_angle", "motor_speed"},
       {"arm_inertia", "torsional_spring", "contact:hertz", "cam_inertia", "shaft_spring", "shaft_damper",
        "motor:torque_speed"}},
  };
}

class ModelBlock : public ::testing::TestWithParam<ModelCase> {};

TEST_P(ModelBlock, ListsExactlyTheStatesAndElementsTheSceneNeeds) {
  const ModelCase& c = GetParam();
  SceneConfig scene = test::follower_scene(c.kind, 500.0);
  c.change(scene);
  const Model model = build_model(scene, "test");
  EXPECT_EQ(model.state_names, c.states);
  EXPECT_EQ(model.state_size, static_cast<int>(c.states.size()));
  EXPECT_EQ(model.elements, c.elements);
  const Json block = summary_json(scene, model, SimulationResult{}).at("model");
  EXPECT_EQ(block.at("state_size").get<int>(), model.state_size);
  EXPECT_EQ(block.at("states").get<Names>(), c.states);
  EXPECT_EQ(block.at("elements").get<Names>(), c.elements);
  EXPECT_EQ(block.at("follower").get<std::string>(), c.kind);
}

INSTANTIATE_TEST_SUITE_P(Scenes, ModelBlock, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<ModelCase>& p) { return p.param.name; });

}  // namespace
}  // namespace camdyn

namespace camdyn {
namespace {

TEST(FollowerExamples, EveryStudyConfigLoadsAndBuildsItsModel) {
  // studies/followers/*.json (run by hand with `camdyn run`; here: they load and their cams can be made).
  const std::filesystem::path dir = std::filesystem::path(CAMDYN_TEST_DATA_DIR) / "../../studies/followers";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const SceneConfig scene = load_scene(entry.path().string());
    const Model model = build_model(scene, entry.path().string());
    EXPECT_GE(model.state_size, 2);
    ++count;
  }
  EXPECT_GE(count, 5);
}

}  // namespace
}  // namespace camdyn
