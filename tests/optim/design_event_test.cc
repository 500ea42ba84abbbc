// An event design (design.event, optim/optimize/design.h) on baselines of
// other kinds than the valve lobe's periodic spline: on a segmented law the
// design space's least-squares start reproduces the baseline over the event
// and keeps the rest bit for bit; a rise that runs into the return gets a
// free nose; and the config refuses what an event design cannot do.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "study_paths.h"

namespace camdyn::optim {
namespace {

OptimizeStudy jump_study(std::vector<std::string> overrides) {
  return read_optimize_study(load_config_json(kOptimizeJump, overrides),
                             ConfigSource{kOptimizeJump, CAMDYN_SOURCE_DIR "/studies"});
}

// optimize_jump.json's baseline: 3-4-5 rise 0-120, dwell, return 180-300,
// dwell. The event covers rise, dwell and return as one curve.
TEST(DesignEvent, StartsFromTheBaselineAndKeepsTheRestBitForBit) {
  const OptimizeStudy s =
      jump_study({"design={\"event\": {\"from_deg\": 0, \"to_deg\": 300}, \"control_points\": 30, "
                  "\"degree\": 5, \"monotone\": false}"});
  const DesignSpace space(s.baseline, s.config.design, kOptimizeJump);
  ASSERT_TRUE(space.is_event());
  EXPECT_EQ(space.dimension(), 30);
  // A 30-point quintic follows the 3-4-5 lobe (and its dwell) to well under
  // 1 % of the lift; its acceleration, which jumps in s''' at the segment
  // ends, to a few percent.
  EXPECT_LT(space.fit_quality().max_lift_error, 1e-2);
  const MotionLaw base = build_motion_law(s.baseline.mechanism.cam.motion_law, kOptimizeJump);
  const MotionLaw start = build_motion_law(space.scene(space.initial()).mechanism.cam.motion_law, kOptimizeJump);
  for (int i = 0; i < 6000; ++i) {
    const double theta = (300.0 + 0.01 * i) * kDegToRad;
    ASSERT_EQ(base.eval(theta).s, start.eval(theta).s);
    ASSERT_EQ(base.eval(theta).d2s, start.eval(theta).d2s);
  }
}

TEST(DesignEvent, HasAFreeNoseWhereARiseRunsIntoTheReturn) {
  // With the dwell gone (the event spline rising and returning in one), the
  // lift at the top need not stop: the control points here make a lobe whose
  // acceleration at its peak is well below zero, which segment boundaries
  // (s' = s'' = 0) forbid.
  const OptimizeStudy s =
      jump_study({"design={\"event\": {\"from_deg\": 0, \"to_deg\": 300}, \"control_points\": 8, "
                  "\"degree\": 5, \"monotone\": false}"});
  const DesignSpace space(s.baseline, s.config.design, kOptimizeJump);
  std::vector<double> c;
  for (int j = 0; j < 8; ++j) c.push_back(std::sin(std::numbers::pi * (j + 1) / 9.0));
  const MotionLaw law = build_motion_law(space.scene_with_control_points(c).mechanism.cam.motion_law, kOptimizeJump);
  double top = 0.0, top_theta = 0.0;
  for (int i = 0; i <= 3000; ++i) {
    const double theta = 0.1 * i * kDegToRad;
    if (law.eval(theta).s > top) {
      top = law.eval(theta).s;
      top_theta = theta;
    }
  }
  EXPECT_LT(law.eval(top_theta).d2s, -0.1 * top);  // [m/rad²]: a rounded nose, not a flat one
}

TEST(DesignEvent, ConfigRefusesEndAngleRangesAndSpansOutOfOrder) {
  EXPECT_THROW(jump_study({"design={\"event\": {\"from_deg\": 0, \"to_deg\": 300}, \"end_deg_range\": "
                           "{\"rise\": [100, 130]}}"}),
               InputError);
  try {
    jump_study({"design={\"event\": {\"from_deg\": 200, \"to_deg\": 100}}"});
    FAIL() << "accepted an event that ends before it starts";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("design.event.to_deg"), std::string::npos) << e.what();
  }
}

// `design.segments: [["rise", "dwell", "return"]]` is the event from the
// start of the rise to the end of the return.
TEST(DesignEvent, AGroupOfSegmentsIsTheEventOverThem) {
  const OptimizeStudy s = jump_study({"design.segments=[[\"rise\", \"dwell\", \"return\"]]", "design.monotone=false"});
  ASSERT_TRUE(s.config.design.event.has_value());
  EXPECT_EQ(s.config.design.event->from_deg, 0.0);
  EXPECT_EQ(s.config.design.event->to_deg, 300.0);
  try {
    jump_study({"design.segments=[[\"return\", \"rise\"]]"});
    FAIL() << "accepted a group the baseline does not have";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("design.segments"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camdyn::optim
