// Interference tracking of docs/model.md §2 in its general two-parameter form:
// any smooth profile A (the cam, rotating) against any smooth profile B (the
// follower, moving), each a curve in its own body frame. The tracked pair
// (u, v) solves the common-normal equations
//   f1(u, v) = t_A · (r_B − r_A) = 0     (B lies on A's normal line)
//   f2(u, v) = t_A · n_B         = 0     (the normals are parallel)
// with opposing normals n_A · n_B < 0, in world coordinates; the signed gap
// is g = n_A · (r_B − r_A) (> 0 apart, < 0 interference, depth −g). Unlike the
// seed's eqs. 1–4 this holds on both sides of first contact, so (u, v) moves
// continuously through g = 0.
//
// With signed curvatures κ (> 0 convex), parameter speeds λ = |r'| and
// τ = t_A · t_B, the Jacobian is
//   ∂f1/∂u = −λ_A (1 + κ_A g)   ∂f1/∂v = λ_B τ
//   ∂f2/∂u = −κ_A λ_A (n_A·n_B) ∂f2/∂v = κ_B λ_B τ
// and on a solution det = −λ_A λ_B τ (κ_A + κ_B + g κ_A κ_B). A pair is
// tracked only where this relative curvature is positive: it is the circle
// reduction's condition 1 + κ_A (g + ρ) > 0 (a local minimum of the distance
// from B's osculating-circle centre to A), it fails for a flat face on a
// concave flank or a roller larger than a concave flank's radius (two-point
// contact), and it rejects many "far side" solutions of the equations (the
// rest have −g of the order of the bodies' size; see global_profile_pair).
//
// Tracking is (a) warm-started damped Newton from the previous pair, or (b)
// differential: (u̇, v̇) from J·(u̇, v̇) = −∂f/∂t − α f. A global search
// (sampling both parameters, Newton from the best grid cells, the valid pair
// with the smallest gap) initialises the pair and recovers from lost tracking;
// the workspace counts how often that happens. Nothing here allocates except
// building a workspace.
#pragma once

#include <Eigen/Core>
#include <numbers>
#include <vector>

#include "geometry/planar_curve.h"

namespace camdyn {

/// Parameter range of a profile: periodic with period 2π, or the closed interval [lower, upper].
struct ParameterDomain {
  bool periodic = true;
  double lower = 0.0, upper = 2.0 * std::numbers::pi;
};

/// A smooth profile as the pair tracker sees it, in its body frame.
class PairProfile {
 public:
  virtual ~PairProfile() = default;
  /// r(u) and its u-derivatives [m, m/rad, m/rad², m/rad³] (only r, r', r'' are used).
  virtual CurvePoint at(double u) const = 0;
  /// +1 when the outward normal (away from the body's material) is the unit
  /// tangent turned clockwise, n = (t_y, −t_x) — a counterclockwise closed
  /// curve — and −1 when it is the tangent turned counterclockwise.
  virtual int outward_side() const = 0;
  virtual ParameterDomain domain() const = 0;
};

/// +1 if the closed curve runs counterclockwise with its parameter, −1 if
/// clockwise (sign of its enclosed area, from `samples` points).
int closed_curve_orientation(const PeriodicCurve& curve, int samples = 1024);

/// A closed curve (a cam contour, a pitch curve, an ellipse) as a pair
/// profile; the material is inside. The curve must outlive this object.
class ClosedCurveProfile final : public PairProfile {
 public:
  explicit ClosedCurveProfile(const PeriodicCurve& curve) : curve_(&curve), side_(closed_curve_orientation(curve)) {}
  CurvePoint at(double u) const override { return curve_->at(u); }
  int outward_side() const override { return side_; }
  ParameterDomain domain() const override { return {}; }

 private:
  const PeriodicCurve* curve_;
  int side_;
};

/// A profile moved inwards (towards its material) by a distance d along its
/// normal, r_d(u) = r(u) − d n(u): a roller cam's contour from its pitch curve
/// (d = roller radius). Regular where d is below the base profile's smallest
/// convex radius of curvature (the cam checks guarantee it for a roller cam).
/// The base must outlive this object. Gives r, r' and r''; the third
/// derivative would need the base's fourth and is returned as zero (the
/// tracker does not use it).
class InwardOffsetProfile final : public PairProfile {
 public:
  InwardOffsetProfile(const PairProfile& base, double distance) : base_(&base), distance_(distance) {}
  CurvePoint at(double u) const override;
  int outward_side() const override { return base_->outward_side(); }
  ParameterDomain domain() const override { return base_->domain(); }

