// Interference tracking of docs/model.md §2 in its one-parameter form for a
// circle follower (roller, mushroom): the circle's centre c against a smooth
// cam-frame profile P(u) (any PeriodicCurve-like type with `at(u)`), whose
// distance to c minus an offset radius ρ is the gap. For a cam synthesised
// from the law P is the centre (pitch) curve and ρ = 0; for a cam given as a
// contour P is the contour and ρ the circle's radius. The common-normal
// condition becomes
//   f(u) = P'(u) · (c − P(u)) = 0,   with  f_u = P''·(c − P) − |P'|² < 0
// at a local minimum of distance (or maximum of interference depth), and the
// signed gap is g = n(u) · (c − P(u)) − ρ with n the outward unit normal. The
// pair is tracked from the previous instant without a global search: either
// by warm-started Newton on f, or differentially (u̇ from ḟ = −α f). A global
// sampled search initialises the pair and recovers when tracking is lost.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "common/constants.h"
#include "geometry/planar_curve.h"

namespace camdyn {

/// The tracked pair at one instant (all in the profile's frame).
struct TrackedPair {
  double u = 0.0;             ///< profile parameter of the pair [rad]
  double gap = 0.0;           ///< g [m]: > 0 apart, < 0 interference (δ = −g)
  double f = 0.0;             ///< common-normal residual f(u) [m²/rad]
  double f_u = 0.0;           ///< ∂f/∂u [m²/rad²]
  Eigen::Vector2d point;      ///< P(u) [m]
  Eigen::Vector2d tangent_u;  ///< P'(u) [m/rad]
  Eigen::Vector2d normal;     ///< outward unit normal at u [-]
};

/// Outward unit normal of a profile that is star-shaped about its frame's
/// origin (check_cam guarantees it for cams): the unit normal pointing away
/// from the origin, whichever way the parameter runs (n·r has the sign of r × r').
inline Eigen::Vector2d outward_normal(const Eigen::Vector2d& r, const Eigen::Vector2d& dr) {
  const Eigen::Vector2d n = Eigen::Vector2d(dr.y(), -dr.x()).normalized();
  return n.dot(r) >= 0.0 ? n : Eigen::Vector2d(-n);
}

/// Evaluates the pair quantities at parameter u for point c (offset radius ρ).
template <class Profile>
TrackedPair evaluate_pair(const Profile& profile, const Eigen::Vector2d& c, double u, double offset_radius = 0.0) {
  const CurvePoint p = profile.at(u);
  TrackedPair pair;
  pair.u = u;
  pair.point = p.r;
  pair.tangent_u = p.dr;
  const Eigen::Vector2d d = c - p.r;
  pair.f = p.dr.dot(d);
  pair.f_u = p.d2r.dot(d) - p.dr.squaredNorm();
  pair.normal = outward_normal(p.r, p.dr);
  pair.gap = pair.normal.dot(d) - offset_radius;
  return pair;
}

/// Warm-started Newton on f(u) = 0 from u. Returns false when it does not
/// converge in `max_iterations`, when f_u ≥ 0 (not a distance minimum: the
/// pair is lost) or when the step exceeds `max_step` [rad].
template <class Profile>
bool newton_track(const Profile& profile, const Eigen::Vector2d& c, double& u, TrackedPair& pair,
                  double offset_radius = 0.0, int max_iterations = 8, double tolerance_u = 1e-13,
                  double max_step = 0.5) {
  double x = u;
  for (int it = 0; it < max_iterations; ++it) {
    pair = evaluate_pair(profile, c, x, offset_radius);
    if (!(pair.f_u < 0.0)) return false;
    const double step = -pair.f / pair.f_u;
    if (!std::isfinite(step) || std::abs(step) > max_step) return false;
    x += step;
    if (std::abs(step) <= tolerance_u * (1.0 + std::abs(x))) {
      pair = evaluate_pair(profile, c, x, offset_radius);
      u = x;
      return pair.f_u < 0.0;
    }
  }
  return false;
}

/// Global initialisation: samples the closed profile at `samples` points over
/// one period [u_ref − π, u_ref + π), keeps the sample with the smallest signed
/// gap among those where the normal faces c, and refines it by Newton. The
/// result stays on the branch nearest u_ref (so an unwrapped u keeps tracking
/// the cam angle across revolutions). Returns false if no valid pair exists.
template <class Profile>
bool global_pair(const Profile& profile, const Eigen::Vector2d& c, double u_ref, double& u, TrackedPair& pair,
                 double offset_radius = 0.0, int samples = 720) {
  double best_u = u_ref, best_distance = INFINITY;
  for (int i = 0; i < samples; ++i) {
    const double x = u_ref - kTwoPi / 2 + kTwoPi * i / samples;
    const CurvePoint p = profile.at(x);
    const double distance = (c - p.r).norm();
    if (distance < best_distance) {
      best_distance = distance;
      best_u = x;
    }
  }
  double x = best_u;
  if (!newton_track(profile, c, x, pair, offset_radius, 50, 1e-13, kTwoPi / samples * 4)) return false;
  u = x;
  return true;
}

}  // namespace camdyn
