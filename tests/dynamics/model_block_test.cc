// summary.json's `model` block (docs/config.md, "Outputs of simulate"): the bare scene has only the
// follower coordinate and its rate (plus the tracking parameter with
// differential tracking), and each feature adds exactly its own states and
// force elements.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "scenes.h"
#include "study/simulation_output.h"

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
  auto newton = [](SceneConfig& s) { s.mechanism.contact.tracking = Tracking::newton; };
  auto shaft = [](SceneConfig& s) {
    s.mechanism.cam.drive.type = Drive::shaft;
    s.mechanism.cam.drive.inertia = 0.01;
    s.mechanism.cam.drive.torsional_stiffness = 1e4;
  };
  return {
      {"bare_translating_roller",
       "translating_roller",
       newton,
       kTranslating,
       {"follower_mass", "spring", "contact:hertz"}},
      {"differential_tracking",
       "translating_roller",
       [](SceneConfig&) {},
       kTranslating + Names{"contact_parameter_u"},
       {"follower_mass", "spring", "contact:hertz"}},
      {"friction_without_roller_inertia_is_free_rolling",
       "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.2;
       },
       kTranslating,
       {"follower_mass", "spring", "contact:hertz"}},
      {"roller_inertia_with_friction",
       "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.2;
         s.mechanism.follower.shape.inertia = 1e-6;
       },
       kTranslating + Names{"roller_spin"},
       {"follower_mass", "spring", "contact:hertz", "friction:coulomb_tanh"}},
      {"damper_gravity_guide_friction",
       "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.damping = 2.0;
         s.gravity = 9.81;
         s.mechanism.follower.guide_friction = GuideFrictionConfig{0.1, 1e-4};
       },
       kTranslating,
       {"follower_mass", "spring", "damper", "gravity", "contact:hertz", "guide_friction:coulomb_tanh"}},
      {"flat_face", "translating_flat", newton, kTranslating, {"follower_mass", "spring", "contact:hertz"}},
      {"flat_face_sliding_friction",
       "translating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.friction.mu = 0.1;
       },
       kTranslating,
       {"follower_mass", "spring", "contact:hertz", "friction:coulomb_tanh"}},
      {"mushroom_differential",
       "translating_mushroom",
       [](SceneConfig&) {},
       kTranslating + Names{"contact_parameter_u"},
       {"follower_mass", "spring", "contact:hertz"}},
      {"oscillating_roller", "oscillating_roller", newton, kArm, {"arm_inertia", "torsional_spring", "contact:hertz"}},
      {"oscillating_flat_pivot_friction_damper",
       "oscillating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.damping = 0.01;
         s.mechanism.follower.pivot_friction = PivotFrictionConfig{0.1, 0.005, 1e-4};
       },
       kArm,
       {"arm_inertia", "torsional_spring", "torsional_damper", "contact:hertz", "pivot_friction:coulomb_tanh"}},
      {"zero_mu_assembles_no_friction",
       "oscillating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.follower.pivot_friction = PivotFrictionConfig{0.0, 0.005, 1e-4};
       },
       kArm,
       {"arm_inertia", "torsional_spring", "contact:hertz"}},
      {"shaft_constant_speed_motor",
       "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         shaft(s);
       },
       kTranslating + Names{"cam_angle", "cam_speed"},
       {"follower_mass", "spring", "contact:hertz", "cam_inertia", "shaft_spring", "motor:constant_speed"}},
      {"shaft_torque_speed_motor_damped_differential",
       "oscillating_roller",
       [&](SceneConfig& s) {
         shaft(s);
         s.mechanism.cam.drive.torsional_damping = 0.1;
         s.mechanism.cam.drive.motor = MotorConfig{Motor::torque_speed, 10.0, 2000.0, 1e-3};
       },
       kArm + Names{"contact_parameter_u", "cam_angle", "cam_speed", "motor_angle", "motor_speed"},
       {"arm_inertia", "torsional_spring", "contact:hertz", "cam_inertia", "shaft_spring", "shaft_damper",
        "motor:torque_speed"}},
      {"general_pair_differential",
       "translating_roller",
       [](SceneConfig& s) { s.mechanism.contact.pair_form = PairFormChoice::general; },
       kTranslating + Names{"contact_parameter_u", "contact_parameter_v"},
       {"follower_mass", "spring", "contact:hertz"}},
      {"general_pair_newton",
       "oscillating_flat",
       [&](SceneConfig& s) {
         newton(s);
         s.mechanism.contact.pair_form = PairFormChoice::general;
       },
       kArm,
       {"arm_inertia", "torsional_spring", "contact:hertz"}},
      {"contour_cam_adds_nothing",
       "translating_roller",
       [&](SceneConfig& s) {
         newton(s);
         test::use_eccentric_disc_contour(s, 64);
       },
       kTranslating,
       {"follower_mass", "spring", "contact:hertz"}},
  };
}

class ModelBlock : public ::testing::TestWithParam<ModelCase> {};

