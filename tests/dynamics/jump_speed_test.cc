// The rigid-model jump speed with the damper (damped_jump_speed_rpm) against
// its closed form for a translating follower: at each cam angle the force
// m ω² s'' + c ω s' + k (s + x₀) ≥ 0 is a quadratic in ω, whose positive root
// where s'' < 0 bounds the speed; the jump speed is the smallest root.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "io/config.h"
#include "study_paths.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// min over θ (on a fine grid) of the positive root of m s'' ω² + c s' ω + hold = 0 [rpm].
double closed_form_rpm(const Model& model) {
  const double x0 = model.forces.spring().preload / model.forces.spring().stiffness;
  double best = std::numeric_limits<double>::infinity();
  constexpr int kAngles = 72000;
  for (int i = 0; i < kAngles; ++i) {
    const LawSample s = model.law->eval(2 * std::numbers::pi * i / kAngles);
    if (!(s.d2s < 0.0)) continue;
    const double a = -model.mass * s.d2s, b = model.forces.damper().damping * s.ds,
                 hold = model.forces.spring().stiffness * (s.s + x0);
    best = std::min(best, (b + std::sqrt(b * b + 4 * a * hold)) / (2 * a));
  }
  return best * 60 / (2 * std::numbers::pi);
}

TEST(JumpSpeed, DamperLowersItAsTheQuadraticSays) {
  const Model model = build_model(load_scene(kQuickstart), kQuickstart);
  const double damped = damped_jump_speed_rpm(model);
  EXPECT_LT(damped, jump_speed_rpm(model));
  // The bound is sampled on 3600 angles against 72000 here: a minimum on a
  // grid of step h is off by O(h²) relative, about 1e-6 at 0.1°.
  constexpr double kAngleSampling = 1e-5;
  EXPECT_NEAR(damped / closed_form_rpm(model), 1.0, kAngleSampling);
}

TEST(JumpSpeed, WithoutADamperItIsTheUndampedBound) {
  const Model model = build_model(load_scene(kQuickstart, {"mechanism.follower.damping=0"}), kQuickstart);
  EXPECT_EQ(damped_jump_speed_rpm(model), jump_speed_rpm(model));
}

}  // namespace
}  // namespace camdyn
