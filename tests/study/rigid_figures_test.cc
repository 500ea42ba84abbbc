// The simulate outputs' rigid figures on a follower train are the held
// train's (docs/model.md §12, "Rigid figures of a train"), computed here from
// held_train + held_train_values: the report's "rigid model" force, stress
// and torque curves and summary.json `spring_sizing` on
// studies/valvetrain/bucket_tappet.json; a scene without a train keeps the
// one-mass sizing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "common/constants.h"
#include "contact/hertz_pressure.h"
#include "dynamics/held_train.h"
#include "dynamics/held_train_force.h"
#include "dynamics/simulation.h"
#include "dynamics/spring_sizing.h"
#include "io/config.h"
#include "study/simulation_output.h"
#include "study_paths.h"

namespace camdyn {
namespace {

const std::string kBucketTappet = kStudies + "valvetrain/bucket_tappet.json";
constexpr int kHeldGrid = RigidContactForce::kHeldAngles;

/// The held train's cam contact force [N] on its grid (the bucket translates: lever 1).
std::vector<double> bucket_held_force(const Model& model) {
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, kHeldGrid);
  const Eigen::VectorXd v = held_train_values(held_train(model), law, model.omega)[0];
  return std::vector<double>(v.data(), v.data() + v.size());
}

/// Linear between the grid angles, θ in degrees.
double at_degrees(const std::vector<double>& grid, double deg) {
  double x = std::fmod(deg / 360.0, 1.0) * static_cast<double>(grid.size());
  if (x < 0.0) x += static_cast<double>(grid.size());
  const std::size_t i = static_cast<std::size_t>(x) % grid.size();
  const double w = x - std::floor(x);
  return (1.0 - w) * grid[i] + w * grid[(i + 1) % grid.size()];
}

const Series& series_of(const Report& report, const std::string& title_start, const std::string& label) {
  for (const Plot& p : report.plots)
    if (p.title.rfind(title_start, 0) == 0)
      for (const Series& s : p.series)
        if (s.label == label) return s;
  throw std::runtime_error("no series " + label + " in a plot " + title_start);
}

TEST(RigidFiguresOutput, ReportCurvesAreTheHeldTrains) {
  SceneConfig scene = load_scene(kBucketTappet, {"mechanism.cam.rpm=1000", "simulation.cycles=2",
                                                 "simulation.discard_cycles=1", "simulation.output_step_deg=2"});
  const Model model = build_model(scene, kBucketTappet);
  const SimulationResult r = simulate_scene(scene, kBucketTappet);
  ASSERT_TRUE(r.solver.converged()) << r.solver.message;
  const Report report = simulation_report(scene, model, r);
  const std::vector<double> held = bucket_held_force(model);
  const double e_star = 2.1e11 / (2.0 * (1.0 - 0.3 * 0.3));  // steel on steel [Pa]
  const Series& force = series_of(report, "Last revolution: contact force and the rigid", "rigid model");
  const Series& stress = series_of(report, "Last revolution: contact stress", "rigid model");
  const Series& torque = series_of(report, "Last revolution: drive torque", "rigid model");
  ASSERT_EQ(force.x.size(), stress.x.size());
  int checked = 0;
  for (std::size_t j = 0; j < force.x.size(); ++j) {
    if (std::isnan(force.y[j])) continue;  // the wrap
    const double deg = force.x[j], p = at_degrees(held, deg);
    const LawSample s = model.law->eval(deg * kPi / 180.0);
    EXPECT_NEAR(force.y[j], p, 1e-6 * std::abs(p) + 1e-6) << deg;
    const double mpa = 1e-6 * hertz_line_pressure(p, 0.012, e_star, 1.0 / (0.02 + s.s + s.d2s));
    EXPECT_NEAR(stress.y[j], mpa, 1e-6 * mpa + 1e-9) << deg;
    EXPECT_NEAR(torque.y[j], p * s.ds, 1e-6 * std::abs(p * s.ds) + 1e-9) << deg;
    ++checked;
  }
  EXPECT_GT(checked, 150);
  // Against a real 600 N, not the ±13 N of the follower alone.
  EXPECT_GT(*std::max_element(force.y.begin(), force.y.end()), 500.0);
}

TEST(RigidFiguresOutput, SpringSizingIsTheHeldTrainsWithItsUnit) {
  const Model model = build_model(load_scene(kBucketTappet), kBucketTappet);
  const Json j = spring_sizing_json(model);
  const HeldSpringSizing s = size_held_spring(model, 0.0, model.omega);
  ASSERT_TRUE(s.available) << s.reason;
  EXPECT_EQ(j.at("model"), "held train");
  EXPECT_EQ(j.at("spring"), "mechanism.follower.spring");
  EXPECT_EQ(j.at("required_preload").get<double>(), s.required_preload);
  EXPECT_EQ(j.at("required_preload_unit"), "N");
  EXPECT_TRUE(j.at("required_stiffness").is_null());
  EXPECT_TRUE(j.at("required_stiffness_unavailable").is_string());
  EXPECT_FALSE(j.contains("required_preload_unavailable"));
}

TEST(RigidFiguresOutput, SpringSizingWithoutASpringIsNullWithTheReason) {
  const Model model = build_model(
      load_scene(kBucketTappet, {"mechanism.follower.spring={\"stiffness\": 0, \"preload\": 0}",
                                 "mechanism.train=[{\"name\": \"a\", \"mass\": 0.05, \"link\": {\"ratio\": 1, "
                                 "\"stiffness\": 1e8}}]"}),
      kBucketTappet);
  const Json j = spring_sizing_json(model);
  EXPECT_TRUE(j.at("required_preload").is_null());
  EXPECT_EQ(j.at("required_preload_unavailable"), "the scene has no spring to size");
  EXPECT_EQ(j.at("required_preload_unit"), "N");
}

TEST(RigidFiguresOutput, WithoutATrainTheSizingIsTheOneMassFigure) {
  const Model model = build_model(load_scene(kQuickstart), kQuickstart);
  ASSERT_FALSE(rigid_figures_held(model));
  const Json j = spring_sizing_json(model);
  const SpringSizing s = size_spring(*model.law, *rigid_spring_load(model, 0.0), model.omega);
  EXPECT_EQ(j.at("required_preload").get<double>(), s.required_preload);
  EXPECT_EQ(j.at("required_preload_unit"), "N");
  EXPECT_FALSE(j.contains("model"));
}

}  // namespace
}  // namespace camdyn
