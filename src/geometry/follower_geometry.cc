#include "geometry/follower_geometry.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "common/errors.h"
#include "geometry/check_text.h"

namespace camdyn {

namespace {

using check_text::num;

/// The candidate with the larger y of `point(psi)`.
template <class Point>
double higher(double psi_a, double psi_b, const Point& point) {
  return point(psi_a).y() >= point(psi_b).y() ? psi_a : psi_b;
}

}  // namespace

FollowerGeometry make_follower_geometry(const FollowerConfig& config, double rb, const std::string& file,
                                        const std::string& path) {
  FollowerGeometry g;
  g.motion = config.motion;
  g.shape = config.shape.type;
  g.base_radius = rb;
  g.radius = g.circle() ? config.shape.radius : 0.0;
  g.face_width = g.circle() ? 0.0 : config.shape.face_width;
  if (!(rb > 0.0) || !std::isfinite(rb))
    throw InputError(file, "mechanism.cam.base_radius", num(rb) + " m must be > 0");
  if (g.circle() && !(g.radius > 0.0)) throw InputError(file, path + ".shape.radius", num(g.radius) + " m must be > 0");
  if (!g.circle() && !(g.face_width > 0.0))
    throw InputError(file, path + ".shape.face_width", num(g.face_width) + " m must be > 0");

  if (!g.oscillating()) {
    g.offset = config.offset;
    if (g.circle()) {
      const double r = rb + g.radius;
      if (!(std::abs(g.offset) < r))
        throw InputError(file, path + ".offset",
                         "|offset| = " + num(std::abs(g.offset)) + " m must be less than base radius + " +
                             std::string(g.traits().label) + " radius = " + num(r) + " m");
      g.y0 = std::sqrt(r * r - g.offset * g.offset);
    } else {
      g.y0 = rb;
    }
    return g;
  }

  if (config.pivot.size() != 2) throw InputError(file, path + ".pivot", "expected [x, y] of the arm's pivot in m");
  g.pivot = Eigen::Vector2d(config.pivot[0], config.pivot[1]);
  g.arm_length = config.arm_length;
  const double a = g.pivot.norm(), alpha = std::atan2(g.pivot.y(), g.pivot.x());
  const double L = g.arm_length;
  if (!(L > 0.0)) throw InputError(file, path + ".arm_length", num(L) + " m must be > 0");
  if (g.circle()) {
    // |A + L u(ψ)| = r_b + ρ  ⇔  A·u = k.
    const double R = rb + g.radius;
    const double k = (R * R - a * a - L * L) / (2.0 * L);
    if (!(a > 0.0) || !(std::abs(k) < a))
      throw InputError(file, path + ".arm_length",
                       "no lowest position: an arm of " + num(L) + " m from the pivot at distance " + num(a) +
                           " m cannot put the " + to_string(config.shape.type) +
                           " centre at base radius + radius = " + num(R) + " m from the cam centre");
    const double beta = std::acos(k / a);
    auto centre = [&](double psi) {
      return Eigen::Vector2d(g.pivot + L * Eigen::Vector2d(std::cos(psi), std::sin(psi)));
    };
    g.psi0 = higher(alpha + beta, alpha - beta, centre);
    const Eigen::Vector2d u(std::cos(g.psi0), std::sin(g.psi0));
    const double lift_rate = g.pivot.dot(Eigen::Vector2d(-u.y(), u.x()));  // d(A·u)/dψ
    if (std::abs(lift_rate) < 1e-3 * a)
      throw InputError(file, path + ".pivot",
                       "the arm points at the cam centre in its lowest position, so turning it cannot lift the "
                       "follower: move the pivot sideways");
    g.kappa = lift_rate > 0.0 ? 1 : -1;
    return g;
  }
  // Flat face through the pivot, tangent to the base circle at q = 0: |A × d| = r_b with d·A < 0
  // (the tangent point A − (d·A) d lies ahead of the pivot along d).
  if (!(a > rb))
    throw InputError(file, path + ".pivot",
                     "the pivot (distance " + num(a) + " m from the cam centre) must lie outside the base circle (" +
                         num(rb) + " m)");
  const double gamma = std::asin(rb / a);
  auto tangent_point = [&](double psi) {
    const Eigen::Vector2d d(std::cos(psi), std::sin(psi));
    return Eigen::Vector2d(g.pivot - g.pivot.dot(d) * d);
  };
  g.psi0 = higher(alpha + std::numbers::pi - gamma, alpha + std::numbers::pi + gamma, tangent_point);
  const Eigen::Vector2d d(std::cos(g.psi0), std::sin(g.psi0));
  // m = side · J d points from the face towards the cam centre: m·(0 − A) > 0.
  g.face_side = Eigen::Vector2d(-d.y(), d.x()).dot(-g.pivot) > 0.0 ? 1 : -1;
  // Distance of the cam centre from the face, −m·A, grows with q: d(−m·A)/dq = κ side d·A > 0.
  g.kappa = g.face_side * g.pivot.dot(d) > 0.0 ? 1 : -1;
  return g;
}

}  // namespace camdyn
