// The force elements that act on the follower's coordinate q against the
// frame (docs/model.md §5): the return spring, the viscous damper and
// gravity. Each owns its parameters and says in one place its generalised
// force on q, the energy it stores, the power it dissipates, whether the
// mechanism has it and its name in summary.json `model.elements`. The
// model's right-hand side (in double, and in dual numbers for the exact
// Jacobian), the energy balance's terms and powers and the list of elements
// loop over them (FollowerForces::for_each). A new element of this kind is a
// struct here with its lines in for_each and follower_forces(), and its
// config field (scene/scene.h, io/config.cc): docs/architecture.md, "Adding a
// force element".
#pragma once

#include "scene/scene.h"

namespace camdyn {

/// The stored energies of docs/model.md §7 that the follower's elements add to [J].
struct StoredEnergy {
  double spring = 0.0;   ///< springs, from their free length
  double gravity = 0.0;  ///< potential energy in gravity
};

/// The return spring: F₀ + k q pushing the follower towards the cam.
struct ReturnSpring {
  double stiffness = 0.0;  ///< k [N/m | N m/rad], >= 0
  double preload = 0.0;    ///< F₀: force [N] or torque [N m] at q = 0, >= 0

  bool present() const { return stiffness > 0.0 || preload > 0.0; }
  const char* name(bool oscillating) const { return oscillating ? "torsional_spring" : "spring"; }
  /// Generalised force on q [N | N m] at q [m | rad], q̇, for a body of inertia M.
  template <class S>
  S force(const S& q, const S& /*q_dot*/, double /*inertia*/) const {
    return -(preload + stiffness * q);
  }
  /// Stored energy [J], measured from the free length so that it is never negative.
  void add_energy(double q, double /*inertia*/, StoredEnergy& e) const {
    e.spring += preload * q + 0.5 * stiffness * q * q + (stiffness > 0.0 ? 0.5 * preload * preload / stiffness : 0.0);
  }
  double power(double /*q_dot*/) const { return 0.0; }  ///< dissipated [W]
};

/// The viscous damper: c q̇ against the motion.
struct ViscousDamper {
  double damping = 0.0;  ///< c [N s/m | N m s/rad], >= 0

  bool present() const { return damping > 0.0; }
  const char* name(bool oscillating) const { return oscillating ? "torsional_damper" : "damper"; }
  template <class S>
  S force(const S& /*q*/, const S& q_dot, double /*inertia*/) const {
    return -(damping * q_dot);
  }
  void add_energy(double /*q*/, double /*inertia*/, StoredEnergy& /*e*/) const {}
  double power(double q_dot) const { return damping * q_dot * q_dot; }
};

/// Gravity pulling a translating follower towards the cam (none on an arm,
/// whose centre of mass the model does not know).
struct FollowerGravity {
  double acceleration = 0.0;  ///< g [m/s²]

  bool present() const { return acceleration != 0.0; }
  const char* name(bool /*oscillating*/) const { return "gravity"; }
  /// A constant: added to a dual number it leaves the derivatives alone.
  template <class S>
  double force(const S& /*q*/, const S& /*q_dot*/, double inertia) const {
    return -(inertia * acceleration);
  }
  void add_energy(double q, double inertia, StoredEnergy& e) const { e.gravity += inertia * acceleration * q; }
  double power(double /*q_dot*/) const { return 0.0; }
};

/// The follower's force elements against the frame, in the order their
/// forces are added.
struct FollowerForces {
  ReturnSpring spring;
  ViscousDamper damper;
  FollowerGravity gravity;

  template <class F>
  void for_each(F&& f) const {
    f(spring);
    f(damper);
    f(gravity);
  }
  /// Weight M g of a body of inertia M [N].
  double weight(double inertia) const { return inertia * gravity.acceleration; }
  /// Energy stored at q [J] for a body of inertia M.
  StoredEnergy energy(double q, double inertia) const {
    StoredEnergy e;
    for_each([&](const auto& element) { element.add_energy(q, inertia, e); });
    return e;
  }
  /// Power dissipated at q̇ [W].
  double power(double q_dot) const {
    double p = 0.0;
    for_each([&](const auto& element) { p += element.power(q_dot); });
    return p;
  }
};

/// The follower's elements of a scene (an oscillating arm has no gravity).
inline FollowerForces follower_forces(const SceneConfig& scene) {
  const FollowerConfig& f = scene.mechanism.follower;
  FollowerForces forces;
  forces.spring = {f.spring.stiffness, f.spring.preload};
  forces.damper = {f.damping};
  forces.gravity = {f.motion == FollowerMotion::oscillating ? 0.0 : scene.gravity};
  return forces;
}

}  // namespace camdyn
