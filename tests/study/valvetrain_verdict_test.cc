// The verdicts a valve-train engineer signs off (docs/valvetrain.md "What
// each verdict means") on the committed scenes with lash: the take-up
// bounces of the bucket are counted, never called a jump; the speed limit is
// the float's, within 3 % of the held train's jump speed (the train's own
// closed form, dynamics/train_jump_speed.h, independent of the simulation);
// the verdict's least contact force lies above the take-up windows; a valve
// held off its seat is red.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "study/simulation_output.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const std::string kBucketTappetStudy = kStudies + "valvetrain/bucket_tappet.json";
const std::string kDohcStudy = kStudies + "valvetrain/dohc_bucket_lash.json";

TEST(ValvetrainVerdict, TakeUpBouncesAreCountedNotCalledAJump) {
  const SceneConfig scene = load_scene(kBucketTappetStudy);
  const Model model = build_model(scene, kBucketTappetStudy);
  const SimulationResult r = simulate_scene(scene, kBucketTappetStudy);
  ASSERT_TRUE(r.solver.converged());
  const Metrics& m = r.metrics;
  ASSERT_TRUE(m.train && m.float_fraction);
  EXPECT_GT(m.separation_fraction, 0.0);  // the bucket bounces after its 1.24 m/s take-up
  EXPECT_GT(m.train->take_up_bounces, 0);
  EXPECT_EQ(*m.float_fraction, 0.0);  // 3000 rpm is below the held train's 3496 rpm
  EXPECT_FALSE(separates(m));
  EXPECT_TRUE(m.train->separates_first.empty());
  const Verdict v = simulation_verdict(scene, model, r);
  EXPECT_NE(v.tone, Verdict::Tone::bad);
  EXPECT_EQ(v.headline.rfind("stays in contact", 0), 0u) << v.headline;
  // The least contact force's angle lies above the take-up windows (not in the open lash nor at seating).
  const std::size_t at = v.headline.rfind(" at ");
  ASSERT_NE(at, std::string::npos) << v.headline;
  const double deg = std::stod(v.headline.substr(at + 4));
  const LawSample law = model.law->eval(deg * std::acos(-1.0) / 180.0);
  EXPECT_FALSE(in_take_up_windows(model.take_up, law)) << v.headline;
  EXPECT_GT(m.min_contact_force, 0.0);
}

TEST(ValvetrainVerdict, AValveHeldOffItsSeatIsRed) {
  SceneConfig scene = load_scene(kDohcStudy, {"mechanism.train[0].link.lash=0.0001"});
  scene.simulation.cycles = 2;
  const Model model = build_model(scene, kDohcStudy);
  const SimulationResult r = simulate_scene(scene, kDohcStudy);
  ASSERT_TRUE(r.metrics.train);
  EXPECT_TRUE(r.metrics.train->held_open);
  const Verdict v = simulation_verdict(scene, model, r);
  EXPECT_EQ(v.tone, Verdict::Tone::bad);
  EXPECT_NE(v.headline.find("valve held open"), std::string::npos) << v.headline;
}

// speed_limit.json of a committed valve-train scene over `low`–`high` rpm.
Json run_valvetrain_limit(const std::string& study, const std::string& name, double low, double high) {
  const fs::path dir = test::scratch_dir("valvetrain_verdict_test", name);
  const Json limit{{"low_rpm", low}, {"high_rpm", high}, {"scan", 13}, {"tolerance_rpm", 10}};
  const test::Outcome r = test::run_camdyn({"run", study, "--out", (dir / "out").string(), "--quiet", "--set",
                                            "study=speed_limit", "--set", "speed_limit=" + limit.dump()},
                                           dir);
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(dir / "out" / "speed_limit.json"));
}

// The float limit against the held train's jump speed: the simulated
// compliant train (surge, contact and link compliance, damping) may differ
// from the linearised held train by a few per cent (the 3 %).
constexpr double kHeldTrainLevel = 0.03;

TEST(ValvetrainVerdict, TheSpeedLimitIsTheFloatsNearTheHeldTrainsJumpSpeed) {
  for (const auto& [study, name] : {std::pair{kBucketTappetStudy, "bucket"}, std::pair{kDohcStudy, "dohc"}}) {
    // Separation is not monotone in speed (the spring's surge): a scan every 100 rpm.
    const Json j = run_valvetrain_limit(study, name, 3000.0, 4200.0);
    ASSERT_TRUE(j.at("limited").get<bool>()) << name;
    // Both float off the cam over the flank; the DOHC valve's link only rings
    // after the take-up (a take-up bounce where the law still accelerates it).
    EXPECT_EQ(j.at("limit_cause"), "float") << name;
    const double held = j.at("train_jump_speed_rpm").get<double>();
    EXPECT_NEAR(j.at("speed_limit_rpm").get<double>() / held, 1.0, kHeldTrainLevel) << name;
    // Below the limit the take-up bounces are there and counted, never a jump.
    long bounces = 0;
    for (const Json& check : j.at("checks"))
      if (check.at("in_contact").get<bool>()) bounces += check.at("take_up_bounces").get<long>();
    if (std::string(name) == "bucket") {
      EXPECT_GT(bounces, 0);
    }
  }
}

}  // namespace
}  // namespace camdyn
