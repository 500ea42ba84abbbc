// Config loading: round trips through to_json, defaults, extends and --set,
// profile and table path resolution, error paths and messages; closest-key
// suggestions.
#include "io/config.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/json_archive.h"
#include "io/suggest.h"
#include "scene/study_kind.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const std::string kDataDir = CAMDYN_TEST_DATA_DIR;
const std::string kGoodBase = kDataDir + "/bad_configs/good_base.json";

/// A scratch directory removed at the end of the test.
class TempDir {
 public:
  TempDir() {
    static int counter = 0;
    path_ = fs::temp_directory_path() /
            ("camdyn_config_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  /// Writes `text` to `name` (sub-directories created) and returns the full path.
  std::string write(const std::string& name, const std::string& text) const {
    const fs::path file = path_ / name;
    fs::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

/// A complete scene as JSON, the motion law given inline.
Json minimal_scene() {
  return Json::parse(R"({
    "name": "minimal",
    "mechanism": {
      "cam": { "base_radius": 0.04, "rpm": 1200, "motion_law": { "segments": [
        { "type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.02 },
        { "type": "dwell", "end_deg": 180 },
        { "type": "return", "law": "polynomial_345", "end_deg": 300 },
        { "type": "dwell", "end_deg": 360 } ] } },
      "follower": { "shape": { "radius": 0.01 }, "mass": 0.3 },
      "contact": { "stiffness": 1e9 }
    }
  })");
}

/// Runs `f`, expects an InputError and returns it.
template <class F>
InputError expect_input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected an InputError";
  return InputError("", "", "");
}

/// to_json → scene_from_json must give back the same struct and the same JSON.
void expect_round_trip(const SceneConfig& scene) {
  const Json written = to_json(scene);
  SceneConfig again = scene_from_json(written, ConfigSource{"round-trip.json", "/"});
  again.mechanism.cam.motion_law.source = scene.mechanism.cam.motion_law.source;  // not serialised
  EXPECT_TRUE(again == scene) << written.dump(2) << "\nvs\n" << to_json(again).dump(2);
  EXPECT_EQ(to_json(again), written);
}

// ---------------------------------------------------------------- defaults and round trips

TEST(Config, GoodBaseLoadsWithEveryValue) {
  const SceneConfig s = load_scene(kGoodBase);
  EXPECT_EQ(s.name, "good-base");
  EXPECT_EQ(s.mechanism.cam.base_radius, 0.04);
  EXPECT_EQ(s.mechanism.cam.rpm, 1200);
  ASSERT_EQ(s.mechanism.cam.motion_law.segments.size(), 4u);
  EXPECT_EQ(s.mechanism.cam.motion_law.segments[0].law, SegmentLaw::cycloidal);
  EXPECT_EQ(s.mechanism.cam.motion_law.segments[0].lift, 0.02);
  EXPECT_FALSE(s.mechanism.cam.motion_law.segments[2].lift.has_value());
  EXPECT_EQ(s.mechanism.follower.spring.preload, 40);
  EXPECT_FALSE(s.mechanism.follower.initial.position.has_value());
  EXPECT_EQ(s.mechanism.contact.stiffness, 1e9);
  EXPECT_EQ(s.simulation.cycles, 4.0);
  EXPECT_EQ(s.integrator.atol, 1e-12);
}

TEST(Config, DefaultsAreFilledInFromTheStructs) {
  const SceneConfig s = scene_from_json(minimal_scene(), ConfigSource{"minimal.json", "/"});
  const SceneConfig defaults;
  EXPECT_EQ(s.study, "simulate");
  EXPECT_EQ(s.mechanism.cam.direction, RotationDirection::ccw);
  EXPECT_EQ(s.mechanism.follower.motion, FollowerMotion::translating);
  EXPECT_EQ(s.mechanism.contact.model, defaults.mechanism.contact.model);
  EXPECT_EQ(s.mechanism.contact.restitution, defaults.mechanism.contact.restitution);
  EXPECT_EQ(s.mechanism.contact.friction, defaults.mechanism.contact.friction);
  EXPECT_EQ(s.integrator, defaults.integrator);
  // Run-length defaults that depend on rpm > 0.
  EXPECT_EQ(s.simulation.cycles, SimulationConfig::kDefaultCycles);
  EXPECT_EQ(s.simulation.output_step_deg, SimulationConfig::kDefaultOutputStepDeg);
  EXPECT_FALSE(s.simulation.duration.has_value());
}

TEST(Config, ToJsonWritesEveryFieldIncludingDefaultsAndNulls) {
  const Json j = to_json(scene_from_json(minimal_scene(), ConfigSource{"minimal.json", "/"}));
  EXPECT_EQ(j["mechanism"]["follower"]["damping"], 0.0);
  EXPECT_EQ(j["mechanism"]["follower"]["spring"]["stiffness"], 0.0);
  EXPECT_TRUE(j["mechanism"]["follower"]["initial"]["position"].is_null());
  EXPECT_TRUE(j["mechanism"]["contact"]["damping"].is_null());
  EXPECT_EQ(j["mechanism"]["contact"]["friction"]["regularization"], "tanh");
  EXPECT_EQ(j["mechanism"]["cam"]["drive"]["type"], "constant_speed");
  EXPECT_EQ(j["integrator"]["max_wall_time_s"], 600.0);
  EXPECT_EQ(j["integrator"]["max_steps"], 5'000'000);
  EXPECT_TRUE(j["integrator"]["step"].is_null());
  EXPECT_EQ(j["simulation"]["cycles"], 4.0);
  EXPECT_FALSE(j.contains("extends"));
}

TEST(Config, ToJsonWritesOnlyTheFieldsOfEachSegmentType) {
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"]["segments"][2] =
      Json::parse(R"({ "type": "return", "law": "spline", "end_deg": 300, "control_points": [0.2, 0.8] })");
  const Json segments =
      to_json(scene_from_json(doc, ConfigSource{"x.json", "/"}))["mechanism"]["cam"]["motion_law"]["segments"];
  auto keys = [](const Json& o) {
    std::vector<std::string> k;
    for (const auto& item : o.items()) k.push_back(item.key());
    return k;
  };
  EXPECT_EQ(keys(segments[0]), (std::vector<std::string>{"type", "law", "end_deg", "lift", "lift_deg"}));
  EXPECT_EQ(keys(segments[1]), (std::vector<std::string>{"type", "end_deg"}));
  EXPECT_EQ(keys(segments[2]),
            (std::vector<std::string>{"type", "law", "end_deg", "lift", "lift_deg", "degree", "control_points"}));
}

TEST(Config, RoundTripOfTheGoodBase) { expect_round_trip(load_scene(kGoodBase)); }

/// A lift table the loader can read (it reads a table's rows at load).
const char* const kLiftTable = "angle_deg,lift\n0,0\n90,0.01\n180,0.02\n270,0.01\n";

TEST(Config, RoundTripOfEveryOptionalShape) {
  TempDir dir;
  dir.write("tables/lift.csv", kLiftTable);
  // Periodic spline law, stiffness from materials, kelvin_voigt, set initial state, rk4.
  Json a = minimal_scene();
  a["mechanism"]["cam"]["motion_law"] =
      Json::parse(R"({ "spline": { "degree": 3, "knots_deg": [0, 90, 180, 270], "lift": [0, 0.01, 0.02, 0.01] } })");
  a["mechanism"]["contact"] = Json::parse(R"({ "model": "kelvin_voigt", "damping": 50, "exponent": 1.0,
      "stiffness": { "from_materials": { "E1": 2.1e11, "nu1": 0.29, "E2": 2.0e11, "nu2": 0.3, "width": 0.01 } } })");
  a["mechanism"]["follower"]["initial"] = Json::parse(R"({ "position": 0.001, "velocity": -0.5 })");
  a["integrator"] = Json::parse(R"({ "method": "rk4", "step": 1e-6, "max_step": 1e-4 })");
  const SceneConfig sa = scene_from_json(a, ConfigSource{"a.json", dir / ""});
  ASSERT_TRUE(sa.mechanism.contact.from_materials.has_value());
  EXPECT_FALSE(sa.mechanism.contact.stiffness.has_value());
  EXPECT_EQ(sa.mechanism.contact.from_materials->width, 0.01);
  EXPECT_EQ(sa.mechanism.follower.initial.position, 0.001);
  expect_round_trip(sa);
  EXPECT_TRUE(to_json(sa)["mechanism"]["contact"]["stiffness"]["from_materials"].is_object());

  // Table law (file made absolute) and a still cam (rpm 0, duration).
  Json b = minimal_scene();
  b["mechanism"]["cam"]["rpm"] = 0;
  b["mechanism"]["cam"]["motion_law"] = Json::parse(R"({ "table": { "file": "lift.csv" } })");
  b["simulation"] = Json::parse(R"({ "duration": 0.05, "output_step": 1e-5 })");
  const SceneConfig sb = scene_from_json(b, ConfigSource{"b.json", dir / "tables"});
  ASSERT_TRUE(sb.mechanism.cam.motion_law.table.has_value());
  EXPECT_EQ(sb.mechanism.cam.motion_law.table->file, dir / "tables/lift.csv");
  EXPECT_EQ(sb.mechanism.cam.motion_law.table->lift, (std::vector<double>{0, 0.01, 0.02, 0.01}));
  EXPECT_EQ(sb.mechanism.cam.motion_law.table->lines, (std::vector<int>{2, 3, 4, 5}));
  EXPECT_FALSE(sb.simulation.cycles.has_value());
  EXPECT_FALSE(sb.simulation.output_step_deg.has_value());
  expect_round_trip(sb);
}

TEST(Config, ContourCamRoundTripsWithoutABaseRadiusAndWithItsPairForm) {
  TempDir dir;
  Json c = minimal_scene();
  c["mechanism"]["cam"].erase("base_radius");
  c["mechanism"]["cam"]["motion_law"] = Json::parse(
      R"({ "contour": { "points": [[0.03, 0], [0, 0.03], [-0.03, 0], [0, -0.03], [0.02, 0.02], [-0.02, 0.02],
                                   [-0.02, -0.02], [0.02, -0.02]], "control_points": 12, "smoothing": 0.5 } })");
  c["mechanism"]["contact"]["pair_form"] = "general";
  const SceneConfig sc = scene_from_json(c, ConfigSource{"c.json", dir / ""});
  ASSERT_TRUE(sc.mechanism.cam.motion_law.contour.has_value());
  EXPECT_EQ(sc.mechanism.cam.motion_law.contour->points.size(), 8u);
  EXPECT_EQ(sc.mechanism.cam.motion_law.contour->degree, 5);
  EXPECT_EQ(sc.mechanism.cam.motion_law.contour->control_points, 12);
  EXPECT_EQ(sc.mechanism.cam.base_radius, 0.0);
  EXPECT_EQ(sc.mechanism.contact.pair_form, PairFormChoice::general);
  EXPECT_FALSE(to_json(sc)["mechanism"]["cam"].contains("base_radius"));
  expect_round_trip(sc);

  // A point that is not [x, y], and a missing base radius on a law cam, name their fields.
  c["mechanism"]["cam"]["motion_law"]["contour"]["points"][3] = Json::parse("[0, -0.03, 0]");
  EXPECT_THROW(
      {
        try {
          scene_from_json(c, ConfigSource{"c.json", dir / ""});
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("mechanism.cam.motion_law.contour.points[3]"), std::string::npos);
          throw;
        }
      },
      InputError);
  Json d = minimal_scene();
  d["mechanism"]["cam"].erase("base_radius");
  try {
    scene_from_json(d, ConfigSource{"d.json", dir / ""});
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.cam.base_radius: missing"), std::string::npos) << e.what();
  }
}

