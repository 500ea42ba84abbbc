// identify's further starts at once on --jobs threads (optim/identify/identify.cc
// identify()): the cam-rig fit of fit_quality_test.cc, whose first start runs
// into a local minimum so that the space-filling starts run, gives the same
// identified.json on one thread and on two, to the bit (every start's values
// and cost, the chosen parameters). Slow: the fit runs twice (about 10 s each).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cli_run.h"
#include "io/config.h"

namespace camdyn::optim {
namespace {

namespace fs = std::filesystem;

Json fit_rig(const std::string& jobs) {
  const fs::path dir = test::scratch_dir("identify_parallel_slowtest", "jobs" + jobs);
  const std::vector<std::string> args = {
      "run",
      std::string(CAMDYN_SOURCE_DIR) + "/studies/identify_cam_rig/identify_cam_rig.json",
      "--out",
      (dir / "out").string(),
      "--quiet",
      "--jobs",
      jobs,
      "--set",
      "mechanism.contact.stiffness=6e9",
      "--set",
      R"(parameters={"follower.damping": {"initial": 150, "lower": 0, "upper": 200},
                     "contact.restitution": {"initial": 0.3, "lower": 0.05, "upper": 1.0}})"};
  const test::Outcome r = test::run_camdyn(args, dir);
  EXPECT_EQ(r.code, 0) << r.err;
  return Json::parse(test::read_text(dir / "out" / "identified.json"));
}

TEST(IdentifyParallelStarts, TheStartsAtOnceGiveTheSequentialFitToTheBit) {
  const Json one = fit_rig("1"), two = fit_rig("2");
  ASSERT_GT(one["starts"].size(), 1u);
  EXPECT_EQ(two["starts"], one["starts"]);
  EXPECT_EQ(two["parameters"], one["parameters"]);
  EXPECT_EQ(two["poor_fit"], one["poor_fit"]);
}

}  // namespace
}  // namespace camdyn::optim
