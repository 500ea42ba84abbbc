// What each follower shape is, in one place (docs/model.md §1 and §4): the one
// switch over FollowerShape. Every other file asks this description (or
// FollowerGeometry::circle() / rolls(), which ask it) and never compares
// FollowerShape values, so a new shape that touches the cam with a circle or a
// line is its word in scene/scene.h and its case here (docs/architecture.md,
// "Adding a follower shape").
#pragma once

#include <stdexcept>
#include <string_view>

#include "scene/scene.h"

namespace camdyn {

/// The element with which a follower touches the cam. It decides the rest of
/// the contact geometry:
///  * circle of radius ρ (`shape.radius` [m], > 0): its centre runs on the
///    cam's pitch curve, which cam synthesis makes as the centre path (the cam
///    contour is that curve offset inwards by ρ); the contact is a one-parameter
///    problem on that curve (ContactReduction::circle) and, for stiffness from
///    materials, has radius of curvature ρ;
///  * line (a flat face of width `shape.face_width` [m], > 0): cam synthesis
///    makes the contour as the envelope of the face line, with no offset; the
///    contact is a line against the contour (ContactReduction::line), of
///    infinite radius of curvature.
enum class FollowerContact { circle, line };

/// The largest circle (roller, mushroom) radius as a multiple of the cam's
/// base radius [-]: beyond it the circle is flat to within the contact's
/// penetration, the contact point is lost in rounding and a run does not
/// finish (docs/warnings.md).
inline constexpr double kMaxCircleToBaseRadius = 1e3;

/// The description of one follower shape.
struct FollowerShapeTraits {
  FollowerContact contact = FollowerContact::circle;
  /// Spins on an axle: it takes a spin inertia (`shape.inertia` [kg m^2],
  /// >= 0), gets the roller spin state when that inertia and friction are both
  /// there, takes the friction force at its axle, and rolls freely (friction
  /// does no work) without inertia. A shape that does not roll slides.
  bool rolls = false;
  /// The shape in outputs and messages ("the flat face", "roller radius").
  std::string_view label;

  constexpr bool circle() const { return contact == FollowerContact::circle; }
  /// The `mechanism.follower.shape` fields it takes besides `type`.
  constexpr bool takes_radius() const { return contact == FollowerContact::circle; }
  constexpr bool takes_face_width() const { return contact == FollowerContact::line; }
  constexpr bool takes_inertia() const { return rolls; }
};

/// The description of `shape`. A shape missing here is a compiler error
/// (-Wswitch), not a silent default.
constexpr FollowerShapeTraits follower_shape_traits(FollowerShape shape) {
  switch (shape) {
    case FollowerShape::roller:
      return {FollowerContact::circle, true, "roller"};
    case FollowerShape::flat:
      return {FollowerContact::line, false, "flat face"};
    case FollowerShape::mushroom:
      return {FollowerContact::circle, false, "mushroom"};
  }
  throw std::invalid_argument("not a FollowerShape value");
}

}  // namespace camdyn