TEST(Config, FollowerTypesAndShaftDriveRoundTripWithOnlyTheirOwnFields) {
  // Oscillating flat face with pivot friction, driven through a shaft by a torque–speed motor.
  Json a = minimal_scene();
  for (auto& seg : a["mechanism"]["cam"]["motion_law"]["segments"])
    if (seg.contains("lift")) {
      seg.erase("lift");
      seg["lift_deg"] = 12;
    }
  a["mechanism"]["follower"] = Json::parse(R"({ "motion": "oscillating", "pivot": [0.1, 0.06], "arm_length": 0.11,
      "shape": { "type": "flat", "face_width": 0.08 }, "inertia": 0.002,
      "spring": { "stiffness": 50, "preload": 5 },
      "pivot_friction": { "mu": 0.1, "pin_radius": 0.005 } })");
  a["mechanism"]["cam"]["drive"] = Json::parse(R"({ "type": "shaft", "inertia": 0.01, "torsional_stiffness": 2000,
      "motor": { "type": "torque_speed", "stall_torque": 20, "no_load_rpm": 1500, "inertia": 0.005 } })");
  const SceneConfig sa = scene_from_json(a, ConfigSource{"a.json", "/"});
  EXPECT_EQ(sa.mechanism.follower.pivot, (std::vector<double>{0.1, 0.06}));
  ASSERT_TRUE(sa.mechanism.follower.pivot_friction.has_value());
  EXPECT_EQ(sa.mechanism.follower.pivot_friction->regularization_velocity, 1e-4);  // default
  EXPECT_EQ(sa.mechanism.cam.drive.motor.no_load_rpm, 1500);
  expect_round_trip(sa);
  const Json written = to_json(sa);
  const Json& follower = written["mechanism"]["follower"];
  for (const char* absent : {"offset", "mass", "guide_friction"}) EXPECT_FALSE(follower.contains(absent)) << absent;
  for (const char* absent : {"radius", "inertia"}) EXPECT_FALSE(follower["shape"].contains(absent)) << absent;

  // Translating mushroom with guide friction; the default drive writes no shaft fields.
  Json b = minimal_scene();
  b["mechanism"]["follower"]["shape"] = Json::parse(R"({ "type": "mushroom", "radius": 0.025 })");
  b["mechanism"]["follower"]["guide_friction"] = Json::parse(R"({ "mu": 0.2 })");
  const SceneConfig sb = scene_from_json(b, ConfigSource{"b.json", "/"});
  expect_round_trip(sb);
  const Json wb = to_json(sb);
  EXPECT_FALSE(wb["mechanism"]["follower"].contains("pivot"));
  EXPECT_FALSE(wb["mechanism"]["follower"]["shape"].contains("inertia"));
  EXPECT_EQ(wb["mechanism"]["cam"]["drive"], Json::parse(R"({ "type": "constant_speed" })"));
}

