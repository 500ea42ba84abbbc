// Follower trains in a config (docs/config.md, "Follower trains"):
// mechanism.train, seats and stops, springs with mass. A train loads with its
// values and defaults and writes back to the same scene; every check names its
// dotted path; a scene without any of it writes none of the new keys, so it
// prints as it did before them; a scene built in code gets the same checks.
#include <gtest/gtest.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "common/errors.h"
#include "input_error_of.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "io/typed_archive.h"

namespace camdyn {
namespace {

using test::input_error_of;

const std::string kGoodTrainBase = std::string(CAMDYN_TEST_DATA_DIR) + "/bad_configs/good_base.json";
const ConfigSource kSource{"train.json", "/"};

/// A complete scene without a train, the motion law inline.
Json scene_without_train() {
  return Json::parse(R"({
    "name": "no-train",
    "mechanism": {
      "cam": { "base_radius": 0.04, "rpm": 1200, "motion_law": { "segments": [
        { "type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.008 },
        { "type": "dwell", "end_deg": 180 },
        { "type": "return", "law": "polynomial_345", "end_deg": 300 },
        { "type": "dwell", "end_deg": 360 } ] } },
      "follower": { "shape": { "type": "flat", "face_width": 0.03 }, "mass": 0.05,
                    "spring": { "stiffness": 5000, "preload": 40 } },
      "contact": { "stiffness": 1e9 }
    }
  })");
}

/// An overhead valve train: a tappet with a massive spring and a lash seat,
/// a rocker tip and the valve, whose seat and retainer stop limit its travel.
Json scene_with_train() {
  Json doc = scene_without_train();
  doc["name"] = "valve-train";
  Json& follower = doc["mechanism"]["follower"];
  follower["spring"] = Json::parse(R"({ "stiffness": 35000, "preload": 250, "mass": 0.045, "coils": 8,
      "damping_ratio": 0.03, "clash": { "gap": 0.0004, "stiffness": 1e8 } })");
  follower["seat"] = Json::parse(R"({ "position": 0.0002, "model": "kelvin_voigt", "stiffness": 5e8,
      "exponent": 1.0, "damping": 3000 })");
  doc["mechanism"]["train"] = Json::parse(R"([
    { "name": "rocker_tip", "mass": 0.02, "link": { "stiffness": 5e7 } },
    { "name": "valve", "mass": 0.06, "damping": 0.5,
      "link": { "ratio": 1.5, "stiffness": 2.0e7, "damping": 40, "lash": 0.0001, "one_sided": true },
      "spring": { "stiffness": 40000, "preload": 350, "mass": 0.06, "coils": 8 },
      "seat": { "position": 0.0, "model": "hunt_crossley", "stiffness": 1e9, "exponent": 1.5, "restitution": 0.3 },
      "stop": { "position": 0.012, "stiffness": 1e9 } }
  ])");
  return doc;
}

SceneConfig load(const Json& doc) { return scene_from_json(doc, kSource); }

/// to_json → scene_from_json must give back the same struct and the same JSON.
void expect_train_round_trip(const SceneConfig& scene) {
  const Json written = to_json(scene);
  SceneConfig again = scene_from_json(written, ConfigSource{"round-trip.json", "/"});
  again.mechanism.cam.motion_law.source = scene.mechanism.cam.motion_law.source;  // not serialised
  EXPECT_TRUE(again == scene) << written.dump(2) << "\nvs\n" << to_json(again).dump(2);
  EXPECT_EQ(to_json(again), written);
}

/// Every key a scene without a train, seat, stop or spring mass must not write.
void expect_none_of_the_train_keys(const Json& j, const std::string& path) {
  if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i)
      expect_none_of_the_train_keys(j[i], path + "[" + std::to_string(i) + "]");
    return;
  }
  if (!j.is_object()) return;
  for (const char* key : {"train", "seat", "stop"}) EXPECT_FALSE(j.contains(key)) << path << "." << key;
  if (j.contains("spring")) {
    for (const char* key : {"mass", "coils", "damping_ratio", "clash"})
      EXPECT_FALSE(j["spring"].contains(key)) << path << ".spring." << key;
  }
  for (const auto& item : j.items()) expect_none_of_the_train_keys(item.value(), path + "." + item.key());
}