 private:
  const PairProfile* base_;
  double distance_;
};

/// A circle of radius ρ about `center` (a roller): r(v) = c + ρ (cos v, sin v).
class CircleProfile final : public PairProfile {
 public:
  CircleProfile(double radius, const Eigen::Vector2d& center = Eigen::Vector2d::Zero())
      : radius_(radius), center_(center) {}
  CurvePoint at(double v) const override;
  int outward_side() const override { return +1; }
  ParameterDomain domain() const override { return {}; }
  double radius() const { return radius_; }

 private:
  double radius_;
  Eigen::Vector2d center_;
};

/// An arc of a circle (a mushroom follower's face): r(v) = c + R (cos v, sin v)
/// for v in [begin, end] [rad]; the material is inside the circle.
class ArcProfile final : public PairProfile {
 public:
  ArcProfile(double radius, const Eigen::Vector2d& center, double begin, double end)
      : radius_(radius), center_(center), begin_(begin), end_(end) {}
  CurvePoint at(double v) const override;
  int outward_side() const override { return +1; }
  ParameterDomain domain() const override { return {false, begin_, end_}; }

 private:
  double radius_;
  Eigen::Vector2d center_;
  double begin_, end_;
};

/// A straight segment (a flat follower face): through `center` with outward
/// unit normal `normal`, r(v) = c + v·t with t = normal turned by +90°, for
/// v in [−half_width, half_width] [m].
class SegmentProfile final : public PairProfile {
 public:
  SegmentProfile(const Eigen::Vector2d& center, const Eigen::Vector2d& normal, double half_width)
      : center_(center), tangent_(-normal.y(), normal.x()), half_width_(half_width) {}
  CurvePoint at(double v) const override;
  int outward_side() const override { return +1; }
  ParameterDomain domain() const override { return {false, -half_width_, half_width_}; }

 private:
  Eigen::Vector2d center_, tangent_;
  double half_width_;
};

/// Where a body is and how it moves: x_W = R(angle)·x_B + position.
struct BodyMotion {
  Eigen::Matrix2d rotation = Eigen::Matrix2d::Identity();  ///< R_WB
  Eigen::Vector2d position = Eigen::Vector2d::Zero();      ///< body origin in the world [m]
  double angular_velocity = 0.0;                           ///< ω [rad/s], counterclockwise +
  Eigen::Vector2d velocity = Eigen::Vector2d::Zero();      ///< of the body origin [m/s]

  static BodyMotion make(double angle, const Eigen::Vector2d& position = Eigen::Vector2d::Zero(),
                         double angular_velocity = 0.0, const Eigen::Vector2d& velocity = Eigen::Vector2d::Zero());
};

/// Everything about a candidate pair (u, v) at one instant, world frame.
struct PairEvaluation {
  double u = 0.0, v = 0.0;                             ///< profile parameters [rad or m]
  Eigen::Vector2d f = Eigen::Vector2d::Zero();         ///< (f1 [m], f2 [-])
  Eigen::Matrix2d jacobian = Eigen::Matrix2d::Zero();  ///< ∂f/∂(u, v)
  Eigen::Vector2d f_t = Eigen::Vector2d::Zero();       ///< ∂f/∂t at fixed (u, v) [m/s, 1/s]
  double gap = 0.0;                                    ///< g [m]
  double gap_rate = 0.0;  ///< ∂g/∂t at fixed (u, v) [m/s]; the total dg/dt wherever f = 0
  Eigen::Vector2d point_A_W = Eigen::Vector2d::Zero();   ///< r_A [m]
  Eigen::Vector2d point_B_W = Eigen::Vector2d::Zero();   ///< r_B [m]
  Eigen::Vector2d point_W = Eigen::Vector2d::Zero();     ///< contact point: midway between r_A and r_B [m]
  Eigen::Vector2d normal_W = Eigen::Vector2d::Zero();    ///< n_A, unit, from A towards B when apart
  Eigen::Vector2d tangent_W = Eigen::Vector2d::Zero();   ///< t_A, unit
  Eigen::Vector2d normal_B_W = Eigen::Vector2d::Zero();  ///< n_B, unit
  double normal_velocity = 0.0;      ///< n_A · (ṙ_B − ṙ_A) of the material points [m/s] (> 0 separating)
  double tangential_velocity = 0.0;  ///< t_A · (ṙ_B − ṙ_A), the slip velocity [m/s]
  double curvature_A = 0.0, curvature_B = 0.0;  ///< signed, > 0 convex [1/m]
  double relative_curvature = 0.0;              ///< κ_A + κ_B + g κ_A κ_B [1/m]