TEST(Config, FollowerTypeAndDriveFieldsAreCheckedAgainstEachOther) {
  auto path_of = [](const Json& doc) {
    return expect_input_error([&] { scene_from_json(doc, ConfigSource{"s.json", "/"}); }).path();
  };
  Json doc = minimal_scene();
  doc["mechanism"]["follower"]["pivot"] = Json::array({0.1, 0.06});  // translating
  EXPECT_EQ(path_of(doc), "mechanism.follower.pivot");
  doc = minimal_scene();
  doc["mechanism"]["follower"]["motion"] = "oscillating";
  doc["mechanism"]["follower"].erase("mass");
  doc["mechanism"]["follower"]["pivot"] = Json::array({0.1});
  doc["mechanism"]["follower"]["arm_length"] = 0.08;
  doc["mechanism"]["follower"]["inertia"] = 0.002;
  EXPECT_EQ(path_of(doc), "mechanism.follower.pivot");  // [x, y] needed
  doc["mechanism"]["follower"]["pivot"] = Json::array({0.1, 0.06});
  EXPECT_EQ(path_of(doc), "mechanism.cam.motion_law.segments[0].lift");  // metres for an arm
  doc = minimal_scene();
  doc["mechanism"]["follower"]["shape"] = Json::parse(R"({ "type": "flat" })");
  EXPECT_EQ(path_of(doc), "mechanism.follower.shape.face_width");
  doc["mechanism"]["follower"]["shape"]["face_width"] = 0.05;
  doc["mechanism"]["follower"]["shape"]["inertia"] = 0.0;
  EXPECT_EQ(path_of(doc), "mechanism.follower.shape.inertia");
  doc = minimal_scene();
  doc["mechanism"]["cam"]["drive"] = Json::parse(R"({ "type": "shaft", "inertia": 0.01, "torsional_stiffness": 1e3,
      "motor": { "type": "torque_speed", "stall_torque": 5 } })");
  EXPECT_EQ(path_of(doc), "mechanism.cam.drive.motor.no_load_rpm");
  doc["mechanism"]["cam"]["drive"]["motor"] = Json::parse(R"({ "type": "constant_speed", "inertia": 1 })");
  EXPECT_EQ(path_of(doc), "mechanism.cam.drive.motor.inertia");
}

// ---------------------------------------------------------------- extends and --set

TEST(Config, ExtendsMergesObjectsChildWinsArraysReplacedWhole) {
  TempDir dir;
  dir.write("base/base.json", minimal_scene().dump());
  const std::string child = dir.write("child.json", R"({
    "extends": "base/base.json",
    "name": "child",
    "mechanism": {
      "follower": { "mass": 0.5 },
      "cam": { "motion_law": { "segments": [
        { "type": "rise", "law": "harmonic", "end_deg": 180, "lift": 0.01 },
        { "type": "return", "law": "harmonic", "end_deg": 360 } ] } }
    }
  })");
  const Json merged = load_config_json(child);
  EXPECT_FALSE(merged.contains("extends"));
  EXPECT_EQ(merged["name"], "child");
  EXPECT_EQ(merged["mechanism"]["follower"]["mass"], 0.5);
  EXPECT_EQ(merged["mechanism"]["follower"]["shape"]["radius"], 0.01);  // kept from the base
  EXPECT_EQ(merged["mechanism"]["cam"]["base_radius"], 0.04);
  EXPECT_EQ(merged["mechanism"]["cam"]["motion_law"]["segments"].size(), 2u);  // replaced whole

  // --set beats the child, which beats the base.
  const SceneConfig s = load_scene(child, {"mechanism.follower.mass=0.7"});
  EXPECT_EQ(s.mechanism.follower.mass, 0.7);
  EXPECT_EQ(s.name, "child");
}

