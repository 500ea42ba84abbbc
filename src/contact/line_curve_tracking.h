// Interference tracking of docs/model.md §2 for a flat face: a straight line
// (point p on it, unit normal m pointing from the face towards the cam, both
// in the profile's frame) against a smooth cam-frame profile r(u) (any type
// with `at(u)`). A line has no curvature, so the pair reduces to the one
// parameter u of the profile point that reaches furthest towards the face:
// the common-normal condition n(u) ∥ −m is
//   f(u) = −r'(u) · m = 0,   with  f_u = −r''(u) · m < 0
// at the support point (a minimum of m·(r − p), the deepest point on a convex
// profile), and the signed gap is g = m · (r(u) − p) (> 0 apart). The sign of
// f is chosen so that f_u < 0 as in the circle reduction
// (point_curve_tracking.h), which shares TrackedPair and the tracking loop.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "common/constants.h"
#include "contact/point_curve_tracking.h"
#include "geometry/planar_curve.h"

namespace camdyn {

/// Evaluates the pair quantities at parameter u for the face line (p, m).
template <class Profile>
TrackedPair evaluate_line_pair(const Profile& profile, const Eigen::Vector2d& p, const Eigen::Vector2d& m, double u) {
  const CurvePoint c = profile.at(u);
  TrackedPair pair;
  pair.u = u;
  pair.point = c.r;
  pair.tangent_u = c.dr;
  pair.f = -c.dr.dot(m);
  pair.f_u = -c.d2r.dot(m);
  pair.normal = outward_normal(c.r, c.dr);
  pair.gap = m.dot(c.r - p);
  return pair;
}

/// Warm-started Newton on f(u) = 0 from u; false when it does not converge,
/// f_u ≥ 0 (not a support point: the pair is lost) or a step exceeds max_step [rad].
template <class Profile>
bool newton_track_line(const Profile& profile, const Eigen::Vector2d& p, const Eigen::Vector2d& m, double& u,
                       TrackedPair& pair, int max_iterations = 8, double tolerance_u = 1e-13, double max_step = 0.5) {
  double x = u;
  for (int it = 0; it < max_iterations; ++it) {
    pair = evaluate_line_pair(profile, p, m, x);
    if (!(pair.f_u < 0.0)) return false;
    const double step = -pair.f / pair.f_u;
    if (!std::isfinite(step) || std::abs(step) > max_step) return false;
    x += step;
    if (std::abs(step) <= tolerance_u * (1.0 + std::abs(x))) {
      pair = evaluate_line_pair(profile, p, m, x);
      u = x;
      return pair.f_u < 0.0;
    }
  }
  return false;
}

/// Global initialisation: the sample of [u_ref − π, u_ref + π) reaching
/// furthest towards the face (smallest m·r), refined by Newton; stays on the
/// branch nearest u_ref. False if no valid pair exists.
template <class Profile>
bool global_line_pair(const Profile& profile, const Eigen::Vector2d& p, const Eigen::Vector2d& m, double u_ref,
                      double& u, TrackedPair& pair, int samples = 720) {
  double best_u = u_ref, best = INFINITY;
  for (int i = 0; i < samples; ++i) {
    const double x = u_ref - kTwoPi / 2 + kTwoPi * i / samples;
    const double reach = m.dot(profile.at(x).r);
    if (reach < best) {
      best = reach;
      best_u = x;
    }
  }
  double x = best_u;
  if (!newton_track_line(profile, p, m, x, pair, 50, 1e-13, kTwoPi / samples * 4)) return false;
  u = x;
  return true;
}

}  // namespace camdyn