// ---------------------------------------------------------------- loading and writing back

TEST(TrainConfig, AValveTrainLoadsWithEveryValue) {
  const SceneConfig s = load(scene_with_train());
  const FollowerConfig& f = s.mechanism.follower;
  EXPECT_EQ(f.spring.mass, 0.045);
  EXPECT_EQ(f.spring.coils, 8);
  EXPECT_EQ(f.spring.damping_ratio, 0.03);
  ASSERT_TRUE(f.spring.clash.has_value());
  EXPECT_EQ(*f.spring.clash, (CoilClashConfig{0.0004, 1e8}));
  EXPECT_TRUE(f.spring.massive());
  ASSERT_TRUE(f.seat.has_value());
  EXPECT_EQ(f.seat->model, ContactModel::kelvin_voigt);
  EXPECT_EQ(f.seat->damping, 3000.0);
  EXPECT_FALSE(f.stop.has_value());

  ASSERT_EQ(s.mechanism.train.size(), 2u);
  const TrainBodyConfig& valve = s.mechanism.train[1];
  EXPECT_EQ(valve.name, "valve");
  EXPECT_EQ(valve.link, (LinkConfig{1.5, 2.0e7, 40, 0.0001, true}));
  EXPECT_EQ(valve.spring.coils, 8);
  EXPECT_FALSE(valve.spring.damping_ratio.has_value());  // the default applies where it is used
  ASSERT_TRUE(valve.seat && valve.stop);
  EXPECT_EQ(valve.seat->model, ContactModel::hunt_crossley);
  EXPECT_FALSE(valve.seat->damping.has_value());
  EXPECT_EQ(valve.stop->position, 0.012);
}

TEST(TrainConfig, LinksSeatsAndBodiesTakeTheirDefaults) {
  const SceneConfig s = load(scene_with_train());
  const TrainBodyConfig& tip = s.mechanism.train[0];
  EXPECT_EQ(tip.link, (LinkConfig{.ratio = 1.0, .stiffness = 5e7, .damping = 0.0, .lash = 0.0, .one_sided = true}));
  EXPECT_EQ(tip.damping, 0.0);
  EXPECT_EQ(tip.spring, SpringConfig{});  // no spring
  EXPECT_FALSE(tip.seat || tip.stop);
  const SeatConfig defaults;
  const SeatConfig& stop = *s.mechanism.train[1].stop;
  EXPECT_EQ(stop.model, defaults.model);
  EXPECT_EQ(stop.exponent, defaults.exponent);
  EXPECT_EQ(stop.restitution, defaults.restitution);
  EXPECT_EQ(stop.reference_velocity, defaults.reference_velocity);
  EXPECT_FALSE(stop.damping.has_value());
}

TEST(TrainConfig, AValveTrainWritesBackToTheSameScene) {
  const SceneConfig s = load(scene_with_train());
  expect_train_round_trip(s);
  const Json written = to_json(s);
  const Json& mechanism = written["mechanism"];
  ASSERT_TRUE(mechanism.contains("train"));
  EXPECT_EQ(mechanism["train"].size(), 2u);
  // Only what a body has is written: no spring, seat or stop on the rocker tip,
  // no damping on a hysteresis seat, no damping ratio the config left out.
  for (const char* absent : {"spring", "seat", "stop"}) EXPECT_FALSE(mechanism["train"][0].contains(absent)) << absent;
  EXPECT_FALSE(mechanism["train"][1]["seat"].contains("damping"));
  EXPECT_FALSE(mechanism["train"][1]["spring"].contains("damping_ratio"));
  EXPECT_FALSE(mechanism["train"][1]["spring"].contains("clash"));
  EXPECT_FALSE(mechanism["follower"].contains("stop"));
  EXPECT_EQ(mechanism["follower"]["spring"]["coils"], 8);
}