TEST(Config, ALiftTableIsReadWhenTheConfigIsLoaded) {
  // The loader reads the rows (geometry reads no files), so a table that
  // cannot be read is reported at load, naming the CSV file.
  TempDir dir;
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"] = Json::parse(R"({ "table": { "file": "missing.csv" } })");
  try {
    scene_from_json(doc, ConfigSource{"scene.json", dir / ""});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir / "missing.csv") << e.what();
    EXPECT_NE(e.reason().find("cannot open"), std::string::npos) << e.what();
  }
}

TEST(Config, ExtendsChainOfThreeAndLawKindSwitch) {
  TempDir dir;
  dir.write("a.json", minimal_scene().dump());
  dir.write("b.json", R"({ "extends": "a.json", "mechanism": { "cam": { "rpm": 600 } } })");
  dir.write("lift.csv", kLiftTable);
  // The motion law is replaced whole, so switching to a table leaves no segments.
  const std::string c = dir.write("c.json", R"({ "extends": "b.json",
      "mechanism": { "cam": { "motion_law": { "table": { "file": "lift.csv" } } } } })");
  const SceneConfig s = load_scene(c);
  EXPECT_EQ(s.mechanism.cam.rpm, 600);
  EXPECT_TRUE(s.mechanism.cam.motion_law.segments.empty());
  ASSERT_TRUE(s.mechanism.cam.motion_law.table.has_value());
}

TEST(Config, SetParsesNumbersStringsArraysObjectsAndNull) {
  const std::vector<std::string> overrides = {
      "mechanism.cam.rpm=1500",                                            // number
      "mechanism.cam.direction=cw",                                        // bare string
      "name=\"quoted\"",                                                   // JSON string
      "mechanism.cam.motion_law.segments[0].lift=0.015",                   // array index
      "mechanism.cam.motion_law.segments[2].lift=0.015",                   // new key inside an element
      "contact.stiffness={\"from_materials\":{\"E1\":2e11,\"E2\":2e11}}",  // shorthand, nested
                                                                           // object
      "contact.friction.mu=0.1",
      "integrator.max_step=1e-5",  // key absent from the file
      "mechanism.follower.initial.position=null",
      "simulation.output_step_deg=[1]",  // array (rejected later)
  };
  const Json j = load_config_json(kGoodBase, overrides);
  EXPECT_EQ(j["mechanism"]["cam"]["rpm"], 1500);
  EXPECT_EQ(j["mechanism"]["cam"]["direction"], "cw");
  EXPECT_EQ(j["name"], "quoted");
  EXPECT_EQ(j["mechanism"]["cam"]["motion_law"]["segments"][0]["lift"], 0.015);
  EXPECT_EQ(j["mechanism"]["contact"]["stiffness"]["from_materials"]["E1"], 2e11);
  EXPECT_EQ(j["mechanism"]["contact"]["friction"]["mu"], 0.1);
  EXPECT_EQ(j["integrator"]["max_step"], 1e-5);
  EXPECT_TRUE(j["mechanism"]["follower"]["initial"]["position"].is_null());
  EXPECT_TRUE(j["simulation"]["output_step_deg"].is_array());

  std::vector<std::string> valid(overrides.begin(), overrides.end() - 1);
  const SceneConfig s = load_scene(kGoodBase, valid);
  EXPECT_EQ(s.mechanism.cam.rpm, 1500);
  EXPECT_EQ(s.mechanism.cam.direction, RotationDirection::cw);
  EXPECT_EQ(s.mechanism.cam.motion_law.segments[2].lift, 0.015);
  ASSERT_TRUE(s.mechanism.contact.from_materials.has_value());
  EXPECT_EQ(s.mechanism.contact.from_materials->E2, 2e11);
  EXPECT_EQ(s.mechanism.contact.friction.mu, 0.1);

  const InputError e = expect_input_error([&] { load_scene(kGoodBase, overrides); });
  EXPECT_EQ(e.path(), "simulation.output_step_deg");
  EXPECT_EQ(e.file(), kGoodBase);
}

TEST(Config, SetRejectsMalformedOverrides) {
  const auto error = [](const std::string& o) { return expect_input_error([&] { load_config_json(kGoodBase, {o}); }); };
  EXPECT_EQ(error("mechanism.cam.rpm").reason(), "expected KEY=VALUE");
  for (const std::string bad :
       {"mechanism..rpm=1", "=1", "mechanism.cam.rpm.=1", "mechanism.cam.motion_law.segments[x].lift=1",
        "mechanism.cam.motion_law.segments[0.lift=1", "mech anism=1"}) {
    const InputError e = error(bad);
    EXPECT_EQ(e.file(), "--set") << bad;
    EXPECT_EQ(e.path(), bad.substr(0, bad.find('='))) << bad;
  }
  EXPECT_NE(error("mechanism.cam.motion_law.segments[9].lift=1").reason().find("out of range"), std::string::npos);
  EXPECT_NE(error("mechanism.cam.rpm.value=1").reason().find("not an object"), std::string::npos);
  EXPECT_NE(error("mechanism.cam[0]=1").reason().find("not an array"), std::string::npos);
}

// A command-line argument may be any bytes; one that is not UTF-8 became a
// bare string in the document and made the next dump of it throw a JSON
// type error, exit 1 (found by config_fuzzer, docs/fuzzing.md).
TEST(Config, SetRejectsTextThatIsNotUtf8) {
  const auto error = [](const std::string& o) { return expect_input_error([&] { load_config_json(kGoodBase, {o}); }); };
  const InputError value = error(
      "mechanism.cam.rpm=\xC5\xC5"
      "1500");
  EXPECT_EQ(value.file(), "--set");
  EXPECT_EQ(value.path(), "mechanism.cam.rpm");
  EXPECT_EQ(value.reason(), "is not valid UTF-8 text");
  const InputError key = error("name\xFF=x");
  EXPECT_EQ(key.path(), "name\xEF\xBF\xBD");  // U+FFFD for the stray byte
  EXPECT_EQ(load_config_json(kGoodBase, {"name=r\xC3\xA9sum\xC3\xA9"})["name"],
            "r\xC3\xA9sum\xC3\xA9");  // UTF-8 is fine
}

