// Slow identification fits (label `slow`, `ctest --preset slow`): the
// cam-rig acceleration records of studies/identify_cam_rig, whose simulations
// run a cam revolution each, and a second far start of the drop study.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/config.h"
#include "optim/identify/identify.h"
#include "study_paths.h"
#include "tolerance.h"

namespace camdyn::optim {
namespace {

IdentifyResult fit(const std::string& file, const std::vector<std::string>& overrides = {}) {
  const Json doc = load_config_json(file, overrides);
  IdentifyOptions options;
  options.threads = 2;
  return identify(load_identify_problem(doc, config_source(file)), options);
}

const ParameterEstimate& estimate(const IdentifyResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters)
    if (p.name == name) return p;
  throw std::out_of_range(name);
}

TEST(IdentifyCamRig, RecoversContactStiffnessAndFollowerDampingWithinFivePercent) {
  // generate.py's truth: K = 6e9 N/m^1.5, c = 20 N s/m; the study starts from
  // the rig's estimates 1e10 and 15 N s/m.
  const IdentifyResult r = fit(kStudies + "identify_cam_rig/identify_cam_rig.json");
  const ParameterEstimate& k = estimate(r, "contact.stiffness");
  const ParameterEstimate& c = estimate(r, "follower.damping");
  EXPECT_NEAR(k.value / 6e9 - 1.0, 0.0, test::kStatistical);
  EXPECT_NEAR(c.value / 20.0 - 1.0, 0.0, test::kStatistical);
  ASSERT_TRUE(k.std_error && c.std_error);
  EXPECT_LT(std::abs(k.value - 6e9), 3.0 * *k.std_error);
  EXPECT_LT(std::abs(c.value - 20.0), 3.0 * *c.std_error);
  EXPECT_TRUE(r.identifiable);
  EXPECT_EQ(r.stages.size(), 3u);  // 2 ms and 0.5 ms smoothing, then the raw records
}

TEST(IdentifyDropSlow, ConvergesFromATenthOfTheStiffnessAndAThirdOfTheRestitution) {
  const std::string study = kStudies + "identify_drop/identify_drop.json";
  const IdentifyResult near = fit(study);
  const IdentifyResult far = fit(study, {"parameters.contact.stiffness.initial=2.5e8",     // truth / 10
                                         "parameters.contact.restitution.initial=0.21"});  // truth × 0.3
  for (const char* name : {"contact.stiffness", "contact.exponent", "contact.restitution"}) {
    SCOPED_TRACE(name);
    EXPECT_LT(std::abs(estimate(far, name).value - estimate(near, name).value), 0.05 * *estimate(near, name).std_error);
  }
}

}  // namespace
}  // namespace camdyn::optim
