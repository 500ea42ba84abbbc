// Spring sizing on the rigid model (docs/model.md §11): for a given motion
// law, the smallest preload F₀ (at the spring's rate k) and the smallest rate
// k (at its preload F₀) that keep the rigid-model force
//   P(θ; ω) = M ω² s''(θ) + c ω s'(θ) + k s(θ) + F₀ + M g
// at least P_min at every cam angle θ and every cam speed ω in [0, ω_max].
// P is linear in (k, F₀), so the feasible springs are the intersection of
// half-planes k s(θ) + F₀ ≥ D(θ), with the demand
//   D(θ) = P_min − M g − min over ω ∈ [0, ω_max] of (M ω² s'' + c ω s')
// (M g, c: the sum of the linear parts of the follower's elements besides
// the spring, dynamics/follower_forces.h; one of them with a rate k_o also
// takes k_o s(θ) from the demand)
// (a quadratic in ω: its minimum is at an end or at its vertex). With one of
// (k, F₀) fixed the other is a closed-form maximum over θ, so no linear
// programme is needed. Generalised coordinate of any follower: an arm's
// figures are torques [N m] and rates [N m/rad].
//
// On a follower train (dynamics/held_train_force.h rigid_figures_held) the
// one-mass force describes only the follower: the sizing is the held train's
// (size_held_spring, docs/model.md §12 "Rigid figures of a train").
#pragma once

#include <optional>
#include <string>

#include "dynamics/model.h"
#include "geometry/motion_law.h"

namespace camdyn {

/// The follower as the rigid model sees it (translating: kg, N s/m, N/m, N):
/// the return spring, sized, and the linear parts of its other force
/// elements (dynamics/follower_forces.h), known.
struct RigidSpringLoad {
  double mass = 0.0;             ///< M [kg | kg m²]
  double damping = 0.0;          ///< c of the other elements (the damper) [N s/m | N m s/rad]
  double weight = 0.0;           ///< F₀ of the other elements: M g towards the cam [N | N m]
  double other_stiffness = 0.0;  ///< k of the other elements (none of the three has one) [N/m | N m/rad]
  double stiffness = 0.0;        ///< k of the spring in place [N/m | N m/rad]
  double preload = 0.0;          ///< F₀ of the spring in place [N | N m]
  double min_force = 0.0;        ///< P_min: the force to keep [N | N m], ≥ 0
};

struct SpringSizing {
  /// Smallest F₀ ≥ 0 that holds with the rate `stiffness` [N | N m].
  double required_preload = 0.0;
  double preload_at_deg = 0.0;  ///< cam angle where it is set [deg]
  /// Smallest k ≥ 0 that holds with the preload `preload` [N/m | N m/rad];
  /// +inf when no rate suffices (the demand exceeds F₀ where s = 0).
  double required_stiffness = 0.0;
};

/// Sizes the spring for `law` up to the cam speed `omega_max` [rad/s], ≥ 0,
/// with `samples` angles per piece of the law (both ends, each from inside
/// its own piece) and the largest demand refined by golden section.
SpringSizing size_spring(const MotionLaw& law, const RigidSpringLoad& load, double omega_max, int samples = 2000);

/// The load of `model` (its mass, its spring and the sum of its other
/// follower elements' linear parts: the damper, gravity) with P_min =
/// `min_force`; none, no sizing, when some follower element has no linear
/// part (dynamics/follower_forces.h kNoLinearPart).
std::optional<RigidSpringLoad> rigid_spring_load(const Model& model, double min_force);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
std::optional<RigidSpringLoad> rigid_spring_load(const Model& model, double min_force,
                                                 const std::optional<FollowerLinearParts>& linear);

/// The preload of one spring of a follower train sized on the held train
/// (dynamics/held_train.h): every held quantity (the cam contact, each link)
/// is L(θ; ω) + ΔF₀ g with g = a·K⁻¹ ∂f0/∂F₀ the static response to the
/// spring's preload (a constant load: the train is linear, and the contact is
/// kept linearised at the scene's own preload), so the smallest preload that
/// keeps every held quantity ≥ `min_force` at every speed up to ω_max is the
/// largest (floor − min L) / g over the quantities the preload raises, taken
/// at 200 equal speed steps and at each natural frequency over each
/// significant harmonic of the lift (where a resonance dips), on a grid of
/// 1024 angles.
struct HeldSpringSizing {
  bool available = false;
  std::string reason;             ///< why not, when not available
  std::string spring;             ///< the spring sized: "mechanism.follower.spring", "mechanism.train[i].spring"
  int body = 0;                   ///< its body (0: the follower; i: mechanism.train[i − 1])
  std::string unit = "N";         ///< of its preload: "N", or "N m" for an arm's own spring
  double required_preload = 0.0;  ///< smallest F₀ ≥ 0 [N | N m]
  double preload_at_deg = 0.0;    ///< cam angle where it is set [deg]
  double preload_at_rpm = 0.0;    ///< cam speed where it is set [rpm]
  std::string binding;            ///< the held quantity that sets it ("cam contact", "link valve")
};

/// `min_force` [N] the floor of the cam contact and of every link;
/// `omega_max` [rad/s] ≥ 0. The spring sized is the first, the follower's
/// first, whose preload unloads no held quantity (a follower's spring pulls
/// it off the links behind it; the valve's spring loads them all); not
/// available (with the reason) without such a spring, or where its preload
/// does not reach a quantity that falls below `min_force`, or when some
/// follower element has no linear part (the held train has none).
HeldSpringSizing size_held_spring(const Model& model, double min_force, double omega_max);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
HeldSpringSizing size_held_spring(const Model& model, double min_force, double omega_max,
                                  const std::optional<FollowerLinearParts>& linear);

}  // namespace camdyn
