// The contact stress a cam designer limits: the Hertz line-contact pressure
// (contact/hertz_pressure.h) of the rigid-model contact force (the follower
// on its law, the force from its equation of motion: rigid_normal_force; on a
// follower train the held train's, dynamics/held_train_force.h) at the
// contact's curvatures, over a cam revolution. It is checked as
// `mechanism.cam.limits.max_contact_stress` when a model is built and held by
// an optimize study's `constraints.max_contact_stress`. Impacts of a follower
// that leaves the cam press harder; the limit is on the design's own force.
#pragma once

#include <optional>
#include <string>

#include "dynamics/held_train_force.h"
#include "dynamics/model.h"

namespace camdyn {

/// A line contact's elastic data.
struct LineContact {
  double e_star = 0.0;  ///< effective modulus E* [Pa]
  double width = 0.0;   ///< contact width L [m]
};

/// From the scene's `contact.stiffness.from_materials` when it gives a width
/// (line contact); none otherwise.
std::optional<LineContact> line_contact(const ContactConfig& contact);

/// The line contact of `contact`, or InputError(file, path) saying that the
/// limit at `path` needs the contact's materials and width.
LineContact require_line_contact(const ContactConfig& contact, const std::string& file, const std::string& path);

/// κ₁ + κ₂ [1/m] of the contact: the cam contour's curvature from its radius
/// `cam_radius_of_curvature` [m] (concave negative; infinite or 0: straight)
/// plus the follower's (1/r for a roller or mushroom, 0 for a flat face).
double curvature_sum(double cam_radius_of_curvature, const FollowerGeometry& follower);

struct PressurePeak {
  double pressure = 0.0;  ///< [Pa]
  double at_deg = 0.0;    ///< cam angle [deg], in [0, 360)
};

/// The highest rigid-model Hertz pressure over a revolution at cam speed
/// `omega` [rad/s]: sampled every 0.1°, the highest local maxima refined by
/// golden section (geometry/extremum.h, as the cam checks do). The follower's curvature is its radius's inverse for a
/// roller or mushroom and 0 for a flat face; the cam's is its contour's at the
/// contact (concave negative). On a follower train the force is the held
/// train's (RigidContactForce), taken at its grid angles (0.088° apart).
PressurePeak peak_rigid_contact_pressure(const Model& model, const LineContact& contact, double omega);

/// The cam contour's radius of curvature [m] at the contact of the evaluation
/// `ev` (> 0 convex; infinite or 0 where straight): a synthesised cam's
/// contour at the tracked pair's parameter (the cam angle at which the rigid
/// follower touches that point, so for a translating flat face r_b + s + s''
/// there), a contour cam's fitted curve at its parameter. The general pair
/// form (a verification form) takes the rigid contact's at the cam angle.
/// Allocates nothing.
double contact_cam_radius_of_curvature(const Model& model, const Evaluation& ev);

/// The Hertz pressure p₀ [Pa] of the evaluation's contact force at its
/// curvatures (curvature_sum of contact_cam_radius_of_curvature and the
/// follower's); 0 without a compressive force. Allocates nothing.
double contact_pressure(const Model& model, const HertzContact& contact, const Evaluation& ev);

/// The rigid model's Hertz pressure p₀ [Pa] at cam angle `theta` [rad] of
/// the force `force` (its speed's) at the rigid contact's curvatures.
double rigid_contact_pressure(const Model& model, const HertzContact& contact, const RigidContactForce& force,
                              double theta);
/// The same at speed `omega` [rad/s] (on a train: the held train's response made for this one angle).
double rigid_contact_pressure(const Model& model, const HertzContact& contact, double theta, double omega);

/// The torque [N m] the drive puts on the cam against the contact (positive
/// driving): −(the contact's generalised force on the cam angle).
inline double cam_drive_torque(const Evaluation& ev) { return -ev.cam_torque; }

/// The rigid model's drive torque [N m] at cam angle `theta` [rad] and speed
/// `omega` [rad/s], without friction: by virtual power T ω = P q̇ with
/// q̇ = ω s'(θ), T = P s'(θ), P the generalised force the follower's
/// equation of motion needs on its law (rigid_normal_force · ∂g/∂q; on a
/// train the held train's, RigidContactForce::torque).
double rigid_cam_torque(const Model& model, double theta, double omega);

}  // namespace camdyn