// describe_json, which every type error quotes, shows a string that is not
// UTF-8 (from a caller's Json, not a parsed file) instead of throwing.
TEST(Config, DescribeJsonShowsBytesThatAreNotUtf8) {
  EXPECT_EQ(describe_json(Json("a\xC5")), "string \"a\xEF\xBF\xBD\"");
}

TEST(Config, SetUnknownKeyIsCaughtBySceneFromJson) {
  const InputError e = expect_input_error([] { load_scene(kGoodBase, {"mechanism.follower.mas=1"}); });
  EXPECT_EQ(e.path(), "mechanism.follower.mas");
  EXPECT_NE(e.reason().find("did you mean 'mass'?"), std::string::npos);
}

// ---------------------------------------------------------------- profiles and tables

const char* const kProfile = R"({
  "description": "cycloidal rise and return",
  "segments": [
    { "type": "rise", "law": "cycloidal", "end_deg": 150, "lift": 0.01 },
    { "type": "dwell", "end_deg": 180 },
    { "type": "return", "law": "cycloidal", "end_deg": 330 },
    { "type": "dwell", "end_deg": 360 } ]
})";

TEST(Config, ProfilePathIsResolvedRelativeToTheConfigAndWrittenInline) {
  TempDir dir;
  const std::string profile = dir.write("profiles/cyc.json", kProfile);
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"] = "profiles/cyc.json";
  const std::string config = dir.write("scene.json", doc.dump());
  const SceneConfig s = load_scene(config);
  EXPECT_EQ(s.mechanism.cam.motion_law.source, fs::path(profile).lexically_normal().string());
  ASSERT_EQ(s.mechanism.cam.motion_law.segments.size(), 4u);
  EXPECT_EQ(s.mechanism.cam.motion_law.segments[0].end_deg, 150);
  const Json law = to_json(s)["mechanism"]["cam"]["motion_law"];
  ASSERT_TRUE(law.is_object());
  EXPECT_EQ(law["segments"].size(), 4u);
  EXPECT_FALSE(law.contains("description"));
  expect_round_trip(s);
}

TEST(Config, ProfilePathFallsBackToTheWorkingDirectory) {
  TempDir dir;
  dir.write("cwd/profiles/cyc.json", kProfile);
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"] = "profiles/cyc.json";
  const std::string config = dir.write("configs/scene.json", doc.dump());
  const fs::path old = fs::current_path();
  fs::current_path(dir / "cwd");
  SceneConfig s;
  EXPECT_NO_THROW(s = load_scene(config));
  fs::current_path(old);
  EXPECT_EQ(s.mechanism.cam.motion_law.source, dir / "cwd/profiles/cyc.json");
}

TEST(Config, DataFilesFallBackToTheSourceDirectory) {
  const auto found = find_data_file("src/io/config.h", "/nonexistent");
  ASSERT_TRUE(found.has_value());
  EXPECT_EQ(fs::canonical(*found), fs::canonical(fs::path(CAMDYN_SOURCE_DIR) / "src/io/config.h"));
}

TEST(Config, ErrorsInsideAProfileNameTheProfileFile) {
  TempDir dir;
  const std::string profile = dir.write("p.json", R"({ "segments": [
      { "type": "rise", "law": "cycloidal", "end_deg": 400, "lift": 0.01 } ] })");
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"] = "p.json";
  const std::string config = dir.write("scene.json", doc.dump());
  const InputError e = expect_input_error([&] { load_scene(config); });
  EXPECT_EQ(e.file(), profile);
  EXPECT_EQ(e.path(), "mechanism.cam.motion_law.segments[0].end_deg");
  EXPECT_EQ(e.reason(), "must be in (0, 360], got 400");

  dir.write("p.json", R"({ "segments": [ { "type": "dwell", "end_deg": 360 } ], "descripton": "typo" })");
  const InputError typo = expect_input_error([&] { load_scene(config); });
  EXPECT_EQ(typo.file(), profile);
  EXPECT_EQ(typo.path(), "mechanism.cam.motion_law.descripton");
}

TEST(Config, TableFileIsResolvedRelativeToTheFileThatNamesIt) {
  TempDir dir;
  // In a profile: relative to the profile.
  dir.write("profiles/table.json", R"({ "table": { "file": "lift.csv", "lift_column": "s" } })");
  dir.write("profiles/lift.csv", "angle_deg,s\n0,0\n90,0.01\n180,0.02\n270,0.01\n");
  dir.write("bases/data/lift.csv", kLiftTable);
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"] = "profiles/table.json";
  const std::string config = dir.write("scene.json", doc.dump());
  const SceneConfig s = load_scene(config);
  ASSERT_TRUE(s.mechanism.cam.motion_law.table.has_value());
  EXPECT_EQ(s.mechanism.cam.motion_law.table->file, dir / "profiles/lift.csv");
  EXPECT_EQ(s.mechanism.cam.motion_law.table->lift_column, "s");

  // In an extended config elsewhere: relative to that config.
  Json base = minimal_scene();
  base["mechanism"]["cam"]["motion_law"] = Json::parse(R"({ "table": { "file": "data/lift.csv" } })");
  dir.write("bases/base.json", base.dump());
  const std::string child = dir.write("child.json", R"({ "extends": "bases/base.json" })");
  EXPECT_EQ(load_scene(child).mechanism.cam.motion_law.table->file, dir / "bases/data/lift.csv");
}

TEST(Config, ProfileNamedInAnExtendedConfigIsResolvedRelativeToIt) {
  TempDir dir;
  dir.write("bases/profiles/cyc.json", kProfile);
  Json base = minimal_scene();
  base["mechanism"]["cam"]["motion_law"] = "profiles/cyc.json";
  dir.write("bases/base.json", base.dump());
  const std::string child = dir.write("child.json", R"({ "extends": "bases/base.json" })");
  EXPECT_EQ(load_scene(child).mechanism.cam.motion_law.source, dir / "bases/profiles/cyc.json");
}

// ---------------------------------------------------------------- errors

