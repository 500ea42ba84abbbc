// The contact stress a cam designer limits: the Hertz line-contact pressure
// (contact/hertz_pressure.h) of the rigid-model contact force (the follower
// on its law, the force from its equation of motion: rigid_normal_force) at
// the contact's curvatures, over a cam revolution. It is checked as
// `mechanism.cam.limits.max_contact_stress` when a model is built and held by
// an optimize study's `constraints.max_contact_stress`. Impacts of a follower
// that leaves the cam press harder; the limit is on the design's own force.
#pragma once

#include <optional>
#include <string>

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
/// contact (concave negative).
PressurePeak peak_rigid_contact_pressure(const Model& model, const LineContact& contact, double omega);

}  // namespace camdyn
