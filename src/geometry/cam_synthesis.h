// Cam synthesis by envelope theory for every follower (docs/model.md §1):
// translating or oscillating, roller, mushroom or flat face
// (geometry/follower_geometry.h), and the manufacturability checks for each.
//
// The cam is the profile the contact tracker sees (a PeriodicCurve in the cam
// frame, parameter u = the cam angle θ at which that point is the contact):
//  * circle followers (roller, mushroom of radius ρ): the centre (pitch) curve
//    P(u) = R(−σu)·c(s(u)); the cam contour is its inner offset by ρ, so the
//    circle reduces to its centre against P with offset radius 0.
//  * flat face: the contour itself, the envelope of the face lines,
//    r(u) = R(−σu)·X(u) with X the world contact point of the follower on the
//    law: translating X = (σ s', r_b + s); oscillating (face through the
//    pivot A, direction d) X = A + μ d, μ = −(d·A) / (1 − σ κ s').
// Derivatives to third order come from truncated Taylor arithmetic on the
// law's s … s'''' (the flat-face contour's r''' needs s'''').
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>

#include "geometry/cam_roller.h"
#include "geometry/follower_geometry.h"
#include "geometry/motion_law.h"
#include "geometry/planar_curve.h"

namespace camdyn {

class SynthesisedCam final : public PeriodicCurve {
 public:
  /// `direction` σ: +1 ccw, −1 cw (the cam frame is at angle σθ in the world).
  SynthesisedCam(std::shared_ptr<const MotionLaw> law, const FollowerGeometry& follower, int direction);

  /// Circle followers: the centre curve; flat face: the contour. Cam frame [m].
  CurvePoint at(double u) const override;

  const MotionLaw& law() const { return *law_; }
  const FollowerGeometry& follower() const { return follower_; }
  int direction() const { return direction_; }

  /// The follower exactly on the law at cam angle θ (rigid model).
  struct Kinematics {
    Eigen::Vector2d contact;           ///< contact point, world [m]
    Eigen::Vector2d normal;            ///< unit normal of the contact force on the follower, world
    double g_q = 0.0;                  ///< ∂g/∂q [m/m or m/rad]: generalised force on q per newton of normal force
    double pressure_angle = 0.0;       ///< angle between the normal and the follower's contact-point velocity [rad]
    double face_offset = 0.0;          ///< contact offset across the face (follower_geometry.h face_frame) [m]
    double radius_of_curvature = 0.0;  ///< of the cam contour at the contact [m], > 0 convex (cusp ≤ 0 for flat)
  };
  Kinematics kinematics(double theta) const;

 private:
  std::shared_ptr<const MotionLaw> law_;
  FollowerGeometry follower_;
  int direction_ = 1;
};

/// Samples the cam over a full turn (at least `samples` points, refined near
/// extrema) and returns its pressure-angle and curvature figures. Throws
/// InputError naming the cam angle [deg] where:
///  * roller / mushroom: the pitch curve turns back about the cam centre, or
///    its convex radius of curvature is not larger than ρ (cusp / undercut);
///  * flat face: r_b + s + s'' ≤ 0 (translating; generally the envelope's
///    radius of curvature ≤ 0: a cusp; the message gives the minimum base
///    radius), the face turns faster than the cam (oscillating, 1 − σκs' ≤ 0),
///    or the contact leaves the face (|offset| > face_width / 2).
CamGeometryReport check_cam(const SynthesisedCam& cam, const std::string& file,
                            const std::string& path = "mechanism.cam", int samples = 3600);

}  // namespace camdyn