TEST(Config, UnknownKeySuggestsTheClosestValidKey) {
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["rpmm"] = 1500;
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(e.file(), "scene.json");
  EXPECT_EQ(e.path(), "mechanism.cam.rpmm");
  EXPECT_EQ(e.reason(), "unknown key 'rpmm' (did you mean 'rpm'?)");
  EXPECT_EQ(std::string(e.what()), "scene.json: mechanism.cam.rpmm: unknown key 'rpmm' (did you mean 'rpm'?)");

  // No close match: the valid keys are listed instead.
  doc = minimal_scene();
  doc["mechanism"]["follower"]["shape"]["zzzzzz"] = 1;
  const InputError far = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(far.reason(), "unknown key 'zzzzzz' (valid keys here: type, radius, inertia)");
}

TEST(Config, UnknownEnumValueSuggestsTheClosestValue) {
  Json doc = minimal_scene();
  doc["integrator"]["method"] = "cvode_bfd";
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(e.path(), "integrator.method");
  EXPECT_NE(e.reason().find("got string \"cvode_bfd\" (did you mean 'cvode_bdf'?)"), std::string::npos) << e.reason();
}

TEST(Config, MistypedStudyListsEveryRegisteredStudy) {
  Json doc = minimal_scene();
  doc["study"] = "simulat";
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(e.path(), "study");
  for (const StudyInfo& study : kStudies)
    EXPECT_NE(e.reason().find("'" + std::string(study.name) + "'"), std::string::npos)
        << study.name << ": " << e.reason();
  EXPECT_NE(e.reason().find("got string \"simulat\" (did you mean 'simulate'?)"), std::string::npos) << e.reason();
}

TEST(Config, AnotherStudysWordIsRefusedForAScene) {
  // A scene is a simulate config: the other studies are run by their own runners.
  Json doc = minimal_scene();
  doc["study"] = "optimize";
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(e.path(), "study");
  EXPECT_EQ(e.reason(), "study 'optimize' is not available in this version of camdyn (see the open issues)");
}

TEST(Config, MisspeltKeyIsReportedRatherThanTheMissingField) {
  Json doc = minimal_scene();
  doc["mechanism"]["follower"].erase("mass");
  doc["mechanism"]["follower"]["mas"] = 0.3;
  EXPECT_EQ(expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path(), "mechanism.follower.mas");
  // A top-level typo hides a whole required object: still the typo first.
  doc = minimal_scene();
  doc["mechanizm"] = doc["mechanism"];
  doc.erase("mechanism");
  EXPECT_EQ(expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path(), "mechanizm");
}

TEST(Config, MissingRequiredFieldsSayWhatIsExpected) {
  Json doc = minimal_scene();
  doc["mechanism"]["follower"].erase("mass");
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); });
  EXPECT_EQ(e.path(), "mechanism.follower.mass");
  EXPECT_EQ(e.reason(), "missing (expected a number > 0)");

  doc = minimal_scene();
  doc["mechanism"]["contact"].erase("stiffness");
  EXPECT_EQ(expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path(), "mechanism.contact.stiffness");

  doc = minimal_scene();
  doc["mechanism"]["cam"].erase("motion_law");
  const InputError law = expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); });
  EXPECT_EQ(law.path(), "mechanism.cam.motion_law");
  EXPECT_NE(law.reason().find("exactly one of"), std::string::npos);
}

// integrator.order (docs/config.md): one of ARKODE's orders for an arkode
// method, refused with any other method; null or absent is the default table.
TEST(Config, IntegratorOrderIsOneOfTheMethodsOrders) {
  const auto with = [](const std::string& method, const Json& order) {
    Json doc = minimal_scene();
    doc["integrator"] = Json{{"method", method}, {"order", order}};
    return doc;
  };
  const auto reason = [](const Json& doc) {
    const InputError e = expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); });
    EXPECT_EQ(e.path(), "integrator.order");
    return e.reason();
  };
  for (const int q : kErkOrders) {
    const SceneConfig s = scene_from_json(with("arkode_erk", q), {"s.json", "/"});
    EXPECT_EQ(s.integrator.order, q);
    expect_round_trip(s);
  }
  for (const int q : kDirkOrders)
    EXPECT_EQ(scene_from_json(with("arkode_dirk", q), {"s.json", "/"}).integrator.order, q);
  EXPECT_FALSE(scene_from_json(with("arkode_erk", nullptr), {"s.json", "/"}).integrator.order.has_value());
  EXPECT_FALSE(scene_from_json(minimal_scene(), {"s.json", "/"}).integrator.order.has_value());

  EXPECT_EQ(reason(with("arkode_erk", 7)), "method 'arkode_erk' has orders 2, 3, 4, 5, 6, 8, got 7");
  EXPECT_EQ(reason(with("arkode_dirk", 6)), "method 'arkode_dirk' has orders 2, 3, 4, 5, got 6");
  EXPECT_EQ(reason(with("arkode_erk", 5.5)), "expected an integer, got 5.5");
  for (const char* method : {"cvode_bdf", "cvode_adams"})
    EXPECT_EQ(reason(with(method, 5)), "only methods 'arkode_erk' and 'arkode_dirk' take an order (method is '" +
                                           std::string(method) + "'); set it to null");
}

TEST(Config, NumbersAndIntegersAreTypeChecked) {
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["rpm"] = 1500;      // an integer is a fine double
  doc["simulation"]["discard_cycles"] = 2.0;  // an integral double is a fine int
  doc["simulation"]["cycles"] = 6;
  const SceneConfig s = scene_from_json(doc, {"s.json", "/"});
  EXPECT_EQ(s.simulation.discard_cycles, 2);

  doc["mechanism"]["cam"]["base_radius"] = true;
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); });
  EXPECT_EQ(e.reason(), "expected a number, got boolean true");

  doc = minimal_scene();
  doc["mechanism"]["follower"]["shape"] = "roller";
  EXPECT_EQ(expect_input_error([&] {
              scene_from_json(doc, {"s.json", "/"});
            }).reason(),
            "expected an object, got string \"roller\"");

  doc = minimal_scene();
  doc["integrator"]["max_steps"] = 1e30;
  EXPECT_EQ(expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path(), "integrator.max_steps");
}