TEST(TrainConfig, ASceneWithoutATrainWritesNoneOfItsKeys) {
  for (const SceneConfig& s : {load(scene_without_train()), load_scene(kGoodTrainBase)}) {
    const Json written = to_json(s);
    expect_none_of_the_train_keys(written, "");
    // The spring is written as it always was: its two fields.
    EXPECT_EQ(written["mechanism"]["follower"]["spring"].size(), 2u);
    expect_train_round_trip(s);
  }
  // An empty train, null seats and a null spring mass are the same scene.
  Json doc = scene_without_train();
  doc["mechanism"]["train"] = Json::array();
  doc["mechanism"]["follower"]["seat"] = nullptr;
  doc["mechanism"]["follower"]["stop"] = nullptr;
  doc["mechanism"]["follower"]["spring"]["mass"] = nullptr;
  EXPECT_EQ(to_json(load(doc)), to_json(load(scene_without_train())));
}

TEST(TrainConfig, SurgeFieldsOfAMasslessSpringAreKeptButUnused) {
  // An engineer toggles the mass to compare: coils, damping ratio and clash stay.
  for (const Json& mass : {Json(0.0), Json(nullptr)}) {
    Json doc = scene_with_train();
    doc["mechanism"]["follower"]["spring"]["mass"] = mass;
    doc["mechanism"]["follower"]["spring"].erase("coils");
    doc["mechanism"]["train"][1]["spring"]["mass"] = mass;
    const SceneConfig s = load(doc);
    EXPECT_FALSE(s.mechanism.follower.spring.massive());
    EXPECT_EQ(s.mechanism.follower.spring.damping_ratio, 0.03);
    EXPECT_TRUE(s.mechanism.follower.spring.clash.has_value());
    EXPECT_EQ(s.mechanism.train[1].spring.coils, 8);
    expect_train_round_trip(s);
  }
}

TEST(TrainConfig, ATwoSidedLinkWithoutLashAndAStopWithoutASeatLoad) {
  Json doc = scene_with_train();
  doc["mechanism"]["train"][1]["link"]["lash"] = 0.0;
  doc["mechanism"]["train"][1]["link"]["one_sided"] = false;
  doc["mechanism"]["train"][1].erase("seat");
  doc["mechanism"]["train"][1]["stop"]["position"] = -0.001;  // only a seat bounds a stop from below
  const SceneConfig s = load(doc);
  EXPECT_FALSE(s.mechanism.train[1].link.one_sided);
  expect_train_round_trip(s);
}

// ---------------------------------------------------------------- errors name their dotted path

struct BadTrain {
  std::string what;
  std::function<void(Json&)> edit;  ///< breaks scene_with_train()
  std::string path;                 ///< the dotted path the error names
  std::string reason;               ///< a fragment of its reason
};

Json& follower_of(Json& doc) { return doc["mechanism"]["follower"]; }
Json& body(Json& doc, std::size_t i) { return doc["mechanism"]["train"][i]; }

