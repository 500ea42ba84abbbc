// Cam synthesis for a translating roller follower with offset, and the
// manufacturability checks of docs/model.md §1 (pressure angle, radius of
// curvature, undercut / cusp).
//
// Frame (docs/model.md §1): the cam turns about the origin; the follower moves
// along +y on the line x = e. With direction σ = +1 (ccw) a cam-fixed point p
// is at R(σθ)·p in the world frame. The roller centre at follower
// displacement s is C = (e, y₀ + s) with y₀ = sqrt((r_b + r_r)² − e²); the
// pitch curve (the roller centre's path in the cam frame) is
// P(u) = R(−σu)·(e, y₀ + s(u)). The cam contour is the inner offset of the
// pitch curve by r_r, so the distance from any roller centre to the contour
// is its distance to the pitch curve minus r_r: contact detection against the
// roller reduces to a point against the pitch curve (docs/model.md §2).
#pragma once

#include <Eigen/Core>

#include "geometry/motion_law.h"
#include "geometry/planar_curve.h"

namespace camdyn {

struct TranslatingRollerCam {
  const MotionLaw* law = nullptr;  ///< not owned; outlives this object
  double base_radius = 0.0;        ///< r_b [m]
  double roller_radius = 0.0;      ///< r_r [m]
  double offset = 0.0;             ///< e [m]
  int direction = +1;              ///< σ: +1 ccw, −1 cw

  /// Lowest roller-centre height y₀ [m].
  double y0() const;

  /// Pitch curve P(u) in the cam frame and its u-derivatives to third order.
  CurvePoint pitch(double u) const;
  /// The pitch curve as the tracked profile (contact/point_curve_tracking.h).
  CurvePoint at(double u) const { return pitch(u); }

  /// Cam contour (inner offset of the pitch curve by r_r) in the cam frame.
  Eigen::Vector2d contour(double u) const;

  /// Pressure angle φ(θ) [rad] of a follower on the law: angle between the
  /// contact normal and the follower axis (+y), signed.
  double pressure_angle(double theta) const;

  /// Signed radius of curvature of the pitch curve at u [m] (> 0 convex).
  double pitch_radius_of_curvature(double u) const;

  /// Outward unit normal of the pitch curve at u, in the cam frame (away from
  /// the cam centre side; the contour is pitch − r_r·normal).
  Eigen::Vector2d pitch_normal(double u) const;

  /// Signed curvature of the pitch curve at u [1/m] (> 0 convex); finite where
  /// the radius of curvature is infinite (straight pieces).
  double pitch_curvature(double u) const;
};

struct CamGeometryReport {
  double max_pressure_angle_deg = 0.0;     ///< max |φ| over the cycle
  double max_pressure_angle_at_deg = 0.0;  ///< cam angle where it occurs
  double min_radius_of_curvature = 0.0;    ///< min |ρ| of the cam contour [m]
  double min_radius_of_curvature_at_deg = 0.0;
  double max_face_offset = 0.0;  ///< flat face: max |contact offset| from the face centre [m] (0 otherwise)
  double max_face_offset_at_deg = 0.0;
};

/// Samples the cam over a full turn (at least `samples` points, refined near
/// extrema) and returns its pressure-angle and curvature figures. Throws
/// InputError naming the cam angle [deg] where the contour has a cusp or
/// undercut (convex pitch radius ≤ r_r) or the geometry is invalid
/// (|e| ≥ r_b + r_r). `file`/`path` go into the error.
CamGeometryReport check_cam(const TranslatingRollerCam& cam, const std::string& file,
                            const std::string& path = "mechanism.cam", int samples = 3600);

}  // namespace camdyn
