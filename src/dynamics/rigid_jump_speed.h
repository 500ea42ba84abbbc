// The rigid-model force and jump speed of docs/model.md §9: the follower held
// exactly on its law, the normal force the cam must push with, and the
// lowest cam speed at which that force would have to pull. Every figure is
// in the generalised coordinate of any follower (translating or oscillating).
#pragma once

#include <optional>

#include "dynamics/model.h"

namespace camdyn {

/// The rigid-model critical (jump) speed of docs/model.md §9 [rpm], in the
/// generalised coordinate of any follower (the cam must push with
/// Q = M ω² s'' + k (s + x₀) + m g ≥ 0, and ∂g/∂q > 0 turns Q into a normal
/// force): min over θ with s'' < 0 of sqrt((k (s + x₀) + m g) / (−M s'')).
/// +inf if the law never decelerates. The forces are the sum of the follower
/// elements' linear parts (follower_linear_parts: k (s + x₀) the return
/// spring, m g and any other element's F₀ + k s beside it); NaN, no figure,
/// when some element has none.
double jump_speed_rpm(const Model& model);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
double jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear);

/// The same bound with the damper's c ω s' term: the lowest cam speed at
/// which the rigid-model normal force (rigid_normal_force) turns negative
/// somewhere on the cam [rpm]. A damper lowers it on the return (s' < 0);
/// equal to jump_speed_rpm without one; +inf if the force never turns; NaN
/// when some follower element has no linear part.
double damped_jump_speed_rpm(const Model& model);
double damped_jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear);

/// Rigid-model normal contact force at cam angle θ and constant speed [N]:
/// Q / (∂g/∂q) with Q = M ω² s'' + c ω s' + k (s + x₀) + m g (translating
/// roller: P / cos φ of docs/model.md §9). Negative: the follower would need
/// pulling. NaN when some follower element has no linear part.
double rigid_normal_force(const Model& model, double theta);
/// The same at cam speed `omega` [rad/s] instead of the model's.
double rigid_normal_force(const Model& model, double theta, double omega);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
double rigid_normal_force(const Model& model, const std::optional<FollowerLinearParts>& linear, double theta,
                          double omega);

}  // namespace camdyn