std::vector<BadTrain> spring_errors() {
  return {
      {"negative spring mass", [](Json& d) { follower_of(d)["spring"]["mass"] = -0.01; },
       "mechanism.follower.spring.mass", "must be >= 0"},
      {"mass without coils", [](Json& d) { follower_of(d)["spring"].erase("coils"); },
       "mechanism.follower.spring.coils", "missing"},
      {"no coils", [](Json& d) { follower_of(d)["spring"]["coils"] = 0; }, "mechanism.follower.spring.coils",
       "must be in [1, 32]"},
      {"too many coils", [](Json& d) { body(d, 1)["spring"]["coils"] = 33; }, "mechanism.train[1].spring.coils",
       "must be in [1, 32]"},
      {"fractional coils", [](Json& d) { follower_of(d)["spring"]["coils"] = 2.5; }, "mechanism.follower.spring.coils",
       "expected an integer"},
      {"negative damping ratio", [](Json& d) { follower_of(d)["spring"]["damping_ratio"] = -0.1; },
       "mechanism.follower.spring.damping_ratio", "must be >= 0"},
      {"clash without a gap", [](Json& d) { follower_of(d)["spring"]["clash"]["gap"] = 0; },
       "mechanism.follower.spring.clash.gap", "must be > 0"},
      {"clash without a stiffness", [](Json& d) { follower_of(d)["spring"]["clash"].erase("stiffness"); },
       "mechanism.follower.spring.clash.stiffness", "missing"},
      {"misspelt surge key", [](Json& d) { follower_of(d)["spring"]["coil"] = 8; }, "mechanism.follower.spring.coil",
       "did you mean 'coils'"},
      {"no lumps", [](Json& d) { follower_of(d)["spring"]["lumps"] = 0; }, "mechanism.follower.spring.lumps",
       "must be in [1, 32]"},
      {"fractional lumps", [](Json& d) { body(d, 1)["spring"]["lumps"] = 4.5; }, "mechanism.train[1].spring.lumps",
       "expected an integer"},
      {"lumps without coils",
       [](Json& d) {
         follower_of(d)["spring"].erase("coils");
         follower_of(d)["spring"]["lumps"] = 8;
       },
       "mechanism.follower.spring.coils", "missing"},
      {"wire without a mean diameter", [](Json& d) { body(d, 1)["spring"]["wire_diameter"] = 0.004; },
       "mechanism.train[1].spring.mean_diameter", "needs both"},
      {"mean diameter within the wire",
       [](Json& d) {
         body(d, 1)["spring"]["wire_diameter"] = 0.004;
         body(d, 1)["spring"]["mean_diameter"] = 0.003;
       },
       "mechanism.train[1].spring.mean_diameter", "larger than wire_diameter"},
      {"no wire", [](Json& d) { follower_of(d)["spring"]["wire_diameter"] = 0; },
       "mechanism.follower.spring.wire_diameter", "must be > 0"},
  };
}

std::vector<BadTrain> seat_errors() {
  return {
      {"seat without stiffness", [](Json& d) { follower_of(d)["seat"].erase("stiffness"); },
       "mechanism.follower.seat.stiffness", "missing"},
      {"seat exponent below the floor", [](Json& d) { body(d, 1)["seat"]["exponent"] = 0.3; },
       "mechanism.train[1].seat.exponent", "must be >= 0.5"},
      {"seat exponent above 5", [](Json& d) { body(d, 1)["seat"]["exponent"] = 6; }, "mechanism.train[1].seat.exponent",
       "must be in (0, 5]"},
      {"seat restitution 0", [](Json& d) { body(d, 1)["seat"]["restitution"] = 0; },
       "mechanism.train[1].seat.restitution", "must be in (0, 1]"},
      {"viscous seat without damping", [](Json& d) { follower_of(d)["seat"].erase("damping"); },
       "mechanism.follower.seat.damping", "needs 'damping'"},
      {"hysteresis seat with damping", [](Json& d) { body(d, 1)["seat"]["damping"] = 100; },
       "mechanism.train[1].seat.damping", "only model 'kelvin_voigt' uses 'damping'"},
      {"stop with damping by default law", [](Json& d) { body(d, 1)["stop"]["damping"] = 100; },
       "mechanism.train[1].stop.damping", "derives it from 'restitution'"},
      {"seat reference velocity 0", [](Json& d) { follower_of(d)["seat"]["reference_velocity"] = 0; },
       "mechanism.follower.seat.reference_velocity", "must be > 0"},
      {"unknown seat model", [](Json& d) { follower_of(d)["seat"]["model"] = "hertzian"; },
       "mechanism.follower.seat.model", "hertz"},
      {"follower stop below its seat", [](Json& d) { follower_of(d)["stop"] = Json::parse(R"({ "stiffness": 1e9 })"); },
       "mechanism.follower.stop.position", "must be above the seat"},
      {"stop at the seat", [](Json& d) { body(d, 1)["stop"]["position"] = 0.0; }, "mechanism.train[1].stop.position",
       "must be above the seat"},
  };
}