// 2^63 is one past the largest long; as a double it equals
// double(LONG_MAX), so a bound of max alone let it through to an undefined
// conversion (a 9223372036854775808.0), or, written as an unsigned JSON
// integer, to a negative step budget (found by scene_fuzzer, docs/fuzzing.md).
TEST(Config, IntegerJustPastTheRangeOfItsFieldIsRejected) {
  for (const char* text : {"9223372036854775808", "9223372036854775808.0", "18446744073709551615", "-9.3e18"}) {
    Json doc = minimal_scene();
    doc["integrator"]["max_steps"] = Json::parse(text);
    const InputError e = expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); });
    EXPECT_EQ(e.path(), "integrator.max_steps") << text;
    EXPECT_NE(e.reason().find("integer out of range"), std::string::npos) << text << ": " << e.reason();
  }
  Json doc = minimal_scene();
  doc["integrator"]["max_steps"] = Json::parse("9223372036854774784.0");  // the largest double below 2^63
  EXPECT_EQ(scene_from_json(doc, {"s.json", "/"}).integrator.max_steps, 9223372036854774784L);
}

TEST(Config, SyntaxErrorGivesLineAndColumnOfTheOffendingToken) {
  TempDir dir;
  // The ':' is missing; the error points at the end of the token read instead, "9.81".
  const std::string file = dir.write("bad.json", "{\n  \"name\": \"x\",\n  \"gravity\" 9.81\n}\n");
  const InputError e = expect_input_error([&] { load_config_json(file); });
  EXPECT_EQ(e.file(), file);
  EXPECT_EQ(e.path(), "line 3, column 16");
  EXPECT_NE(e.reason().find("JSON syntax error"), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("expected ':'"), std::string::npos) << e.reason();
  EXPECT_EQ(e.reason().find("json.exception"), std::string::npos) << e.reason();

  const std::string empty = dir.write("empty.json", "");
  EXPECT_EQ(expect_input_error([&] { load_config_json(empty); }).path(), "line 1, column 0");
}

TEST(Config, MissingOrUnreadableFileIsAnInputError) {
  TempDir dir;
  const InputError missing = expect_input_error([&] { load_scene(dir / "nope.json"); });
  EXPECT_EQ(missing.file(), dir / "nope.json");
  EXPECT_NE(missing.reason().find("cannot open"), std::string::npos);
  const InputError directory = expect_input_error([&] { load_scene(dir / ""); });
  EXPECT_NE(directory.reason().find("directory"), std::string::npos);
  const std::string array = dir.write("array.json", "[1, 2]");
  EXPECT_NE(expect_input_error([&] { load_scene(array); }).reason().find("JSON object"), std::string::npos);
  const std::string huge = dir.write("huge.json", "{\n  \"gravity\": 1e999\n}");
  const InputError overflow = expect_input_error([&] { load_scene(huge); });
  EXPECT_EQ(overflow.file(), huge);
  // The field and where the number is, not only nlohmann's message.
  EXPECT_EQ(overflow.path(), "gravity at line 2, column 14");
  EXPECT_NE(overflow.reason().find("1e999"), std::string::npos) << overflow.reason();
}

// Everything that walks a document recurses, so nesting is limited when the
// file is read (an identify `parameters` entry 20,000 levels deep crashed
// validate with SIGSEGV), and for --set values too.
TEST(Config, NestingDeeperThanTheLimitIsAnInputErrorNamingThePath) {
  TempDir dir;
  std::string deep = "{\"parameters\": ";
  for (int i = 0; i < 20000; ++i) deep += "{\"a\": ";
  deep += "1" + std::string(20001, '}');
  const std::string file = dir.write("deep.json", deep);
  const InputError e = expect_input_error([&] { load_config_json(file); });
  EXPECT_EQ(e.file(), file);
  EXPECT_TRUE(e.path().starts_with("parameters.a.a.a")) << e.path();
  EXPECT_NE(e.reason().find("nested deeper than 64 levels"), std::string::npos) << e.reason();

  std::string value;
  for (int i = 0; i < 100; ++i) value += "[";
  value += std::string(100, ']');
  const InputError set = expect_input_error([&] { load_config_json(kGoodBase, {"mechanism.x=" + value}); });
  EXPECT_EQ(set.file(), "--set");
  EXPECT_EQ(set.path(), "mechanism.x");
}

// Work a config asks for is bounded before anything runs: revolutions and
// time-series rows (a denormal output step made a run grow 250 MB/s).
TEST(Config, RunsAndOutputsBeyondTheWorkLimitsAreRefusedNamingTheField) {
  const auto error = [](const std::string& o) { return expect_input_error([&] { load_scene(kGoodBase, {o}); }); };
  EXPECT_EQ(error("simulation.cycles=1e100").path(), "simulation.cycles");
  const InputError denormal = error("simulation.output_step_deg=5e-324");
  EXPECT_EQ(denormal.path(), "simulation.output_step_deg");
  EXPECT_NE(denormal.reason().find("time-series rows"), std::string::npos) << denormal.reason();
  EXPECT_NO_THROW(load_scene(kGoodBase, {"simulation.cycles=1000", "simulation.output_step_deg=1"}));
}

// The time series a run would record must fit the memory budget (192 bytes
// a row): 360,000 rows are 66 MB, refused under 50 MB and taken under 100 MB.
TEST(Config, ATimeSeriesBeyondTheMemoryBudgetIsRefusedNamingTheOutputStep) {
  const std::vector<std::string> rows = {"simulation.cycles=1000", "simulation.output_step_deg=1"};
  {
    const StudyBudgetScope budget(1e9, 50.0);
    const InputError e = expect_input_error([&] { load_scene(kGoodBase, rows); });
    EXPECT_EQ(e.path(), "simulation.output_step_deg");
    EXPECT_NE(e.reason().find("360000 time-series rows, about 66 MB"), std::string::npos) << e.reason();
    EXPECT_NE(e.reason().find("--max-memory"), std::string::npos) << e.reason();
  }
  const StudyBudgetScope budget(1e9, 100.0);
  EXPECT_NO_THROW(load_scene(kGoodBase, rows));
}

