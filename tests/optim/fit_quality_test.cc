// A fit that cannot be confidently wrong (optim/identify/fit_quality.h and
// identify()'s starts): the cam-rig records (studies/identify_cam_rig, made
// by camdyn with follower damping 20 N s/m, restitution 0.8 and contact
// stiffness 6e9) fitted for damping and restitution from a start that runs
// into a local minimum. With one start the fit is flagged poor and reported
// as not identified, without standard errors; with the automatic starts the
// space-filling design finds the truth.
#include "optim/identify/fit_quality.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

TEST(FitQuality, TheCriticalRatioFallsWithTheSamplesToItsFloor) {
  EXPECT_GT(critical_variance_ratio(20), 2.0);
  EXPECT_NEAR(critical_variance_ratio(1000000), 1.5, 1e-12);
  EXPECT_GE(critical_variance_ratio(100), critical_variance_ratio(1000));
}

TEST(FitQuality, AMisfitAtTheNoiseIsGoodAndTwiceItIsPoor) {
  ExperimentFit fit;
  fit.name = "e";
  fit.time.assign(1000, 0.0);
  fit.signals = {"contact_force"};
  fit.noise = {2.0};
  fit.rms_error = {2.1};
  EXPECT_FALSE(assess_fit({fit}).poor);
  fit.rms_error = {4.0};
  const FitQuality q = assess_fit({fit});
  EXPECT_TRUE(q.poor);
  EXPECT_DOUBLE_EQ(q.worst_ratio, 4.0);
  EXPECT_EQ(q.where, "experiment 'e', contact_force");
}

Json fit_rig(const std::string& name, const std::vector<std::string>& more) {
  const fs::path dir = test::scratch_dir("fit_quality_test", name);
  std::vector<std::string> args = {"run",
                                   std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_cam_rig/identify_cam_rig.json",
                                   "--out",
                                   (dir / "out").string(),
                                   "--quiet",
                                   "--jobs",
                                   "2",
                                   "--set",
                                   "mechanism.contact.stiffness=6e9",
                                   "--set",
                                   R"(parameters={"follower.damping": {"initial": 150, "lower": 0, "upper": 200},
                     "contact.restitution": {"initial": 0.3, "lower": 0.05, "upper": 1.0}})"};
  args.insert(args.end(), more.begin(), more.end());
  const test::Outcome r = test::run_camdyn(args, dir);
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(dir / "out" / "identified.json"));
}

TEST(FitQuality, ALocalMinimumIsFlaggedNotIdentified) {
  const Json j = fit_rig("one_start", {"--set", "solver.starts=1"});
  EXPECT_TRUE(j["poor_fit"].get<bool>());
  EXPECT_FALSE(j["identifiable"].get<bool>());
  for (const auto& [name, p] : j["parameters"].items()) EXPECT_TRUE(p["std_error"].is_null()) << name;
  EXPECT_EQ(j["starts"].size(), 1u);
  EXPECT_NE(j["warnings"][0].get<std::string>().find("poor_fit: local minimum likely"), std::string::npos);
}

TEST(FitQuality, TheAutomaticStartsRecoverTheTruth) {
  const Json j = fit_rig("auto_starts", {});
  EXPECT_FALSE(j["poor_fit"].get<bool>());
  EXPECT_TRUE(j["identifiable"].get<bool>());
  EXPECT_GT(j["starts"].size(), 1u);
  const Json& damping = j["parameters"]["follower.damping"];
  const Json& restitution = j["parameters"]["contact.restitution"];
  // The truth within three standard errors (1 % noise on the records).
  EXPECT_NEAR(damping["value"].get<double>(), 20.0, 3.0 * damping["std_error"].get<double>() + 1e-3);
  EXPECT_NEAR(restitution["value"].get<double>(), 0.8, 3.0 * restitution["std_error"].get<double>());
}

}  // namespace
}  // namespace camdyn::optim