std::vector<BadTrain> link_and_body_errors() {
  return {
      {"link without stiffness", [](Json& d) { body(d, 1)["link"].erase("stiffness"); },
       "mechanism.train[1].link.stiffness", "missing"},
      {"no link", [](Json& d) { body(d, 1).erase("link"); }, "mechanism.train[1].link", "missing"},
      {"null link", [](Json& d) { body(d, 0)["link"] = nullptr; }, "mechanism.train[0].link", "missing"},
      {"link ratio 0", [](Json& d) { body(d, 1)["link"]["ratio"] = 0; }, "mechanism.train[1].link.ratio",
       "must be > 0"},
      {"negative link damping", [](Json& d) { body(d, 1)["link"]["damping"] = -1; }, "mechanism.train[1].link.damping",
       "must be >= 0"},
      {"negative lash", [](Json& d) { body(d, 1)["link"]["lash"] = -1e-4; }, "mechanism.train[1].link.lash",
       "must be >= 0"},
      {"lash on a two-sided link", [](Json& d) { body(d, 1)["link"]["one_sided"] = false; },
       "mechanism.train[1].link.lash", "a two-sided link has no lash"},
      {"one_sided not a boolean", [](Json& d) { body(d, 1)["link"]["one_sided"] = "yes"; },
       "mechanism.train[1].link.one_sided", "expected true or false"},
      {"body without a name", [](Json& d) { body(d, 0).erase("name"); }, "mechanism.train[0].name", "missing"},
      {"empty name", [](Json& d) { body(d, 0)["name"] = ""; }, "mechanism.train[0].name", "must not be empty"},
      {"name with a dash", [](Json& d) { body(d, 0)["name"] = "rocker-tip"; }, "mechanism.train[0].name",
       "only letters, digits and '_'"},
      {"name 'follower'", [](Json& d) { body(d, 1)["name"] = "follower"; }, "mechanism.train[1].name", "is taken"},
      {"name given twice", [](Json& d) { body(d, 1)["name"] = "rocker_tip"; }, "mechanism.train[1].name",
       "'rocker_tip' is already the name of train[0]"},
      {"body without mass", [](Json& d) { body(d, 0).erase("mass"); }, "mechanism.train[0].mass", "missing"},
      {"body mass 0", [](Json& d) { body(d, 1)["mass"] = 0; }, "mechanism.train[1].mass", "must be > 0"},
      {"negative body damping", [](Json& d) { body(d, 1)["damping"] = -0.5; }, "mechanism.train[1].damping",
       "must be >= 0"},
      {"unknown body key", [](Json& d) { body(d, 1)["lash"] = 1e-4; }, "mechanism.train[1].lash", "unknown key"},
      {"negative follower lash", [](Json& d) { follower_of(d)["lash"] = -1e-4; }, "mechanism.follower.lash",
       "must be >= 0"},
      {"follower lash not a number", [](Json& d) { follower_of(d)["lash"] = "0.2 mm"; }, "mechanism.follower.lash",
       "expected a number"},
      {"train not an array", [](Json& d) { d["mechanism"]["train"] = body(d, 0); }, "mechanism.train",
       "expected an array"},
  };
}

