// The friction elements (docs/model.md §4, §5): sliding friction at the cam
// contact with the roller's spin it drives, and friction at the follower's
// support (a translating follower's guide, an arm's pivot pin). Each owns its
// parameters and says in one place whether the mechanism has it, the states it
// adds, its force, the energy it stores and its names in summary.json
// `model.elements`; the model's right-hand side (double, and dual numbers for
// the exact Jacobian), the energy balance and the state layout call them
// (docs/architecture.md, "Adding a force element").
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "contact/friction.h"
#include "dynamics/state_layout.h"
#include "geometry/vec2.h"  // value(double)

namespace camdyn {

/// "kind:coulomb_linear" or "kind:coulomb_tanh": a friction element's name.
inline std::string friction_element_name(const char* kind, const FrictionLaw& law) {
  return std::string(kind) + ":coulomb_" + (law.linear_ramp ? "linear" : "tanh");
}

/// Sliding friction at the cam contact; on a roller with inertia, the spin Ω it drives.
struct ContactFriction {
  FrictionLaw law;
  bool present = false;         ///< friction force at the contact assembled
  double roller_inertia = 0.0;  ///< [kg m²]
  bool spin = false;            ///< roller spin state (roller with inertia and friction)

  /// Adds the roller's spin state to the layout.
  void declare_states(StateLayout& layout) const {
    if (spin) layout.spin = layout.add("roller_spin");
  }
  /// The roller's kinetic energy at spin Ω [J].
  double kinetic_energy(double omega_spin) const { return 0.5 * roller_inertia * omega_spin * omega_spin; }
  void add_names(std::vector<std::string>& elements) const {
    if (present) elements.push_back(friction_element_name("friction", law));
  }
};

/// Friction where the follower is held: μ_g |side load| against q̇ in a
/// translating follower's guide, μ_p r_pin |reaction| against q̇ at an arm's pivot.
struct SupportFriction {
  bool guide = false;
  FrictionLaw guide_law;
  bool pivot = false;
  FrictionLaw pivot_law;
  double pin_radius = 0.0;  ///< [m]

  bool present() const { return guide || pivot; }
  /// The guide's force [N] and the pivot's torque [N m] on q at rate q̇, from
  /// the contact force on the follower: its world x component (the side load)
  /// and its normal and friction parts [N].
  template <class S>
  void forces(const S& q_dot, const S& side_load, const S& normal_force, const S& friction_force, S& guide_force,
              S& pivot_torque) const {
    using std::abs;
    using std::sqrt;
    guide_force = S(0.0);
    pivot_torque = S(0.0);
    if (guide) guide_force = -(guide_law.coefficient_t(q_dot) * abs(side_load));
    if (pivot && value(normal_force) > 0.0) {
      const S reaction = sqrt(normal_force * normal_force + friction_force * friction_force);
      pivot_torque = -(pin_radius * pivot_law.coefficient_t(pin_radius * q_dot) * reaction);
    }
  }
  void add_names(std::vector<std::string>& elements) const {
    if (guide) elements.push_back(friction_element_name("guide_friction", guide_law));
    if (pivot) elements.push_back(friction_element_name("pivot_friction", pivot_law));
  }
};

}  // namespace camdyn
