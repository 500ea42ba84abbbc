// The loader's visit walked over typed scenes (io/typed_archive.h): the typed
// check refuses what the loader refuses, with the same dotted path and
// reason, and the locator finds a scene's numeric fields by dotted path.
#include "io/typed_archive.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "common/errors.h"
#include "input_error_of.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

using test::input_error_of;

const std::string kOscillating = std::string(CAMDYN_SOURCE_DIR) + "/studies/followers/oscillating_roller.json";
const std::string kShaftDrive = std::string(CAMDYN_SOURCE_DIR) + "/studies/followers/shaft_drive.json";

/// The loader's error for `scene` printed back with `key` set to `json`.
InputError loader_error(const SceneConfig& scene, const std::string& key, const std::string& json) {
  Json doc = to_json(scene);
  set_config_value(doc, key, Json::parse(json));
  return input_error_of([&] { scene_from_json(doc, ConfigSource{"scene.json", "."}); });
}

TEST(TypedCheck, AcceptsTheScenesTheLoaderLoads) {
  for (const std::string& file : {kQuickstart, kOscillating, kShaftDrive}) {
    const SceneConfig scene = load_scene(file);
    EXPECT_NO_THROW(check_scene(scene, file)) << file;
  }
}

TEST(TypedCheck, RefusesWhatTheLoaderRefusesWithTheSamePathAndReason) {
  struct Case {
    const char* file;
    const char* key;
    const char* json;
    std::function<void(SceneConfig&)> set;
  };
  const std::vector<Case> cases = {
      {kQuickstart.c_str(), "mechanism.follower.mass", "-1", [](SceneConfig& s) { s.mechanism.follower.mass = -1; }},
      {kQuickstart.c_str(), "mechanism.contact.exponent", "0.4",
       [](SceneConfig& s) { s.mechanism.contact.exponent = 0.4; }},
      {kQuickstart.c_str(), "mechanism.contact.restitution", "1.5",
       [](SceneConfig& s) { s.mechanism.contact.restitution = 1.5; }},
      {kQuickstart.c_str(), "mechanism.contact.stiffness", "0",
       [](SceneConfig& s) { s.mechanism.contact.stiffness = 0.0; }},
      {kQuickstart.c_str(), "mechanism.follower.spring.preload", "-3",
       [](SceneConfig& s) { s.mechanism.follower.spring.preload = -3; }},
      {kQuickstart.c_str(), "mechanism.cam.base_radius", "250",
       [](SceneConfig& s) { s.mechanism.cam.base_radius = 250; }},
      {kQuickstart.c_str(), "integrator.rtol", "0.5", [](SceneConfig& s) { s.integrator.rtol = 0.5; }},
      {kQuickstart.c_str(), "name", "\"a/b\"", [](SceneConfig& s) { s.name = "a/b"; }},
      {kOscillating.c_str(), "gravity", "9.81", [](SceneConfig& s) { s.gravity = 9.81; }},
      {kOscillating.c_str(), "mechanism.follower.inertia", "0",
       [](SceneConfig& s) { s.mechanism.follower.inertia = 0; }},
      {kShaftDrive.c_str(), "mechanism.cam.drive.torsional_stiffness", "-5",
       [](SceneConfig& s) { s.mechanism.cam.drive.torsional_stiffness = -5; }},
  };
  for (const Case& c : cases) {
    SceneConfig scene = load_scene(c.file);
    const InputError loader = loader_error(scene, c.key, c.json);
    EXPECT_EQ(loader.path(), c.key) << c.key;
    c.set(scene);
    const InputError typed = input_error_of([&] { check_scene(scene, "scene.json"); });
    EXPECT_EQ(typed.file(), "scene.json") << c.key;
    EXPECT_EQ(typed.path(), loader.path()) << c.key;
    EXPECT_EQ(typed.reason(), loader.reason()) << c.key;
  }
}

TEST(TypedCheck, RefusesANumberSetInCodeThatIsNotFinite) {
  SceneConfig scene = load_scene(kQuickstart);
  scene.mechanism.follower.damping = std::numeric_limits<double>::quiet_NaN();
  const InputError e = input_error_of([&] { check_scene(scene, "code"); });
  EXPECT_EQ(e.path(), "mechanism.follower.damping");
  EXPECT_EQ(e.reason(), "expected a finite number, got nan");
}

