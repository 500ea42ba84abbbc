// A spring's wire stress (docs/model.md §12, "Spring stress"): the Wahl
// factor against its closed form, and `peak_spring_stress` against the
// spring's largest force, for a massless follower spring and a spring with
// mass on a train body.
#include "dynamics/spring_stress.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "converged_run.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "scenes.h"

namespace camdyn {
namespace {

TEST(SpringStress, WahlFactorAgainstItsClosedForm) {
  // Index C = 24 / 4 = 6: K_W = 23/20 + 0.615/6 = 1.2525 (handbooks tabulate 1.253).
  const double per_newton = wahl_stress_per_newton(0.004, 0.024);
  const double nominal = 8.0 * 0.024 / (std::numbers::pi * 0.004 * 0.004 * 0.004);  // 8 D / (π d³) [Pa/N]
  EXPECT_NEAR(per_newton / nominal, 1.2525, 1e-12);
  // A large index (C = 1000): K_W → 1, the uncorrected torsion stress of a slender coil.
  EXPECT_NEAR(wahl_stress_per_newton(0.001, 1.0) / (8.0 / (std::numbers::pi * 1e-9)), 1.0, 2e-3);
}

SceneConfig quasi_static_scene() {
  SceneConfig s = test::cycloidal_cam_scene(60.0);
  s.mechanism.follower.spring.wire_diameter = 0.004;
  s.mechanism.follower.spring.mean_diameter = 0.024;
  return s;
}

using test::converged_run;

// The follower's massless spring: τ = K_W 8 D F / (π d³) at its largest
// force F₀ + k y, where the follower is highest.
TEST(SpringStress, AMasslessSpringPeaksAtItsLargestForce) {
  const SceneConfig scene = quasi_static_scene();
  const SimulationResult r = converged_run(scene);
  ASSERT_TRUE(r.metrics.peak_spring_stress);
  const double top = *std::max_element(r.series.follower_position.begin(), r.series.follower_position.end());
  const SpringConfig& s = scene.mechanism.follower.spring;
  const double expected = wahl_stress_per_newton(0.004, 0.024) * (s.preload + s.stiffness * top);  // [Pa]
  // The metric folds the samples the series records, and more: at least the
  // series' peak, and above it by no more than the lift between samples.
  EXPECT_GE(*r.metrics.peak_spring_stress, expected * (1.0 - 1e-12));
  EXPECT_LT(*r.metrics.peak_spring_stress, expected * (1.0 + 1e-6));
  // Without the wire, no metric.
  SceneConfig plain = scene;
  plain.mechanism.follower.spring.wire_diameter.reset();
  plain.mechanism.follower.spring.mean_diameter.reset();
  EXPECT_FALSE(converged_run(plain).metrics.peak_spring_stress);
}

// A spring with mass on the follower, lumped: quasi-statically every segment
// carries the frame end's force (the lumps' inertia aside), so the stress is
// the frame-end force's, which peak_spring_force measures.
TEST(SpringStress, ASpringWithMassPeaksAtItsMostLoadedSegment) {
  SceneConfig scene = quasi_static_scene();
  scene.mechanism.follower.spring.mass = 0.03;
  scene.mechanism.follower.spring.coils = 6;
  const SimulationResult r = converged_run(scene);
  ASSERT_TRUE(r.metrics.peak_spring_stress);
  ASSERT_TRUE(r.metrics.train);
  const double frame_end = wahl_stress_per_newton(0.004, 0.024) * r.metrics.train->peak_spring_force;
  EXPECT_GE(*r.metrics.peak_spring_stress, frame_end * (1.0 - 1e-12));
  EXPECT_LT(*r.metrics.peak_spring_stress, frame_end * (1.0 + 1e-3));
}

}  // namespace
}  // namespace camdyn
