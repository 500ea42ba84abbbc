// The jump speed of a follower train (docs/model.md §12): the train with every
// one-sided force held — the cam contact linearised at its mean load, every
// link in contact, seats, stops and coil clash left out — is linear, and its
// jump speed is the lowest cam speed at which the smallest cam contact or link
// force over a revolution of its periodic response reaches zero
// (dynamics/linear_train_response.h). For one rigid mass it is the rigid
// figure of docs/model.md §9.
#pragma once

#include <optional>
#include <string>

#include "dynamics/linear_train_response.h"
#include "dynamics/model.h"

namespace camdyn {

/// The model's train, held and linearised: coordinate 0 the follower, then
/// the train's coordinates in order. Held forces: the cam contact first, then
/// each link; peaks: each spring's frame end. The cam contact is taken along
/// the follower's coordinate (δ = s − q; an arm: δ = L (s − q), L the arm
/// length), linearised at the mean contact force of the static train.
LinearTrain linearised_train(const Model& model);

/// The same train without the cam contact: coordinate 0's row holds the
/// follower's inertia, spring, damper and weight and the train's forces on it
/// (the held train of dynamics/held_train.h prescribes that coordinate):
/// the sum of the follower forces' linear parts (follower_linear_parts).
/// Throws std::invalid_argument when some follower element has none (as do
/// linearised_train and held_train, which build on it).
LinearTrain linear_train_without_contact(const Model& model);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
LinearTrain linear_train_without_contact(const Model& model, const std::optional<FollowerLinearParts>& linear);

/// The train's jump speed [rpm] for a model whose train has coordinates of
/// its own (bodies or spring lumps); +inf when no held force reaches zero up
/// to 20 times the rigid figure (or 100 000 rpm without one); 0 when the
/// static train does not hold the contact; NaN, no figure, when some
/// follower element has no linear part.
double train_jump_speed_rpm(const Model& model);
double train_jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear);

/// The model's jump speed [rpm]: its train's (Model::train_jump_speed_rpm)
/// where the train has coordinates of its own, else the rigid figure of
/// docs/model.md §9 (dynamics/rigid_jump_speed.h).
double model_jump_speed_rpm(const Model& model);

/// A jump speed [rpm] for messages: `digits` significant digits and " rpm";
/// "none (the law never decelerates)" for +inf; for NaN (the closed form is
/// off: an element without a linear part, such as a gas load) "not
/// available" with the reason.
std::string jump_speed_text(double rpm, int digits);

/// What model_jump_speed_rpm is, for messages: "train jump speed (held, linearised)"
/// or "rigid-model jump speed".
const char* jump_speed_name(const Model& model);

/// Whether the rigid single-mass spring sizing (dynamics/spring_sizing.h)
/// describes the model: not for a train with coordinates of its own or a
/// follower spring with mass.
bool rigid_spring_sizing_applies(const Model& model);

}  // namespace camdyn