std::vector<BadTrain> size_errors() {
  return {
      {"nine bodies",
       [](Json& d) {
         Json bodies = Json::array();
         for (int i = 0; i < 9; ++i) {
           bodies.push_back(Json::parse(R"({ "mass": 0.01, "link": { "stiffness": 1e7 } })"));
           bodies.back()["name"] = "b" + std::to_string(i);
         }
         d["mechanism"]["train"] = bodies;
       },
       "mechanism.train", "holds at most 8 bodies, got 9"},
      // 2 bodies (4) + the follower's 8 coils (16) + 2 x 32 coils (128) = 148 states.
      {"too many states",
       [](Json& d) {
         body(d, 0)["spring"] = Json::parse(R"({ "stiffness": 1e4, "mass": 0.01, "coils": 32 })");
         body(d, 1)["spring"]["coils"] = 32;
       },
       "mechanism.train", "the train has 148 states"},
  };
}

void expect_errors(const std::vector<BadTrain>& cases) {
  for (const BadTrain& c : cases) {
    SCOPED_TRACE(c.what);
    Json doc = scene_with_train();
    c.edit(doc);
    const InputError e = input_error_of([&] { load(doc); });
    EXPECT_EQ(e.file(), kSource.file);
    EXPECT_EQ(e.path(), c.path) << e.reason();
    EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.reason();
  }
}

TEST(TrainConfig, LashAndLumpsLoadAndWriteBackOnlyWhenGiven) {
  Json doc = scene_with_train();
  follower_of(doc)["lash"] = 0.0002;
  body(doc, 1)["spring"]["lumps"] = 16;
  const SceneConfig s = load(doc);
  EXPECT_EQ(s.mechanism.follower.lash, std::optional<double>(0.0002));
  EXPECT_EQ(s.mechanism.train[1].spring.coils, std::optional<int>(8));
  EXPECT_EQ(s.mechanism.train[1].spring.lump_count(), 16);
  EXPECT_EQ(s.mechanism.follower.spring.lump_count(), 8);  // lumps = coils without it, as before
  expect_train_round_trip(s);
  const Json without = to_json(load(scene_with_train()));
  EXPECT_FALSE(without["mechanism"]["follower"].contains("lash"));
  EXPECT_FALSE(without["mechanism"]["follower"]["spring"].contains("lumps"));
}

TEST(TrainConfig, SpringMassChecksNameTheirPath) { expect_errors(spring_errors()); }
TEST(TrainConfig, SeatAndStopChecksNameTheirPath) { expect_errors(seat_errors()); }
TEST(TrainConfig, LinkAndBodyChecksNameTheirPath) { expect_errors(link_and_body_errors()); }
TEST(TrainConfig, TrainSizeChecksNameTheTrain) { expect_errors(size_errors()); }

TEST(TrainConfig, TheStateLimitCountsEveryLumpedMass) {
  // 2 bodies (4) + 8 coils on the follower (16) + 32 + 14 coils (92) = 112: at the limit.
  Json doc = scene_with_train();
  body(doc, 0)["spring"] = Json::parse(R"({ "stiffness": 1e4, "mass": 0.01, "coils": 32 })");
  body(doc, 1)["spring"]["coils"] = 14;
  EXPECT_NO_THROW(load(doc));
  body(doc, 1)["spring"]["coils"] = 15;
  const InputError e = input_error_of([&] { load(doc); });
  EXPECT_EQ(e.path(), "mechanism.train");
  EXPECT_NE(e.reason().find("114 states"), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("limit of 112"), std::string::npos) << e.reason();
  // Coils of a massless spring are not states.
  body(doc, 1)["spring"]["mass"] = 0;
  EXPECT_NO_THROW(load(doc));
}

// ---------------------------------------------------------------- an oscillating follower

/// scene_without_train() with an oscillating roller arm (its law in degrees).
Json scene_with_an_arm() {
  Json doc = scene_without_train();
  for (auto& segment : doc["mechanism"]["cam"]["motion_law"]["segments"]) {
    if (!segment.contains("lift")) continue;
    segment.erase("lift");
    segment["lift_deg"] = 12;
  }
  doc["mechanism"]["follower"] = Json::parse(R"({ "motion": "oscillating", "pivot": [0.1, 0.06], "arm_length": 0.11,
      "shape": { "radius": 0.01 }, "inertia": 0.002, "spring": { "stiffness": 50, "preload": 5 } })");
  return doc;
}

