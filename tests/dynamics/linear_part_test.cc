// The linear parts of the follower's force elements (dynamics/follower_forces.h,
// issue 57): their sum against the hand-written F₀ = preload + M g, k and c of
// a scene; an element without a linear part (a test-only nonlinear lash
// adjuster) turns every closed form off, none of them left silently wrong; and
// a test-only linear element is read through the sum by each closed form,
// which then agrees with the same closed form on a scene whose own spring
// carries that element's F₀ and k.
#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <stdexcept>

#include "dynamics/follower_forces.h"
#include "dynamics/free_flight.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/spring_sizing.h"
#include "dynamics/train_jump_speed.h"
#include "linear_train_case.h"
#include "optim/optimize/jump_bound.h"
#include "scenes.h"

namespace camdyn {
namespace {
namespace linear_part_test {  // its names kept apart from the other files of the unity build

constexpr double kFollowerMass = 0.3, kSpringRate = 5000.0, kSpringPreload = 40.0, kDamperRate = 2.0,
                 kGravityHere = 9.81;

SceneConfig full_scene() {
  SceneConfig s = test::cycloidal_cam_scene(600.0);
  s.mechanism.follower.mass = kFollowerMass;
  s.mechanism.follower.spring.stiffness = kSpringRate;
  s.mechanism.follower.spring.preload = kSpringPreload;
  s.mechanism.follower.damping = kDamperRate;
  s.gravity = kGravityHere;
  return s;
}

/// A nonlinear element, test-only: a cubic spring p q³ (a lash adjuster's
/// kind of force), with no linear part.
struct CubicSpring {
  double coefficient = 0.0;  ///< p [N/m³]

  bool present() const { return coefficient != 0.0; }
  const char* name(bool /*oscillating*/) const { return "cubic_spring"; }
  template <class S>
  S force(const S& q, const S& /*q_dot*/, double /*inertia*/) const {
    return -(coefficient * q * q * q);
  }
  void add_energy(double q, double /*inertia*/, StoredEnergy& e) const {
    e.spring += 0.25 * coefficient * q * q * q * q;
  }
  double power(double /*q_dot*/) const { return 0.0; }
  std::optional<LinearPart> linear(double /*inertia*/) const { return std::nullopt; }
};

/// A linear element, test-only: a second spring of F₀ and k beside the return spring.
struct HelperSpring {
  double load = 0.0, stiffness = 0.0;  ///< [N], [N/m]

