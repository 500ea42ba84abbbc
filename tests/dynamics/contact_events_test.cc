// What an onset is (dynamics/contact_events.h): an impact needs a separation
// before it and a positive approach speed; every study's run keeps that, and
// impact_count counts exactly the impacts of the evaluated window.
#include "dynamics/contact_events.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "dynamics/simulation.h"
#include "io/config.h"
#include "study_paths.h"

namespace camdyn {
namespace {

TEST(ContactEvents, AnImpactNeedsASeparationBeforeAndAnApproach) {
  EXPECT_TRUE(classify_onset(true, 0.3).impact);
  EXPECT_FALSE(classify_onset(true, 0.3).grazing);
  // A graze: the gap touches zero without closing.
  EXPECT_FALSE(classify_onset(true, 0.0).impact);
  EXPECT_TRUE(classify_onset(true, 0.0).grazing);
  EXPECT_FALSE(classify_onset(true, -1e-6).impact);
  // A re-entry: a second onset with no separation between.
  EXPECT_FALSE(classify_onset(false, 0.3).impact);
  EXPECT_TRUE(classify_onset(false, 0.3).grazing);
}

/// Every onset of a run is an impact or a graze, never both; an impact has a
/// positive approach speed and follows a separation (or the run's start off
/// the cam); impact_count and max_impact_velocity are those of the impacts in
/// the evaluated window.
void expect_events_mean_what_they_say(const SimulationResult& r, bool started_off_the_cam, const std::string& what) {
  ASSERT_TRUE(r.solver.converged()) << what << ": " << r.solver.message;
  bool separated = started_off_the_cam;
  long impacts = 0;
  double fastest = 0.0;
  for (const ContactEvent& e : r.events) {
    if (!e.onset) {
      EXPECT_FALSE(e.impact || e.grazing) << what << " at t = " << e.time;
      separated = !e.lash;  // a lash opening (a body on its seat) is no separation
      continue;
    }
    if (e.lash) {  // the lash taken up: neither an impact nor a graze
      EXPECT_FALSE(e.impact || e.grazing) << what << " at t = " << e.time;
      separated = false;
      continue;
    }
    EXPECT_NE(e.impact, e.grazing) << what << " at t = " << e.time;
    EXPECT_EQ(e.impact, separated && e.speed > 0.0) << what << " at t = " << e.time;
    if (e.impact) {
      EXPECT_GT(e.speed, 0.0) << what << " at t = " << e.time;
    }
    if (e.impact && e.time >= r.evaluated_from) {
      ++impacts;
      fastest = std::max(fastest, e.speed);
    }
    separated = false;
  }
  EXPECT_EQ(r.metrics.impact_count, impacts) << what;
  EXPECT_EQ(r.metrics.max_impact_velocity, fastest) << what;
}

TEST(ContactEvents, EveryStudyRunCountsOnlyImpacts) {
  // Every committed simulate study (the scenes the others are built on).
  int studies = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(kStudiesDir)) {
    if (entry.path().extension() != ".json") continue;
    const Json doc = Json::parse(std::ifstream(entry.path()), nullptr, false);
    if (doc.is_discarded() || !doc.is_object() || !doc.contains("mechanism") || doc.contains("extends") ||
        doc.value("study", std::string("simulate")) != "simulate")
      continue;
    const std::string file = entry.path().string();
    const SceneConfig scene = load_scene(file);
    const SimulationResult r = simulate_scene(scene, file);
    // A run that starts off the cam (a drop test) lands first.
    const bool starts_off = !r.events.empty() && r.events.front().onset;
    expect_events_mean_what_they_say(r, starts_off, file);
    ++studies;
  }
  EXPECT_GE(studies, 8);
}

TEST(ContactEvents, AnArmSettlingThroughManyImpactsCountsOnlyImpacts) {
  // A packaging arm on a weak spring at 850 rpm: it leaves the cam on the
  // return and comes back through a long sequence of ever smaller impacts.
  const std::string file = kStudiesDir + "/followers/oscillating_roller.json";
  const SceneConfig scene = load_scene(
      file,
      {"mechanism.cam.rpm=850", "mechanism.follower.spring={\"stiffness\": 20, \"preload\": 2}",
       "mechanism.cam.motion_law=" + std::string(CAMDYN_SOURCE_DIR) + "/profiles/oscillating_roller_packaging.json"});
  const SimulationResult r = simulate_scene(scene, file);
  expect_events_mean_what_they_say(r, false, "arm at 850 rpm");
  EXPECT_GT(r.metrics.impact_count, 20);
}

}  // namespace
}  // namespace camdyn
