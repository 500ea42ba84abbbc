// The force elements that act on the follower's coordinate q against the
// frame (docs/model.md §5): the return spring, the viscous damper and
// gravity. Each owns its parameters and says in one place its generalised
// force on q, the energy it stores, the power it dissipates, whether the
// mechanism has it and its name in summary.json `model.elements`. The
// model's right-hand side (in double, and in dual numbers for the exact
// Jacobian), the energy balance's terms and powers and the list of elements
// loop over them (FollowerForces::for_each). Each also declares its linear,
// time-invariant part (LinearPart) or that it has none: the closed forms
// (free flight, the rigid and held-train jump speeds, spring sizing, the
// rigid design stage) read the sum of those parts (linear_parts), never an
// element by name, and are off when some element has none. A new element of
// this kind is a struct here, its type in the FollowerForces list and its
// line in follower_forces(), and its config field (scene/scene.h,
// io/config.cc): docs/architecture.md, "Adding a force element".
#pragma once

#include <concepts>
#include <optional>
#include <tuple>
#include <type_traits>

#include "dynamics/spring_stress.h"
#include "scene/scene.h"

namespace camdyn {

/// The linear, time-invariant part of a generalised force on q: the force is
/// −(F₀ + k q + c q̇), with constant F₀, k and c.
struct LinearPart {
  double load = 0.0;       ///< F₀: force at q = 0, q̇ = 0 [N | N m], towards the cam when positive
  double stiffness = 0.0;  ///< k [N/m | N m/rad]
  double damping = 0.0;    ///< c [N s/m | N m s/rad]

  LinearPart& operator+=(const LinearPart& o) {
    load += o.load;
    stiffness += o.stiffness;
    damping += o.damping;
    return *this;
  }
  /// F₀ + k q: the force at q and q̇ = 0, towards the cam [N | N m].
  double at(double q) const { return stiffness * q + load; }
};

/// The stored energies of docs/model.md §7 that the follower's elements add to [J].
struct StoredEnergy {
  double spring = 0.0;   ///< springs, from their free length
  double gravity = 0.0;  ///< potential energy in gravity
};

/// The return spring: F₀ + k q pushing the follower towards the cam.
struct ReturnSpring {
  double stiffness = 0.0;          ///< k [N/m | N m/rad], >= 0
  double preload = 0.0;            ///< F₀: force [N] or torque [N m] at q = 0, >= 0
  double stress_per_newton = 0.0;  ///< its wire's shear stress per newton [Pa/N] (0: wire not given)

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
  /// Its linear part: all of it (none without stiffness or preload).
  std::optional<LinearPart> linear(double /*inertia*/) const { return LinearPart{preload, stiffness, 0.0}; }
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
  std::optional<LinearPart> linear(double /*inertia*/) const { return LinearPart{0.0, 0.0, damping}; }
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
  /// The weight M g, a constant load.
  std::optional<LinearPart> linear(double inertia) const { return LinearPart{inertia * acceleration, 0.0, 0.0}; }
};

/// A force element of the follower: what FollowerForces::for_each hands on.
/// `linear` is its linear, time-invariant part, or none for a force that is
/// nonlinear in q or q̇ or depends on the time or the cam angle (then every
/// closed form is off while the element is present).
template <class E>
concept FollowerForceElement = requires(const E& e, double x, StoredEnergy& energy) {
  { e.present() } -> std::convertible_to<bool>;
  { e.name(true) } -> std::convertible_to<const char*>;
  { e.force(x, x, x) } -> std::convertible_to<double>;
  e.add_energy(x, x, energy);
  { e.power(x) } -> std::convertible_to<double>;
  { e.linear(x) } -> std::same_as<std::optional<LinearPart>>;
};

/// What the closed forms read of the follower's forces: the return spring by
/// name (spring sizing solves for its preload or rate) and the linear parts of
/// every other element, summed in for_each order.
struct FollowerLinearParts {
  LinearPart spring;  ///< the return spring's F₀ and k (its c is 0)
  LinearPart others;  ///< every other element's, summed (gravity: F₀ = M g)

  /// The whole linear force, the spring's first.
  LinearPart total() const {
    LinearPart t = spring;
    t += others;
    return t;
  }
};

/// Why a closed form is off: the words every "not available" of one says.
inline constexpr const char* kNoLinearPart =
    "a force element on the follower or its train has no linear, time-invariant part (a gas load), so the closed "
    "form does not apply";

/// The follower's force elements against the frame, in the order their
/// forces are added: `Elements` each a FollowerForceElement, so an element
/// cannot join the list without saying its linear part. FollowerForces is
/// the model's list; a test may add an element of its own.
template <FollowerForceElement... Elements>
class BasicFollowerForces {
 public:
  template <class F>
  void for_each(F&& f) const {
    std::apply([&](const auto&... element) { (f(element), ...); }, elements_);
  }
  template <class E>
  E& get() {
    return std::get<E>(elements_);
  }
  template <class E>
  const E& get() const {
    return std::get<E>(elements_);
  }
  ReturnSpring& spring() { return get<ReturnSpring>(); }
  const ReturnSpring& spring() const { return get<ReturnSpring>(); }
  ViscousDamper& damper() { return get<ViscousDamper>(); }
  const ViscousDamper& damper() const { return get<ViscousDamper>(); }
  FollowerGravity& gravity() { return get<FollowerGravity>(); }
  const FollowerGravity& gravity() const { return get<FollowerGravity>(); }

  /// Weight M g of a body of inertia M [N].
  double weight(double inertia) const { return inertia * gravity().acceleration; }
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
  /// The sum of every element's linear part for a body of inertia M, or none
  /// as soon as one present element has none.
  std::optional<LinearPart> linear(double inertia) const {
    const std::optional<FollowerLinearParts> parts = linear_parts(inertia);
    if (!parts) return std::nullopt;
    return parts->total();
  }
  /// The return spring's linear part and the sum of the others', or none as
  /// soon as one present element has none.
  std::optional<FollowerLinearParts> linear_parts(double inertia) const {
    FollowerLinearParts parts;
    bool linear = true;
    for_each([&](const auto& element) {
      const std::optional<LinearPart> part = element.linear(inertia);
      if (!part)
        linear = linear && !element.present();  // an absent element adds no force
      else if constexpr (std::is_same_v<std::decay_t<decltype(element)>, ReturnSpring>)
        parts.spring += *part;
      else
        parts.others += *part;
    });
    if (!linear) return std::nullopt;
    return parts;
  }

 private:
  std::tuple<Elements...> elements_;
};

/// The model's follower elements.
using FollowerForces = BasicFollowerForces<ReturnSpring, ViscousDamper, FollowerGravity>;

/// The follower's elements of a scene (an oscillating arm has no gravity).
inline FollowerForces follower_forces(const SceneConfig& scene) {
  const FollowerConfig& f = scene.mechanism.follower;
  FollowerForces forces;
  const double stress = f.spring.wire_diameter && f.spring.mean_diameter
                            ? wahl_stress_per_newton(*f.spring.wire_diameter, *f.spring.mean_diameter)
                            : 0.0;
  forces.spring() = {f.spring.stiffness, f.spring.preload, stress};
  forces.damper() = {f.damping};
  forces.gravity() = {f.motion == FollowerMotion::oscillating ? 0.0 : scene.gravity};
  return forces;
}

}  // namespace camdyn