  bool present() const { return load != 0.0 || stiffness != 0.0; }
  const char* name(bool /*oscillating*/) const { return "helper_spring"; }
  template <class S>
  S force(const S& q, const S& /*q_dot*/, double /*inertia*/) const {
    return -(load + stiffness * q);
  }
  void add_energy(double q, double /*inertia*/, StoredEnergy& e) const {
    e.spring += load * q + 0.5 * stiffness * q * q;
  }
  double power(double /*q_dot*/) const { return 0.0; }
  std::optional<LinearPart> linear(double /*inertia*/) const { return LinearPart{load, stiffness, 0.0}; }
};

/// An element that does not say its linear part cannot join the list.
struct Undeclared {
  bool present() const { return true; }
  const char* name(bool /*oscillating*/) const { return "undeclared"; }
  template <class S>
  S force(const S& q, const S& /*q_dot*/, double /*inertia*/) const {
    return -q;
  }
  void add_energy(double /*q*/, double /*inertia*/, StoredEnergy& /*e*/) const {}
  double power(double /*q_dot*/) const { return 0.0; }
};
static_assert(FollowerForceElement<CubicSpring> && FollowerForceElement<HelperSpring>);
static_assert(!FollowerForceElement<Undeclared>, "an element must declare its linear part");

template <class Extra>
using Extended = BasicFollowerForces<ReturnSpring, ViscousDamper, FollowerGravity, Extra>;

/// The model's own three elements with `extra` after them.
template <class Extra>
Extended<Extra> extended(const FollowerForces& forces, const Extra& extra) {
  Extended<Extra> out;
  out.spring() = forces.spring();
  out.damper() = forces.damper();
  out.gravity() = forces.gravity();
  out.template get<Extra>() = extra;
  return out;
}

TEST(LinearPart, SumIsThePreloadAndWeightRateAndDamping) {
  const Model model = build_model(full_scene(), "test");
  const std::optional<LinearPart> sum = model.forces.linear(model.mass);
  ASSERT_TRUE(sum);
  EXPECT_DOUBLE_EQ(sum->load, kSpringPreload + kFollowerMass * kGravityHere);
  EXPECT_DOUBLE_EQ(sum->stiffness, kSpringRate);
  EXPECT_DOUBLE_EQ(sum->damping, kDamperRate);
  const std::optional<FollowerLinearParts> parts = follower_linear_parts(model);
  ASSERT_TRUE(parts);
  EXPECT_DOUBLE_EQ(parts->spring.load, kSpringPreload);
  EXPECT_DOUBLE_EQ(parts->spring.stiffness, kSpringRate);
  EXPECT_DOUBLE_EQ(parts->others.load, kFollowerMass * kGravityHere);
  EXPECT_DOUBLE_EQ(parts->others.stiffness, 0.0);
  EXPECT_DOUBLE_EQ(parts->others.damping, kDamperRate);
  // The elements' forces are −(F₀ + k q + c q̇) of the sum at any state.
  for (const double q : {-0.01, 0.0, 0.013})
    for (const double v : {-2.0, 0.5}) {
      double force = 0.0;
      model.forces.for_each([&](const auto& e) { force += e.force(q, v, model.mass); });
      EXPECT_NEAR(force, -(kSpringPreload + kFollowerMass * kGravityHere + kSpringRate * q + kDamperRate * v), 1e-12);
    }
}

TEST(LinearPart, AnArmHasNoWeight) {
  SceneConfig s = full_scene();
  s.mechanism.follower.motion = FollowerMotion::oscillating;
  FollowerForces forces = follower_forces(s);
  const std::optional<LinearPart> sum = forces.linear(0.002);
  ASSERT_TRUE(sum);
  EXPECT_EQ(sum->load, kSpringPreload);
  EXPECT_EQ(sum->stiffness, kSpringRate);
  EXPECT_EQ(sum->damping, kDamperRate);
}

TEST(LinearPart, AnElementWithoutOneLeavesNoSum) {
  const Model model = build_model(full_scene(), "test");
  // Absent (no force), it leaves the sum as it was.
  const auto absent = extended(model.forces, CubicSpring{});
  ASSERT_TRUE(absent.linear(model.mass));
  EXPECT_EQ(absent.linear(model.mass)->load, model.forces.linear(model.mass)->load);
  const auto present = extended(model.forces, CubicSpring{1e9});
  EXPECT_FALSE(present.linear(model.mass));
  EXPECT_FALSE(present.linear_parts(model.mass));
}

// Each closed form, given the forces with a nonlinear element present, says
// it has no answer; with the model's own forces it has one.
TEST(LinearPart, ANonlinearElementTurnsEveryClosedFormOff) {
  const Model model = build_model(full_scene(), "test");
  const std::optional<FollowerLinearParts> own = follower_linear_parts(model);
  const std::optional<FollowerLinearParts> none = extended(model.forces, CubicSpring{1e9}).linear_parts(model.mass);
  ASSERT_TRUE(own);
  ASSERT_FALSE(none);

  EXPECT_TRUE(flight_has_closed_form(model, own));
  EXPECT_FALSE(flight_has_closed_form(model, none));

  EXPECT_TRUE(std::isfinite(jump_speed_rpm(model, own)));
  EXPECT_TRUE(std::isnan(jump_speed_rpm(model, none)));
  EXPECT_TRUE(std::isfinite(damped_jump_speed_rpm(model, own)));
  EXPECT_TRUE(std::isnan(damped_jump_speed_rpm(model, none)));
  EXPECT_TRUE(std::isfinite(rigid_normal_force(model, own, 1.0, model.omega)));
  EXPECT_TRUE(std::isnan(rigid_normal_force(model, none, 1.0, model.omega)));

  EXPECT_TRUE(rigid_spring_load(model, 0.0, own));
  EXPECT_FALSE(rigid_spring_load(model, 0.0, none));
  EXPECT_TRUE(optim::rigid_follower(model, 0.0, own));
  EXPECT_FALSE(optim::rigid_follower(model, 0.0, none));

  EXPECT_NO_THROW(linear_train_without_contact(model, own));
  EXPECT_THROW(linear_train_without_contact(model, none), std::invalid_argument);

  const Model train = build_model(test::linear_train_case(1).scene, "test");
  ASSERT_TRUE(train.train.has_coordinates());
  const std::optional<FollowerLinearParts> train_none =
      extended(train.forces, CubicSpring{1e9}).linear_parts(train.mass);
  EXPECT_TRUE(std::isfinite(train_jump_speed_rpm(train, follower_linear_parts(train))));
  EXPECT_TRUE(std::isnan(train_jump_speed_rpm(train, train_none)));
  EXPECT_TRUE(size_held_spring(train, 0.0, 100.0, follower_linear_parts(train)).available);
  const HeldSpringSizing held = size_held_spring(train, 0.0, 100.0, train_none);
  EXPECT_FALSE(held.available);
  EXPECT_EQ(held.reason, kNoLinearPart);
}

constexpr double kHelperLoad = 7.0, kHelperRate = 1500.0;

/// full_scene with the helper spring's F₀ and k moved into its own spring.
Model combined_model() {
  SceneConfig s = full_scene();
  s.mechanism.follower.spring.stiffness = kSpringRate + kHelperRate;
  s.mechanism.follower.spring.preload = kSpringPreload + kHelperLoad;
  return build_model(s, "test");
}

// A linear element beside the spring goes into every closed form through the
// sum: the answers are those of a spring carrying its F₀ and k too.
TEST(LinearPart, ALinearElementIsReadThroughTheSum) {
  const Model model = build_model(full_scene(), "test");
  const Model combined = combined_model();
  const std::optional<FollowerLinearParts> parts =
      extended(model.forces, HelperSpring{kHelperLoad, kHelperRate}).linear_parts(model.mass);
  ASSERT_TRUE(parts);
  EXPECT_DOUBLE_EQ(parts->total().load, kSpringPreload + kHelperLoad + kFollowerMass * kGravityHere);
  EXPECT_DOUBLE_EQ(parts->total().stiffness, kSpringRate + kHelperRate);

  EXPECT_NEAR(jump_speed_rpm(model, parts), jump_speed_rpm(combined), 1e-9 * jump_speed_rpm(combined));
  EXPECT_NEAR(damped_jump_speed_rpm(model, parts), damped_jump_speed_rpm(combined),
              1e-9 * damped_jump_speed_rpm(combined));
  for (const double theta : {0.3, 1.5, 3.0, 4.5})
    EXPECT_NEAR(rigid_normal_force(model, parts, theta, model.omega), rigid_normal_force(combined, theta), 1e-9);

  FreeFlight flight(model, parts->total()), reference(combined);
  flight.start(0.0, 0.01, 1.5);
  reference.start(0.0, 0.01, 1.5);
  for (const double t : {1e-4, 3e-3, 2e-2}) {
    double q = 0.0, v = 0.0, q_ref = 0.0, v_ref = 0.0;
    flight.at(t, q, v);
    reference.at(t, q_ref, v_ref);
    EXPECT_NEAR(q, q_ref, 1e-14);
    EXPECT_NEAR(v, v_ref, 1e-12);
  }

  const LinearTrain lt = linear_train_without_contact(model, parts), lt_ref = linear_train_without_contact(combined);
  EXPECT_DOUBLE_EQ(lt.K(0, 0), lt_ref.K(0, 0));
  EXPECT_DOUBLE_EQ(lt.f0[0], lt_ref.f0[0]);

  // The spring sized stays the return spring: the helper's F₀ and k are known.
  const double omega_max = 2.0 * model.omega;
  RigidSpringLoad load = *rigid_spring_load(model, 0.0, parts);
  EXPECT_DOUBLE_EQ(load.other_stiffness, kHelperRate);
  EXPECT_DOUBLE_EQ(load.stiffness, kSpringRate);
  const SpringSizing sized = size_spring(*model.law, load, omega_max);
  const SpringSizing sized_ref = size_spring(*combined.law, *rigid_spring_load(combined, 0.0), omega_max);
  ASSERT_GT(sized_ref.required_preload, kHelperLoad);
  EXPECT_NEAR(sized.required_preload, sized_ref.required_preload - kHelperLoad, 1e-9 * sized_ref.required_preload);

  const optim::RigidFollower f = *optim::rigid_follower(model, 0.0, parts);
  const optim::RigidFollower f_ref = *optim::rigid_follower(combined, 0.0);
  for (const double theta : {0.3, 1.5, 3.0, 4.5}) {
    const LawSample s = model.law->eval(theta);
    EXPECT_NEAR(f.margin(model.omega, s), f_ref.margin(model.omega, s), 1e-9);
  }
}

}  // namespace linear_part_test
}  // namespace
}  // namespace camdyn
