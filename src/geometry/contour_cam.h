// Contour cams (issue 4, item 3): a cam given directly as a closed list of
// points in its own frame (measured, or exported from CAD), fitted with a
// smooth periodic B-spline curve; the fit's residuals and the curvature
// analysis a follower needs (concave portions, smallest radius of curvature);
// and the rigid-follower lift of a translating roller, mushroom or flat face
// on such a cam, from which the kinematic law s(θ) of a contour cam follows.
//
// Fit: a least-squares *regression* spline (fewer control points than points)
// rather than an interpolating one, because measured points carry noise and an
// interpolant passes through every error, turning it into curvature wiggles
// that look like concave flanks. Parameters start from chord length (Piegl &
// Tiller, *The NURBS Book*, §9.2.1, scaled to a period of 2π) and are then
// corrected by projecting every point on the current curve and refitting
// (Hoschek 1988, "intrinsic parametrization"), so that the residuals minimised
// are the orthogonal distances from the points to the curve. An optional
// third-difference penalty on the control points (P-splines, Eilers & Marx
// 1996) smooths rough data further.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <string>
#include <vector>

#include "geometry/planar_curve.h"
#include "scene/follower_shape.h"

namespace camdyn {

/// Fewest points a contour may have.
inline constexpr int kMinContourPoints = 8;

/// How the contour is fitted (`mechanism.cam.motion_law.contour.*` besides `points`).
struct ContourFitOptions {
  int degree = 5;                 ///< p, polynomial degree of the spline, in [3, kMaxSplineDegree]
  int control_points = 0;         ///< m, per coordinate; 0 = automatic: N/2 within [2(p + 1), 400], at most N
  double smoothing = 0.0;         ///< λ ≥ 0, weight of the third-difference penalty relative to the
                                  ///< data term (traces of the normal matrices); 0 = plain least squares
  int parameter_corrections = 4;  ///< projection / refit rounds after the chord-length fit, ≥ 0
};

/// A portion of the contour where it is concave (signed curvature < 0).
struct ConcavePortion {
  double u_begin = 0.0, u_end = 0.0;  ///< curve parameter [rad], u_begin in [0, 2π) < u_end (may exceed 2π)
  double angle_begin_deg = 0.0, angle_end_deg = 0.0;  ///< polar angle in the cam frame [deg, 0..360)
  int point_begin = 0, point_end = 0;                 ///< nearest input points (indices into the given list)
  double min_abs_radius = 0.0;                        ///< smallest |ρ| inside the portion [m]
  double min_abs_radius_angle_deg = 0.0;              ///< polar angle where it occurs [deg]
};

/// What the fit achieved and what the contour looks like.
struct ContourFitReport {
  int points = 0;              ///< N, after dropping a repeated closing point
  int degree = 0;              ///< p
  int control_points = 0;      ///< m
  double rms_residual = 0.0;   ///< sqrt(mean of squared point-to-curve distances) [m]
  double max_residual = 0.0;   ///< largest point-to-curve distance [m]
  int max_residual_point = 0;  ///< index of that point
  double min_radius_of_curvature = std::numeric_limits<double>::infinity();  ///< smallest |ρ| [m]
  double min_radius_of_curvature_angle_deg = 0.0;                            ///< where [deg]
  double min_convex_radius = std::numeric_limits<double>::infinity();        ///< smallest ρ where convex [m]
  double min_convex_radius_angle_deg = 0.0;                                  ///< where [deg]
  std::vector<ConcavePortion> concave;                                       ///< empty for a convex cam
};

/// The fitted contour: a closed C^{p−1} curve r(u), u periodic in 2π (u is
/// the corrected chord-length parameter, not the polar angle). Immutable;
/// at() allocates nothing.
class ContourCam final : public PeriodicCurve {
 public:
  /// Validates and fits `points` [m] (cam frame at cam angle 0, in order
  /// around the cam, either sense). A last point repeating the first closes
  /// the list and is dropped. Requirements (InputError(file, path + ".points",
  /// reason naming the point index and polar angle)): at least
  /// kMinContourPoints points, all finite, no point repeating its predecessor,
  /// and the list star-shaped about the cam centre: the polar angle turns
  /// strictly one way, once around (this rules out the obvious
  /// self-intersections and a centre outside the cam). The fitted curve must
  /// be star-shaped too. Bad options give InputError at path + ".degree" etc.
  /// `path` is the dotted path of the contour object.
  static ContourCam fit(const std::vector<Eigen::Vector2d>& points, const ContourFitOptions& options,
                        const std::string& file, const std::string& path = "mechanism.cam.motion_law.contour");

  /// r(u) and its first three u-derivatives in the cam frame [m, m/rad, ...].
  CurvePoint at(double u) const override;

  /// +1 when the curve runs counterclockwise with u, −1 clockwise.
  int orientation() const { return orientation_; }