  /// Opposing normals and positive relative curvature: a pair worth tracking.
  bool valid() const { return normal_W.dot(normal_B_W) < 0.0 && relative_curvature > 0.0; }
};

/// Evaluates the pair (u, v) for the two profiles in their current motion.
PairEvaluation evaluate_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                                     const BodyMotion& motion_b, double u, double v);

/// Why a Newton solve or a rate computation ended.
enum class PairStatus {
  converged,      ///< f = 0 to tolerance, valid pair, inside both domains
  not_converged,  ///< iteration limit reached
  singular,       ///< Jacobian (nearly) singular: conformal contact or a lost pair
  invalid,        ///< converged to a pair with equal-facing normals or negative relative curvature
  out_of_domain,  ///< the pair left an open profile's parameter range
};

const char* to_string(PairStatus status);

struct PairNewtonOptions {
  int max_iterations = 8;         ///< 2–3 are typical from a warm start
  double step_tolerance = 1e-12;  ///< stop when |Δu|, |Δv| fall below this × (1 + |u|), ... [rad or m]
  double max_step = 0.5;          ///< largest accepted change of u or v per iteration [rad or m]
  int max_halvings = 6;           ///< damping: halve a step that does not reduce |f|
};

/// Damped Newton on f(u, v) = 0 from (u, v); on return (u, v) and `pair` hold
/// the last iterate. The merit is f1² + (λ_A f2)², λ_A = |r_A'| at the start.
PairStatus newton_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                               const BodyMotion& motion_b, double& u, double& v, PairEvaluation& pair,
                               const PairNewtonOptions& options = {});

/// Differential tracking: (u̇, v̇) from J·(u̇, v̇) = −∂f/∂t − α f with α [1/s]
/// the drift-correction rate; `pair` must be evaluate_profile_pair at (u, v).
/// Returns singular (rates zeroed) when J cannot be solved.
PairStatus profile_pair_rates(const PairEvaluation& pair, double alpha, double& u_dot, double& v_dot);

/// Sampling resolution of the global search.
struct PairSearchOptions {
  int samples_a = 256;  ///< over one period (or the domain) of A
  int samples_b = 64;   ///< of B
  int candidates = 12;  ///< grid cells refined by Newton
};

/// Scratch space and counters for one pair of profiles: build once (it
/// allocates), reuse for every call. Holds the body-frame samples of both
/// profiles, so it belongs to one (A, B).
struct PairTrackerWorkspace {
  PairTrackerWorkspace(const PairProfile& a, const PairProfile& b, const PairSearchOptions& options = {});

  PairSearchOptions options;
  std::vector<double> a_offset, b_offset;        ///< sample parameters relative to the domain start / reference
  std::vector<CurvePoint> a_samples, b_samples;  ///< body frame, at the reference-free sample parameters
  std::vector<double> merit;                     ///< samples_a × samples_b grid
  std::vector<int> candidate_cells;              ///< best cells, size options.candidates

  long global_searches = 0;  ///< calls of global_profile_pair
  long newton_failures = 0;  ///< warm-started Newton solves that failed in track_profile_pair
};

/// Global initialisation: samples A over [u_ref − π, u_ref + π) (periodic) or
/// its domain, B likewise around v_ref, refines the best grid cells by Newton
/// and keeps the valid pair with the smallest |g|: the closest approach when
/// apart, the local interference when in contact. (The equations also have
/// "far side" solutions, e.g. a roller's top against the cam's opposite
/// flank, with −g of the order of the bodies' size, which the relative
/// curvature does not always exclude; a compliant contact's depth is far
/// smaller.) Periodic parameters stay on the branch nearest the references
/// (so an unwrapped u keeps following the cam angle).
/// Returns false if no valid pair was found. Counts in ws.global_searches.
bool global_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                         const BodyMotion& motion_b, double u_ref, double v_ref, PairTrackerWorkspace& ws, double& u,
                         double& v, PairEvaluation& pair);

/// Warm-started Newton from (u, v); on failure one global search (counted as
/// a reset). Returns false if both fail (then (u, v) are unchanged).
bool track_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                        const BodyMotion& motion_b, PairTrackerWorkspace& ws, double& u, double& v,
                        PairEvaluation& pair, const PairNewtonOptions& options = {});

}  // namespace camdyn
