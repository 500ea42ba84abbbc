// Plausibility of units (dynamics/plausibility.h, docs/warnings.md "Units"):
// a spring rate that needs metres of installed compression for its preload, a
// mass too heavy for the kind of follower or valve-train part, a checking
// height of outputs.valvetrain at or above the lift it is measured on. Each
// fires on the slip, names the dotted field and stays silent on the plausible
// value and on every committed simulate study.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "dynamics/plausibility.h"
#include "io/config.h"
#include "scenes.h"
#include "study_paths.h"

namespace camdyn {
namespace {

/// The three causes of this file.
const std::vector<std::string> kUnitCauses = {"spring_units", "mass_units", "checking_height"};

std::vector<PlausibilityWarning> unit_warnings_of(const SceneConfig& scene) {
  return input_warnings(scene, build_model(scene, "test"));
}

int unit_count(const std::vector<PlausibilityWarning>& warnings, const std::string& cause, const std::string& field) {
  int n = 0;
  for (const PlausibilityWarning& w : warnings) n += w.cause == cause && w.field == field;
  return n;
}

int count_unit_causes(const std::vector<PlausibilityWarning>& warnings) {
  int n = 0;
  for (const PlausibilityWarning& w : warnings)
    for (const std::string& cause : kUnitCauses) n += w.cause == cause;
  return n;
}

/// The cycloidal test cam (20 mm lift) under a flat bucket tappet: 0.09 kg,
/// a 35 N/mm valve spring with 250 N installed and a seat 0.2 mm above the
/// base circle (0.2 mm lash), with outputs.valvetrain at 1 mm.
SceneConfig bucket_scene() {
  SceneConfig s = test::follower_scene("translating_flat", 0.0);
  FollowerConfig& f = s.mechanism.follower;
  f.mass = 0.09;
  f.spring.stiffness = 35000.0;
  f.spring.preload = 250.0;
  f.seat = test::hunt_crossley_seat(2e-4, 1e9);
  s.outputs.valvetrain = ValvetrainOutputConfig{};
  return s;
}

TEST(UnitPlausibility, TheBucketIsPlausible) { EXPECT_EQ(count_unit_causes(unit_warnings_of(bucket_scene())), 0); }

// 250 N on 40 N/m is 6.25 m of installed compression: the rate was meant in N/mm.
TEST(UnitPlausibility, SpringRateInNPerMmFires) {
  SceneConfig s = bucket_scene();
  s.mechanism.follower.spring.stiffness = 40.0;
  const std::vector<PlausibilityWarning> w = unit_warnings_of(s);
  EXPECT_EQ(unit_count(w, "spring_units", "mechanism.follower.spring.stiffness"), 1);
  // F0 / k just below 1 m (250 N on 251 N/m) does not.
  s.mechanism.follower.spring.stiffness = 251.0;
  EXPECT_EQ(unit_count(unit_warnings_of(s), "spring_units", "mechanism.follower.spring.stiffness"), 0);
  // A train body's spring is judged alike.
  SceneConfig train = bucket_scene();
  TrainBodyConfig valve;
  valve.name = "valve";
  valve.mass = 0.06;
  valve.link = {1.5, 2e7, 40.0, 0.0, true};
  valve.spring.stiffness = 45.0;
  valve.spring.preload = 400.0;
  train.mechanism.train = {valve};
  EXPECT_EQ(unit_count(unit_warnings_of(train), "spring_units", "mechanism.train[0].spring.stiffness"), 1);
}

// A 35 g bucket given as 35 (kg): above the 1 kg of any valve-train part.
TEST(UnitPlausibility, AFollowerMassInGramsFires) {
  SceneConfig s = bucket_scene();
  s.mechanism.follower.mass = 35.0;
  EXPECT_EQ(unit_count(unit_warnings_of(s), "mass_units", "mechanism.follower.mass"), 1);
  s.mechanism.follower.mass = 0.9;  // a heavy tappet, still plausible
  EXPECT_EQ(unit_count(unit_warnings_of(s), "mass_units", "mechanism.follower.mass"), 0);
  // Without a seat or a train the follower may be an industrial one: 35 kg is still too heavy (10 kg), 5 kg is not.
  SceneConfig industrial = test::follower_scene("translating_roller", 0.0);
  industrial.mechanism.follower.mass = 35.0;
  EXPECT_EQ(unit_count(unit_warnings_of(industrial), "mass_units", "mechanism.follower.mass"), 1);
  industrial.mechanism.follower.mass = 5.0;
  EXPECT_EQ(unit_count(unit_warnings_of(industrial), "mass_units", "mechanism.follower.mass"), 0);
  // An arm's inertia above 1 kg m².
  SceneConfig arm = test::follower_scene("oscillating_roller", 0.0);
  arm.mechanism.follower.inertia = 2.0;
  EXPECT_EQ(unit_count(unit_warnings_of(arm), "mass_units", "mechanism.follower.inertia"), 1);
}

// A checking height of 1 m on a lift of 20 mm (19.8 mm at the valve, from its seat).
TEST(UnitPlausibility, ACheckingHeightAboveTheLiftFires) {
  SceneConfig s = bucket_scene();
  s.outputs.valvetrain->checking_heights = {0.001, 1.0};
  EXPECT_EQ(unit_count(unit_warnings_of(s), "checking_height", "outputs.valvetrain.checking_heights[1]"), 1);
  EXPECT_EQ(unit_count(unit_warnings_of(s), "checking_height", "outputs.valvetrain.checking_heights[0]"), 0);
  // At the valve the lift is the cam's less the lash: 19.9 mm is above it, not above the cam's 20 mm.
  s.outputs.valvetrain->checking_heights = {0.0199};
  EXPECT_EQ(unit_count(unit_warnings_of(s), "checking_height", "outputs.valvetrain.checking_heights[0]"), 1);
  s.outputs.valvetrain->at = ValvetrainAt::cam;
  EXPECT_EQ(unit_count(unit_warnings_of(s), "checking_height", "outputs.valvetrain.checking_heights[0]"), 0);
}

TEST(UnitPlausibility, NoCommittedSimulateStudyFires) {
  int studies = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kStudiesDir)) {
    if (entry.path().extension() != ".json") continue;
    const Json doc = Json::parse(std::ifstream(entry.path()), nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("mechanism") || doc.contains("extends") ||
        doc.value("study", std::string("simulate")) != "simulate")
      continue;
    const std::string file = entry.path().string();
    const SceneConfig scene = load_scene(file);
    const std::vector<PlausibilityWarning> w = input_warnings(scene, build_model(scene, file));
    EXPECT_EQ(count_unit_causes(w), 0) << file;
    ++studies;
  }
  EXPECT_GE(studies, 8);
}

}  // namespace
}  // namespace camdyn