TEST(TrainConfig, AnArmsTorsionalSpringHasNoMassButItsTrainsSpringsMay) {
  Json doc = scene_with_an_arm();
  doc["mechanism"]["follower"]["spring"]["mass"] = 0.0;  // massless: fine
  doc["mechanism"]["follower"]["stop"] = Json::parse(R"({ "position": 0.3, "stiffness": 1e4, "exponent": 1 })");
  doc["mechanism"]["train"] = Json::parse(R"([ { "name": "valve", "mass": 0.06,
      "link": { "ratio": 0.04, "stiffness": 2e7 },
      "spring": { "stiffness": 40000, "preload": 350, "mass": 0.06, "coils": 6 } } ])");
  const SceneConfig s = load(doc);
  EXPECT_TRUE(s.mechanism.train[0].spring.massive());
  expect_train_round_trip(s);

  Json wire = doc;  // an arm's torsional spring has no helical wire
  wire["mechanism"]["follower"]["spring"]["wire_diameter"] = 0.004;
  wire["mechanism"]["follower"]["spring"]["mean_diameter"] = 0.024;
  const InputError w = input_error_of([&] { load(wire); });
  EXPECT_EQ(w.path(), "mechanism.follower.spring.wire_diameter");
  EXPECT_NE(w.reason().find("torsional"), std::string::npos) << w.reason();

  doc["mechanism"]["follower"]["spring"]["mass"] = 0.02;
  doc["mechanism"]["follower"]["spring"]["coils"] = 4;
  const InputError e = input_error_of([&] { load(doc); });
  EXPECT_EQ(e.path(), "mechanism.follower.spring.mass");
  EXPECT_NE(e.reason().find("spring mass is modelled for a translating follower or a train body; put the valve "
                            "spring on a train body"),
            std::string::npos)
      << e.reason();
}

// ---------------------------------------------------------------- scenes built in code

TEST(TrainConfig, AScenesBuiltInCodeGetTheLoadersChecks) {
  SceneConfig s = load(scene_with_train());
  EXPECT_NO_THROW(check_scene(s, "code"));

  SceneConfig bad = s;
  bad.mechanism.train[1].link.stiffness = 0.0;
  InputError e = input_error_of([&] { check_scene(bad, "code"); });
  EXPECT_EQ(e.path(), "mechanism.train[1].link.stiffness");

  bad = s;
  bad.mechanism.train[0].name = bad.mechanism.train[1].name;
  EXPECT_EQ(input_error_of([&] { check_scene(bad, "code"); }).path(), "mechanism.train[1].name");

  bad = s;
  bad.mechanism.follower.spring.coils.reset();
  EXPECT_EQ(input_error_of([&] { check_scene(bad, "code"); }).path(), "mechanism.follower.spring.coils");

  bad = s;
  bad.mechanism.train.resize(9, s.mechanism.train[0]);
  EXPECT_EQ(input_error_of([&] { check_scene(bad, "code"); }).path(), "mechanism.train");
}

TEST(TrainConfig, ATrainsNumbersAreFoundByTheirDottedPath) {
  SceneConfig s = load(scene_with_train());
  const SceneField link = find_scene_field(s, "mechanism.train[1].link.stiffness", "code");
  EXPECT_EQ(link.value, &s.mechanism.train[1].link.stiffness);
  EXPECT_EQ(link.reason(0.0), "must be > 0, got 0");
  const SceneField mass = find_scene_field(s, "mechanism.follower.spring.mass", "code");
  EXPECT_EQ(*mass.value, 0.045);

  // What the scene does not give is named as such, not as an unknown key.
  SceneConfig plain = load(scene_without_train());
  const InputError e = input_error_of([&] { find_scene_field(plain, "mechanism.follower.spring.mass", "code"); });
  EXPECT_EQ(e.path(), "mechanism.follower.spring.mass");
  EXPECT_EQ(e.reason(), "is not given in this scene");
  EXPECT_EQ(input_error_of([&] { find_scene_field(plain, "mechanism.follower.seat.stiffness", "code"); }).reason(),
            "is not given in this scene");
}