TEST_P(ModelBlock, ListsExactlyTheStatesAndElementsTheSceneNeeds) {
  const ModelCase& c = GetParam();
  SceneConfig scene = test::follower_scene(c.kind, 500.0);
  c.change(scene);
  const Model model = build_model(scene, "test");
  EXPECT_EQ(model.layout.names, c.states);
  EXPECT_EQ(model.layout.size, static_cast<int>(c.states.size()));
  EXPECT_EQ(model.elements, c.elements);
  const Json block = summary_json(scene, model, SimulationResult{}).at("model");
  EXPECT_EQ(block.at("state_size").get<int>(), model.layout.size);
  EXPECT_EQ(block.at("states").get<Names>(), c.states);
  EXPECT_EQ(block.at("elements").get<Names>(), c.elements);
  EXPECT_EQ(block.at("follower").get<std::string>(), c.kind);
  const bool general = scene.mechanism.contact.pair_form == PairFormChoice::general;
  EXPECT_EQ(block.at("contact_pair").get<std::string>().find("general") != std::string::npos, general);
  EXPECT_EQ(summary_json(scene, model, SimulationResult{}).contains("contour_fit"),
            scene.mechanism.cam.motion_law.contour.has_value());
}

INSTANTIATE_TEST_SUITE_P(Scenes, ModelBlock, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<ModelCase>& p) { return p.param.name; });

// The work quadratures follow the scene as the states do: the drive's work
// only where the cam turns, the damper's only with a damper, the hysteresis
// only for a dissipative contact law, the friction work only with friction.
TEST(ModelBlock, ListsOnlyTheWorkQuadraturesTheSceneHas) {
  auto quadratures = [](const SceneConfig& scene) {
    const Model model = build_model(scene, "test");
    const Names listed = summary_json(scene, model, SimulationResult{}).at("model").at("quadratures").get<Names>();
    EXPECT_EQ(listed, integrated_quadratures(model));
    return listed;
  };
  SceneConfig scene = test::follower_scene("translating_roller", 500.0);
  scene.mechanism.follower.damping = 0.0;
  EXPECT_EQ(quadratures(scene), Names{"drive_work"});
  scene.mechanism.follower.damping = 5.0;
  scene.mechanism.contact.model = ContactModel::lankarani_nikravesh;
  EXPECT_EQ(quadratures(scene), (Names{"drive_work", "damper_work", "hysteresis_work"}));
  scene.mechanism.contact.friction.mu = 0.1;  // a roller without inertia rolls: no friction work
  EXPECT_EQ(quadratures(scene), (Names{"drive_work", "damper_work", "hysteresis_work"}));
  SceneConfig flat = test::follower_scene("translating_flat", 500.0);  // a flat face slides
  flat.mechanism.follower.damping = 5.0;
  flat.mechanism.contact.model = ContactModel::lankarani_nikravesh;
  flat.mechanism.contact.friction.mu = 0.1;
  EXPECT_EQ(quadratures(flat), (Names{"drive_work", "damper_work", "hysteresis_work", "friction_work"}));
  EXPECT_EQ(quadratures(test::drop_scene(ContactModel::hertz, 1.0)), Names{});  // a still cam does no work
}

// Every named state has its slot at its position in the names; absent states have none.
TEST(StateLayout, SlotsMatchTheNamesAndAbsentStatesHaveNone) {
  const std::vector<std::pair<std::string, StateSlot StateLayout::*>> slots = {
      {"contact_parameter_u", &StateLayout::u},  {"contact_parameter_v", &StateLayout::v},
      {"roller_spin", &StateLayout::spin},       {"cam_angle", &StateLayout::cam_angle},
      {"cam_speed", &StateLayout::cam_speed},    {"motor_angle", &StateLayout::motor_angle},
      {"motor_speed", &StateLayout::motor_speed}};
  for (const ModelCase& c : cases()) {
    SCOPED_TRACE(c.name);
    SceneConfig scene = test::follower_scene(c.kind, 500.0);
    c.change(scene);
    const StateLayout& layout = build_model(scene, "test").layout;
    for (const auto& [name, slot] : slots) {
      const auto it = std::find(layout.names.begin(), layout.names.end(), name);
      ASSERT_EQ(static_cast<bool>(layout.*slot), it != layout.names.end()) << name;
      if (layout.*slot) {
        EXPECT_EQ(*(layout.*slot), it - layout.names.begin()) << name;
      }
    }
  }
}

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
    EXPECT_GE(model.layout.size, 2);
    ++count;
  }
  EXPECT_GE(count, 5);
}

TEST(ContourCamExample, LoadsFitsAndReportsItsFit) {
  // studies/contour_cam/measured_roller_cam.json (made by its generate.py):
  // 360 points with 1.5 µm noise on a cam of base radius 35 mm.
  const std::string file =
      (std::filesystem::path(CAMDYN_TEST_DATA_DIR) / "../../studies/contour_cam/measured_roller_cam.json").string();
  const Model model = build_model(load_scene(file), file);
  ASSERT_TRUE(model.contour);
  const ContourFitReport& fit = model.contour->report();
  EXPECT_EQ(fit.points, 360);
  EXPECT_GT(fit.rms_residual, 0.5e-6);  // the noise is there, and is not fitted away ...
  EXPECT_LT(fit.rms_residual, 1.5e-6);  // ... nor left above its level
  EXPECT_TRUE(fit.concave.empty());
  constexpr double kNoisyFit = 5e-6;  // [m], ≈ 3× the 1.5 µm noise on the points
  EXPECT_NEAR(model.follower.base_radius, 0.035, kNoisyFit);
}

}  // namespace
}  // namespace camdyn
