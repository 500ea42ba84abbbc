// The contact stress and drive metrics in summary.json and the report
// (docs/model.md §8): a metric that does not apply is absent, never a number
// or NaN; one that is not known (the drive power without the work
// quadratures) is null; the report plots stress, torque and a flat face's
// contact point against cam angle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "study/simulation_output.h"
#include "tests/dynamics/scenes.h"

namespace camdyn {
namespace {

bool has_plot(const Report& report, const std::string& title_start) {
  return std::any_of(report.plots.begin(), report.plots.end(),
                     [&](const Plot& p) { return p.title.rfind(title_start, 0) == 0; });
}

TEST(StressOutput, MetricsThatDoNotApplyAreAbsentFromTheSummary) {
  Metrics m;
  m.peak_cam_torque = 3.0;
  m.mean_drive_power = std::numeric_limits<double>::quiet_NaN();  // no work quadratures
  const Json without = metrics_json(m);
  EXPECT_FALSE(without.contains("peak_contact_stress"));
  EXPECT_FALSE(without.contains("max_face_excursion"));
  EXPECT_EQ(without.at("peak_cam_torque").get<double>(), 3.0);
  EXPECT_TRUE(without.at("rms_cam_torque").is_number());
  EXPECT_TRUE(without.at("mean_drive_power").is_null());
  m.peak_contact_stress = 1.2e9;
  m.max_face_excursion = 0.018;
  const Json with = metrics_json(m);
  EXPECT_EQ(with.at("peak_contact_stress").get<double>(), 1.2e9);
  EXPECT_EQ(with.at("max_face_excursion").get<double>(), 0.018);
}

TEST(StressOutput, ReportPlotsStressTorqueAndTheFaceExcursion) {
  SceneConfig scene = test::follower_scene("translating_flat", 600.0);
  ContactConfig& c = scene.mechanism.contact;
  c.stiffness.reset();
  c.from_materials = MaterialsConfig{210e9, 0.3, 210e9, 0.3, 0.012};
  c.exponent = 1.0;
  scene.simulation.cycles = 2;
  scene.mechanism.cam.limits.max_contact_stress = 2e9;
  const Model model = build_model(scene, "test");
  const SimulationResult r = simulate_scene(scene, "test");
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  ASSERT_TRUE(r.metrics.peak_contact_stress.has_value());
  const Json summary = metrics_json(r.metrics);
  EXPECT_GT(summary.at("peak_contact_stress").get<double>(), 0.0);
  EXPECT_GT(summary.at("max_face_excursion").get<double>(), 0.0);
  const Report report = simulation_report(scene, model, r);
  EXPECT_TRUE(has_plot(report, "Last revolution: contact stress"));
  EXPECT_TRUE(has_plot(report, "Last revolution: drive torque"));
  EXPECT_TRUE(has_plot(report, "Last revolution: contact point across the flat face"));
}

}  // namespace
}  // namespace camdyn