// ---------------------------------------------------------------- gas loads

const std::string kPressureTable = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/cylinder_pressure.csv";

/// The valve of scene_with_train() under a gas load (docs/config.md, "`gas`: a gas load").
Json scene_with_gas() {
  Json doc = scene_with_train();
  body(doc, 1)["gas"] = Json{{"area", 7e-4}, {"pressure", kPressureTable}, {"tdc_deg", 100}};
  return doc;
}

TEST(TrainConfig, ASpringsWireLoadsAndWritesBackOnlyWhenGiven) {
  Json doc = scene_with_train();
  body(doc, 1)["spring"]["wire_diameter"] = 0.004;
  body(doc, 1)["spring"]["mean_diameter"] = 0.024;
  const SceneConfig s = load(doc);
  EXPECT_EQ(s.mechanism.train[1].spring.wire_diameter, std::optional<double>(0.004));
  EXPECT_EQ(s.mechanism.train[1].spring.mean_diameter, std::optional<double>(0.024));
  expect_train_round_trip(s);
  EXPECT_FALSE(to_json(load(scene_with_train()))["mechanism"]["train"][1]["spring"].contains("wire_diameter"));
}

TEST(TrainConfig, AGasLoadReadsItsTableAndWritesBack) {
  const SceneConfig s = load(scene_with_gas());
  ASSERT_TRUE(s.mechanism.train[1].gas);
  const GasLoadConfig& g = *s.mechanism.train[1].gas;
  EXPECT_EQ(g.area, 7e-4);
  EXPECT_EQ(g.crank_ratio, 2.0);
  EXPECT_EQ(g.tdc_deg, 100.0);
  EXPECT_EQ(g.port_pressure, 1.01325e5);
  ASSERT_EQ(g.crank_deg.size(), 72u);
  EXPECT_EQ(g.crank_deg.front(), 0.0);
  EXPECT_EQ(g.crank_deg.back(), 710.0);
  EXPECT_EQ(g.pressure_pa.front(), 95000.0);
  EXPECT_EQ(g.lines.front(), 3);  // after the comment and the header
  expect_train_round_trip(s);
  EXPECT_FALSE(to_json(load(scene_with_train()))["mechanism"]["train"][1].contains("gas"));
}

TEST(TrainConfig, GasLoadChecksNameTheirPath) {
  const std::vector<BadTrain> cases = {
      {"area", [](Json& d) { body(d, 1)["gas"]["area"] = 0.0; }, "mechanism.train[1].gas.area", "> 0"},
      {"unknown key", [](Json& d) { body(d, 1)["gas"]["aera"] = 1e-3; }, "mechanism.train[1].gas.aera", "area"},
      {"crank ratio", [](Json& d) { body(d, 1)["gas"]["crank_ratio"] = -2; }, "mechanism.train[1].gas.crank_ratio",
       "> 0"},
      {"tdc", [](Json& d) { body(d, 1)["gas"]["tdc_deg"] = 360; }, "mechanism.train[1].gas.tdc_deg", "360"},
      {"no table", [](Json& d) { body(d, 1)["gas"]["pressure"] = "/nonexistent/p.csv"; },
       "mechanism.train[1].gas.pressure", "cannot open"},
  };
  for (const BadTrain& c : cases) {
    SCOPED_TRACE(c.what);
    Json doc = scene_with_gas();
    c.edit(doc);
    const InputError e = input_error_of([&] { load(doc); });
    EXPECT_EQ(e.path(), c.path) << e.reason();
    EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.reason();
  }
}

}  // namespace
}  // namespace camdyn