TEST(TypedCheck, RestrictedToSomeFieldsChecksOnlyThoseAndTheConditionsNamingThem) {
  SceneConfig scene;  // no motion law, no base radius: not a valid scene
  scene.mechanism.contact.stiffness = 1e9;
  const std::string_view contact[] = {"mechanism.contact"};
  EXPECT_NO_THROW(check_scene_fields(scene, contact, "code"));
  scene.mechanism.contact.exponent = 0.4;  // in the range (0, 5], below the floor
  const InputError e = input_error_of([&] { check_scene_fields(scene, contact, "code"); });
  EXPECT_EQ(e.path(), "mechanism.contact.exponent");
  EXPECT_EQ(e.reason(), loader_error(load_scene(kQuickstart), "mechanism.contact.exponent", "0.4").reason());
  const std::string_view mass[] = {"mechanism.follower.mass"};
  scene.mechanism.follower.mass = 0.3;  // [kg]; the exponent is not among the fields checked
  EXPECT_NO_THROW(check_scene_fields(scene, mass, "code"));
}

TEST(FieldLocator, FindsANumericFieldWithTheLoadersChecks) {
  SceneConfig scene = load_scene(kQuickstart);
  const SceneField stiffness = find_scene_field(scene, "mechanism.contact.stiffness", "code");
  EXPECT_EQ(stiffness.path, "mechanism.contact.stiffness");
  EXPECT_EQ(stiffness.value, &*scene.mechanism.contact.stiffness);
  EXPECT_EQ(stiffness.reason(-1.0), "must be > 0, got -1");
  EXPECT_EQ(stiffness.reason(2e9), "");
  const SceneField restitution = find_scene_field(scene, "contact.restitution", "code");  // the short form of --set
  EXPECT_EQ(restitution.value, &scene.mechanism.contact.restitution);
  EXPECT_EQ(restitution.reason(1.5), loader_error(scene, "mechanism.contact.restitution", "1.5").reason());
  EXPECT_EQ(find_scene_field(scene, "gravity", "code").value, &scene.gravity);
  EXPECT_EQ(find_scene_field(scene, "mechanism.follower.spring.stiffness", "code").value,
            &scene.mechanism.follower.spring.stiffness);
}

TEST(FieldLocator, RefusesAnUnknownPathAsTheLoaderRefusesTheKey) {
  SceneConfig scene = load_scene(kQuickstart);
  for (const char* path : {"mechanism.contact.stifness", "mechanism.folower.mass", "gravty"}) {
    const InputError located = input_error_of([&] { find_scene_field(scene, path, "code"); });
    const InputError loaded = loader_error(scene, path, "1");
    EXPECT_EQ(located.path(), loaded.path()) << path;
    EXPECT_EQ(located.reason(), loaded.reason()) << path;
    EXPECT_NE(located.reason().find("did you mean"), std::string::npos) << path;
    EXPECT_FALSE(try_find_scene_field(scene, path)) << path;
  }
}

TEST(FieldLocator, FindsOnlyTheFieldsTheScenesChoicesGive) {
  SceneConfig oscillating = load_scene(kOscillating);
  EXPECT_EQ(find_scene_field(oscillating, "mechanism.follower.inertia", "code").value,
            &oscillating.mechanism.follower.inertia);
  // An oscillating follower has no mass: the loader's reason for refusing one.
  const InputError mass = input_error_of([&] { find_scene_field(oscillating, "mechanism.follower.mass", "code"); });
  EXPECT_EQ(mass.path(), "mechanism.follower.mass");
  EXPECT_EQ(mass.reason(), loader_error(oscillating, "mechanism.follower.mass", "1").reason());
  SceneConfig quickstart = load_scene(kQuickstart);
  EXPECT_FALSE(try_find_scene_field(quickstart, "mechanism.follower.guide_friction.mu"));  // no such block
  EXPECT_FALSE(try_find_scene_field(quickstart, "mechanism.contact"));                     // an object
  EXPECT_FALSE(try_find_scene_field(quickstart, "mechanism.contact.model"));               // a word
}

}  // namespace
}  // namespace camdyn
