// The rigid follower of a scene, computed in the tests independently of the
// library: the generalised force the cam must supply on the law, and the lever
// ∂g/∂q that turns it into a normal force, from the follower's geometry by
// finite differences (pitch-curve tangent; the envelope point of neighbouring
// face lines). For a ccw cam.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "geometry/motion_law.h"
#include "io/config.h"

namespace camdyn::test {

inline constexpr double kRigidTwoPi = 2 * std::numbers::pi;

inline Eigen::Vector2d rot(const Eigen::Vector2d& v, double a) {
  return {std::cos(a) * v.x() - std::sin(a) * v.y(), std::sin(a) * v.x() + std::cos(a) * v.y()};
}
inline Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }
inline Eigen::Vector2d unit(double a) { return {std::cos(a), std::sin(a)}; }

/// Root of h on [a, b] by bisection (h(a), h(b) of opposite signs).
template <class H>
double bisect(const H& h, double a, double b) {
  double ha = h(a);
  for (int i = 0; i < 200; ++i) {
    const double m = 0.5 * (a + b), hm = h(m);
    if ((hm < 0) == (ha < 0))
      a = m, ha = hm;
    else
      b = m;
  }
  return 0.5 * (a + b);
}

/// The rigid follower of a scene (ccw cam), from its config alone.
struct Rigid {
  SceneConfig scene;
  MotionLaw law;
  bool oscillating = false, flat = false;
  double rb = 0, rho = 0, e = 0, L = 0, psi0 = 0, kappa = 1;
  Eigen::Vector2d A = Eigen::Vector2d::Zero();

  explicit Rigid(const SceneConfig& s) : scene(s), law(build_motion_law(s.mechanism.cam.motion_law, "test")) {
    const FollowerConfig& f = s.mechanism.follower;
    oscillating = f.motion == FollowerMotion::oscillating;
    flat = f.shape.type == FollowerShape::flat;
    rb = s.mechanism.cam.base_radius;
    rho = flat ? 0.0 : f.shape.radius;
    e = f.offset;
    if (!oscillating) return;
    A = {f.pivot[0], f.pivot[1]};
    L = f.arm_length;
    // Lowest position by a scan over the arm angle: the circle centre at r_b + ρ
    // from the cam centre, or the face line (through A) at distance r_b with its
    // tangent point ahead of the pivot; of the solutions, the higher one.
    auto residual = [&](double psi) {
      if (!flat) return (A + L * unit(psi)).norm() - (rb + rho);
      return std::abs(A.x() * std::sin(psi) - A.y() * std::cos(psi)) - rb;
    };
    auto point = [&](double psi) -> Eigen::Vector2d {
      return flat ? Eigen::Vector2d(A - A.dot(unit(psi)) * unit(psi)) : Eigen::Vector2d(A + L * unit(psi));
    };
    double best_y = -INFINITY;
    const int n = 3600;
    for (int i = 0; i < n; ++i) {
      const double a = kRigidTwoPi * i / n, b = kRigidTwoPi * (i + 1) / n;
      if ((residual(a) < 0) == (residual(b) < 0)) continue;
      const double psi = bisect(residual, a, b);
      if (flat && A.dot(unit(psi)) >= 0) continue;
      if (point(psi).y() > best_y) best_y = point(psi).y(), psi0 = psi;
    }
    // κ: the sign of rotation that moves the follower away from the cam
    // (its distance from the cam centre grows).
    auto distance = [&](double p) {
      return flat ? std::abs(A.x() * std::sin(p) - A.y() * std::cos(p)) : (A + L * unit(p)).norm();
    };
    kappa = distance(psi0 + 1e-6) > distance(psi0 - 1e-6) ? 1.0 : -1.0;
  }

  double psi(double theta) const { return psi0 + kappa * law.eval(theta).s; }

  /// World contact normal on the follower and ∂g/∂q at cam angle θ (follower on the law).
  double lever(double theta) const {
    const double h = 1e-5;
    if (!oscillating && flat) return 1.0;
    if (!oscillating) {
      const LawSample s = law.eval(theta);
      const double y0 = std::sqrt((rb + rho) * (rb + rho) - e * e);
      return std::cos(std::atan((s.ds - e) / (y0 + s.s)));
    }
    if (!flat) {
      // Pitch curve P(θ) = R(−θ) c(θ); its outward normal turned back into the world.
      auto pitch = [&](double th) { return rot(A + L * unit(psi(th)), -th); };
      const Eigen::Vector2d tangent = (pitch(theta + h) - pitch(theta - h)) / (2 * h);
      Eigen::Vector2d n = perp(tangent).normalized();
      if (n.dot(pitch(theta)) < 0) n = -n;
      const Eigen::Vector2d n_world = rot(n, theta);
      return n_world.dot(kappa * L * perp(unit(psi(theta))));
    }
    // Flat: the envelope point is where the face lines at θ ± h (cam frame) meet;
    // the normal force's lever about the pivot is its distance along the face.
    auto line = [&](double th, Eigen::Vector2d& p, Eigen::Vector2d& d) {
      p = rot(A, -th);
      d = rot(unit(psi(th)), -th);
    };
    Eigen::Vector2d p1, d1, p2, d2;
    line(theta - h, p1, d1);
    line(theta + h, p2, d2);
    // p1 + a d1 = p2 + b d2.
    Eigen::Matrix2d m;
    m << d1.x(), -d2.x(), d1.y(), -d2.y();
    const Eigen::Vector2d ab = m.inverse() * (p2 - p1);
    const Eigen::Vector2d contact = rot(p1 + ab(0) * d1, theta);
    return (contact - A).dot(unit(psi(theta)));
  }

  /// Generalised force the cam must supply on q (frictionless), and its normal force.
  double generalised(double theta, double omega) const {
    const FollowerConfig& f = scene.mechanism.follower;
    const LawSample s = law.eval(theta);
    const double inertia = oscillating ? f.inertia : f.mass;
    return inertia * omega * omega * s.d2s + f.damping * omega * s.ds + f.spring.stiffness * s.s + f.spring.preload +
           (oscillating ? 0.0 : f.mass * scene.gravity);
  }
  double force(double theta, double omega) const { return generalised(theta, omega) / lever(theta); }

  double jump_rpm() const {
    const FollowerConfig& f = scene.mechanism.follower;
    const double inertia = oscillating ? f.inertia : f.mass;
    double best = INFINITY;
    for (int i = 0; i < 36000; ++i) {
      const LawSample s = law.eval(kRigidTwoPi * i / 36000);
      if (s.d2s < 0)
        best = std::min(best, std::sqrt((f.spring.stiffness * s.s + f.spring.preload) / (-inertia * s.d2s)));
    }
    return best * 60 / kRigidTwoPi;
  }
};

}  // namespace camdyn::test