TEST(Config, DuplicateKeysAreRejectedWithTheirPath) {
  TempDir dir;
  const std::string file = dir.write("dup.json", R"({ "a": [ {}, { "b": { "c": 1, "c": 2 } } ] })");
  const InputError e = expect_input_error([&] { load_config_json(file); });
  EXPECT_EQ(e.path(), "a[1].b.c");
  EXPECT_EQ(e.reason(), "duplicate key 'c'");
}

TEST(Config, CrossFieldChecks) {
  const auto path_of_error = [](const Json& doc) {
    return expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path();
  };
  Json doc = minimal_scene();
  doc["mechanism"]["cam"]["rpm"] = 0;
  doc["simulation"] = Json::parse(R"({ "duration": 0.1 })");
  EXPECT_EQ(path_of_error(doc), "simulation.output_step");
  doc["simulation"] = Json::parse(R"({ "duration": 0.1, "output_step": 1e-4, "cycles": 2 })");
  EXPECT_EQ(path_of_error(doc), "simulation.cycles");

  doc = minimal_scene();
  doc["simulation"] = Json::parse(R"({ "duration": 0.1, "discard_cycles": 2 })");  // 2 cycles at 1200 rpm
  EXPECT_EQ(path_of_error(doc), "simulation.discard_cycles");
  doc["simulation"] = Json::parse(R"({ "output_step": 1e-4, "output_step_deg": 1 })");
  EXPECT_EQ(path_of_error(doc), "simulation.output_step");

  doc = minimal_scene();
  doc["mechanism"]["contact"]["damping"] = 10;  // not kelvin_voigt
  EXPECT_EQ(path_of_error(doc), "mechanism.contact.damping");

  doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"]["segments"][0].erase("lift");
  EXPECT_EQ(path_of_error(doc), "mechanism.cam.motion_law.segments[0].lift");
  doc["mechanism"]["cam"]["motion_law"]["segments"][0]["lift_deg"] = 20;
  EXPECT_EQ(path_of_error(doc), "mechanism.cam.motion_law.segments[0].lift_deg");

  doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"]["segments"][0]["degree"] = 5;  // not a spline segment
  EXPECT_EQ(path_of_error(doc), "mechanism.cam.motion_law.segments[0].degree");

  doc = minimal_scene();
  doc["mechanism"]["cam"]["motion_law"]["spline"] = Json::parse(R"({ "knots_deg": [0], "lift": [0] })");
  EXPECT_EQ(path_of_error(doc), "mechanism.cam.motion_law");

  doc = minimal_scene();
  doc["mechanism"]["follower"]["friction"] = 0.1;  // belongs to contact
  EXPECT_EQ(path_of_error(doc), "mechanism.follower.friction");

  // A roller with friction is fine, and so is an offset inside the reach.
  doc = minimal_scene();
  doc["mechanism"]["contact"]["friction"]["mu"] = 0.2;
  doc["mechanism"]["follower"]["offset"] = 0.049;
  EXPECT_NO_THROW(scene_from_json(doc, {"s.json", "/"}));
}

TEST(Config, NameMustBeUsableAsAFolder) {
  Json doc = minimal_scene();
  doc["name"] = "../escape";
  EXPECT_EQ(expect_input_error([&] { scene_from_json(doc, {"s.json", "/"}); }).path(), "name");
}

// ---------------------------------------------------------------- suggestions

TEST(Suggest, EditDistanceCountsAnAdjacentTranspositionAsOneEdit) {
  EXPECT_EQ(edit_distance("", ""), 0u);
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("rpm", "rpm"), 0u);
  EXPECT_EQ(edit_distance("rmp", "rpm"), 1u);  // transposition
  EXPECT_EQ(edit_distance("rpmm", "rpm"), 1u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("ca", "abc"), 3u);  // optimal string alignment, not full Damerau
  EXPECT_EQ(edit_distance("abc", "ca"), edit_distance("ca", "abc"));
}

TEST(Suggest, ClosestMatchFindsPlausibleTyposOnly) {
  const std::vector<std::string> keys = {"base_radius", "rpm", "direction", "motion_law", "drive"};
  EXPECT_EQ(closest_match("rpmm", keys), "rpm");
  EXPECT_EQ(closest_match("RPM", keys), "rpm");  // case-insensitive
  EXPECT_EQ(closest_match("base_raduis", keys), "base_radius");
  EXPECT_EQ(closest_match("motionlaw", keys), "motion_law");
  EXPECT_EQ(closest_match("dirve", keys), "drive");
  EXPECT_FALSE(closest_match("xyz", keys).has_value());
  EXPECT_FALSE(closest_match("radius", keys).has_value());
  EXPECT_FALSE(closest_match("rpm", {}).has_value());
  EXPECT_EQ(closest_match("ab", {"ax", "ay"}), "ax");  // ties: the first
}

TEST(Suggest, APartialNameSuggestsTheShortestNameItStarts) {
  const std::vector<std::string> models = {"hertz", "kelvin_voigt", "hunt_crossley", "lankarani_nikravesh", "flores"};
  EXPECT_EQ(closest_match("lankarani", models), "lankarani_nikravesh");
  EXPECT_EQ(closest_match("Kelvin", models), "kelvin_voigt");
  EXPECT_EQ(closest_match("polynomial", {"polynomial_4567", "polynomial_345"}), "polynomial_345");
  EXPECT_FALSE(closest_match("la", models).has_value());         // too short to be a partial name
  EXPECT_FALSE(closest_match("nikravesh", models).has_value());  // a prefix, not any part
}

TEST(Config, APartialContactModelNameGetsTheFullNameSuggested) {
  Json doc = minimal_scene();
  doc["mechanism"]["contact"]["model"] = "lankarani";
  const InputError e = expect_input_error([&] { scene_from_json(doc, {"scene.json", "/"}); });
  EXPECT_EQ(e.path(), "mechanism.contact.model");
  EXPECT_NE(e.reason().find("(did you mean 'lankarani_nikravesh'?)"), std::string::npos) << e.reason();
}

TEST(Suggest, DidYouMeanFormatsTheHint) {
  EXPECT_EQ(did_you_mean("stifness", {"stiffness", "exponent"}), " (did you mean 'stiffness'?)");
  EXPECT_EQ(did_you_mean("qqqq", {"stiffness", "exponent"}), "");
}

}  // namespace
}  // namespace camdyn
