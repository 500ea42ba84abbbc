// The rigid stage's limits for followers without a pointwise form
// (optim/optimize/rigid_limits.h): an oscillating roller's pressure angle, radius of
// curvature and contact pressure. Each limit is set just below what the
// unlimited design reaches, so the case is worth testing; after tightening the
// design must meet it as `validate` checks it (the model's geometry report,
// the dynamics code's peak pressure over the whole revolution).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numbers>
#include <string>

#include "dynamics/contact_stress.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"

namespace camdyn::optim {
namespace {

const std::string kOscillatingRoller = std::string(CAMDYN_SOURCE_DIR) + "/studies/followers/oscillating_roller.json";

/// The oscillating roller as an optimize study at 1200 and 1600 rpm, steel
/// line contact, with `constraints` as given.
OptimizeStudy arm_study(const Json& constraints) {
  Json doc = load_config_json(kOscillatingRoller);
  doc["study"] = "optimize";
  doc["mechanism"]["cam"].erase("rpm");
  doc["mechanism"]["contact"]["stiffness"] =
      Json{{"from_materials", {{"E1", 2.1e11}, {"nu1", 0.3}, {"E2", 2.1e11}, {"nu2", 0.3}, {"width", 0.012}}}};
  doc["mechanism"]["contact"]["exponent"] = 1.0;
  doc["design"] = Json{{"segments", {"rise", "return"}}, {"control_points", 6}, {"degree", 5}};
  doc["operating_rpm"] = {1200, 1600};
  doc["objective"] = Json{{"separation", 1}};
  Json c = Json{{"max_pressure_angle_deg", nullptr}};
  for (const auto& [key, value] : constraints.items()) c[key] = value;
  doc["constraints"] = c;
  return read_optimize_study(doc, ConfigSource{kOscillatingRoller, CAMDYN_SOURCE_DIR "/studies/followers"});
}

struct DesignFigures {
  double pressure_angle_deg = 0.0, radius = 0.0, pressure = 0.0;  // [deg], [m], [Pa]
};

DesignFigures figures(const OptimizeStudy& s, const DesignSpace& space, const RigidDesign& d) {
  SceneConfig scene = space.scene(d.x);
  scene.mechanism.cam.rpm = 1600;
  const Model model = build_model(scene, kOscillatingRoller);
  DesignFigures out{model.geometry.max_pressure_angle_deg, model.geometry.min_radius_of_curvature, 0.0};
  const LineContact contact = *line_contact(scene.mechanism.contact);
  for (const double rpm : s.config.operating_rpm)
    out.pressure =
        std::max(out.pressure, peak_rigid_contact_pressure(model, contact, rpm * std::numbers::pi / 30.0).pressure);
  return out;
}

TEST(RigidLimits, ArmLimitsHoldAfterTightening) {
  const OptimizeStudy free = arm_study(Json::object());
  const DesignSpace space(free.baseline, free.config.design, kOscillatingRoller);
  const RigidStageResult a = run_rigid_stage(free.baseline, free.config, space, kOscillatingRoller);
  ASSERT_TRUE(a.design.have);
  const DesignFigures unlimited = figures(free, space, a.design);
  struct Case {
    const char* key;
    double limit;
    double DesignFigures::*figure;
    bool at_most;
  };
  const Case cases[] = {
      {"max_pressure_angle_deg", 0.97 * unlimited.pressure_angle_deg, &DesignFigures::pressure_angle_deg, true},
      {"min_radius_of_curvature", 1.03 * unlimited.radius, &DesignFigures::radius, false},
      {"max_contact_stress", 0.97 * unlimited.pressure, &DesignFigures::pressure, true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.key);
    const OptimizeStudy limited = arm_study(Json{{c.key, c.limit}});
    const RigidStageResult b = run_rigid_stage(limited.baseline, limited.config, space, kOscillatingRoller);
    ASSERT_TRUE(b.design.have);
    const double value = figures(limited, space, b.design).*c.figure;
    if (c.at_most)
      EXPECT_LE(value, c.limit);
    else
      EXPECT_GE(value, c.limit);
    EXPECT_GT(b.design.jump_free_rpm, 1600.0);  // still jump-free at both speeds
    std::printf("%s: %.5g -> %.5g (limit %.5g), jump-free %.5g -> %.5g rpm, %d LPs\n", c.key, unlimited.*c.figure,
                value, c.limit, a.design.jump_free_rpm, b.design.jump_free_rpm, b.lp_solves);
  }
}

}  // namespace
}  // namespace camdyn::optim