  /// Signed curvature κ(u) [1/m]: > 0 convex, < 0 concave (seen from outside).
  double curvature(double u) const;

  /// Outward unit normal at u (away from the cam material).
  Eigen::Vector2d outward_normal(double u) const;

  /// Parameter of the foot point of input point i on the curve [rad].
  double point_parameter(int i) const { return parameters_[i]; }
  const std::vector<Eigen::Vector2d>& points() const { return points_; }

  const ContourFitReport& report() const { return report_; }

  int degree() const { return degree_; }
  const std::vector<Eigen::Vector2d>& control_points() const { return coefficients_; }

 private:
  ContourCam() = default;

  int degree_ = 0;
  int m_ = 0;                                  ///< control points per period
  std::vector<double> knots_;                  ///< unwrapped uniform knots, m + 2p + 1, domain [0, 2π)
  std::vector<Eigen::Vector2d> coefficients_;  ///< m control points; index i is used as i mod m
  int orientation_ = 1;
  std::vector<Eigen::Vector2d> points_;  ///< the input points (closing duplicate dropped)
  std::vector<double> parameters_;       ///< foot-point parameter of each point [rad]
  ContourFitReport report_;
};

/// Throws InputError(file, path + ".points", reason naming the polar angle and
/// the nearest point) when the follower cannot follow the fitted contour:
/// a flat face (`follower` = line) any concave portion (it would bridge it); a
/// roller or mushroom (circle) of radius `radius` [m] any concave portion with |ρ| < radius (its centre
/// path would have a cusp: two-point contact). Convex portions need nothing
/// (a smooth fit has no corners), but a convex radius of curvature below
/// `min_convex_radius` [m] (default 0 = unchecked) is reported the same way,
/// since it points at a corner in the data that the fit rounded off.
void check_contour_for_follower(const ContourCam& cam, FollowerContact follower, double radius, const std::string& file,
                                const std::string& path = "mechanism.cam.motion_law.contour",
                                double min_convex_radius = 0.0);

/// The rigid lift of a translating follower on a curve at one cam angle.
struct RigidLift {
  double y = 0.0;                                       ///< height of the follower reference above the cam centre [m]:
                                                        ///< the roller (mushroom arc) centre, or the flat face
  double dy = 0.0;                                      ///< dy/dθ [m/rad]
  double d2y = 0.0;                                     ///< d²y/dθ² [m/rad²]
  double u = 0.0;                                       ///< contour parameter of the contact point [rad]
  Eigen::Vector2d contact_W = Eigen::Vector2d::Zero();  ///< contact point in the world frame [m]
};

/// Rigid (no compliance, always in contact) follower on a closed curve: the
/// follower moves along +y on the line x = offset, the cam turns about the
/// origin, a cam-fixed point p is at R(σθ)·p (docs/model.md §1 frame). For a
/// roller or mushroom (radius ρ, centre on the axis) the centre height is
/// y(θ) = max over u of [q_y + sqrt(ρ² − (q_x − e)²)], q = R(σθ)·r(u), over the
/// points within ρ of the axis; for a flat face (perpendicular to the axis)
/// y(θ) = max over u of q_y. The maximum is found globally (sampling the
/// curve) and refined by Newton on ∂Y/∂u = 0; dy/dθ follows from the envelope
/// theorem and d²y/dθ² from implicit differentiation, both exact for the curve.
/// The kinematic law of a contour cam is s(θ) = y(θ) − lowest().
class RigidFollowerLift {
 public:
  /// `curve` must outlive this object. `radius` ρ [m] > 0 for a circle
  /// `follower` (roller, mushroom; ignored for a line, the flat face),
  /// `offset` e [m], `direction` σ = ±1, `samples` of the curve for the global
  /// search. Throws InputError(file, offset_path) when a roller/mushroom on
  /// that axis misses the cam at some angle.
  RigidFollowerLift(const PeriodicCurve& curve, FollowerContact follower, double radius, double offset, int direction,
                    int samples = 2048, const std::string& file = "",
                    const std::string& offset_path = "mechanism.follower.offset");

  /// y, dy/dθ, d²y/dθ² at cam angle θ [rad]. Allocates nothing.
  RigidLift at(double theta) const;

  /// Lowest follower height over a turn, min over θ of y(θ) [m], and where [rad].
  double lowest() const { return lowest_; }
  double lowest_angle() const { return lowest_angle_; }

  /// s(θ) = y(θ) − lowest() [m].
  double displacement(double theta) const { return at(theta).y - lowest_; }

 private:
  const PeriodicCurve* curve_;
  FollowerContact follower_;
  double radius_, offset_;
  int direction_;
  std::vector<double> sample_u_;
  std::vector<Eigen::Vector2d> sample_r_;
  double lowest_ = 0.0, lowest_angle_ = 0.0;
};

}  // namespace camdyn
