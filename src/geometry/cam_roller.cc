#include "geometry/cam_roller.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/check_text.h"
#include "geometry/extremum.h"
#include "geometry/vec2.h"

namespace camdyn {

using geometry_detail::Extremum;
using geometry_detail::refine_max;

namespace {

/// J·v: v turned by +90°.

Eigen::Matrix2d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

using check_text::num;
using check_text::sibling;
using check_text::to_deg_0_360;

}  // namespace

double TranslatingRollerCam::y0() const {
  const double r = base_radius + roller_radius;
  return std::sqrt(r * r - offset * offset);
}

CurvePoint TranslatingRollerCam::pitch(double u) const {
  assert(law != nullptr && (direction == 1 || direction == -1));
  const LawSample l = law->eval(u);
  const double sg = direction;
  // Follower-frame roller centre q(u) = (e, y₀ + s) and its u-derivatives.
  const Eigen::Vector2d q(offset, y0() + l.s), q1(0.0, l.ds), q2(0.0, l.d2s), q3(0.0, l.d3s);
  // P = R(−σu)·q with dR(−σu)/du = −σ R J (J = +90° turn, J² = −I), so
  // P^(k) = R (d/du − σJ)^k q, expanded:
  const Eigen::Matrix2d rot = rotation(-sg * u);
  CurvePoint p;
  p.r = rot * q;
  p.dr = rot * (q1 - sg * perp(q));
  p.d2r = rot * (q2 - 2.0 * sg * perp(q1) - q);
  p.d3r = rot * (q3 - 3.0 * sg * perp(q2) - 3.0 * q1 + sg * perp(q));
  return p;
}

Eigen::Vector2d TranslatingRollerCam::pitch_normal(double u) const {
  // The pitch curve runs clockwise for σ = +1 (counterclockwise for σ = −1), so
  // the outward normal is σ·J·tangent; check_cam ensures the curve is
  // star-shaped around the cam centre, which makes this point away from it.
  const Eigen::Vector2d d = pitch(u).dr;
  return static_cast<double>(direction) * perp(d) / d.norm();
}

Eigen::Vector2d TranslatingRollerCam::contour(double u) const { return pitch(u).r - roller_radius * pitch_normal(u); }

double TranslatingRollerCam::pressure_angle(double theta) const {
  // World frame: the cam-fixed normal turned by the cam rotation R(σθ). The
  // angle is measured from +y towards −x, so that for σ = +1 it is
  // atan((s' − e)/(y₀ + s)) (generally σ·atan((s' − σe)/(y₀ + s))).
  const Eigen::Vector2d n_W = rotation(direction * theta) * pitch_normal(theta);
  return std::atan2(-n_W.x(), n_W.y());
}

double TranslatingRollerCam::pitch_curvature(double u) const {
  const CurvePoint p = pitch(u);
  // P'×P'' < 0 on a convex clockwise curve; −σ makes convex positive either way.
  return -direction * cross(p.dr, p.d2r) / std::pow(p.dr.norm(), 3);
}

double TranslatingRollerCam::pitch_radius_of_curvature(double u) const {
  const double kappa = pitch_curvature(u);
  return kappa == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / kappa;
}

CamGeometryReport check_cam(const TranslatingRollerCam& cam, const std::string& file, const std::string& path,
                            int samples) {
  assert(cam.law != nullptr);
  const double rb = cam.base_radius, rr = cam.roller_radius, e = cam.offset;
  if (!(rb > 0.0) || !std::isfinite(rb)) throw InputError(file, path + ".base_radius", num(rb) + " m must be > 0");
  if (!(rr > 0.0) || !std::isfinite(rr))
    throw InputError(file, sibling(path, "follower.shape.radius"), num(rr) + " m must be > 0");
  if (!std::isfinite(e) || std::abs(e) >= rb + rr)
    throw InputError(
        file, sibling(path, "follower.offset"),
        "|offset| = " + num(std::abs(e)) + " m must be less than base radius + roller radius = " + num(rb + rr) + " m");
  if (cam.direction != 1 && cam.direction != -1)
    throw InputError(file, path + ".direction", "must be +1 (ccw) or -1 (cw)");

  // Sample angles: a uniform grid plus a few points inside every law piece, so
  // that short, sharp segments are never stepped over.
  const int n_uniform = std::max(samples, 360);
  std::vector<double> us;
  for (int i = 0; i < n_uniform; ++i) us.push_back(kTwoPi * i / n_uniform);
  for (const auto& piece : cam.law->pieces()) {
    constexpr int kPerPiece = 16;
    for (int k = 0; k < kPerPiece; ++k) us.push_back(piece.start + (piece.end - piece.start) * (k + 0.5) / kPerPiece);
  }
  std::sort(us.begin(), us.end());

  const double sg = cam.direction;
  // Star-shapedness: the polar angle of P turns one way only, i.e. its rate
  // −σ·(P × P')/|P|² stays > 0; neg_star is its negative, to be maximised.
  auto neg_star = [&](double u) {
    const CurvePoint p = cam.pitch(u);
    return sg * cross(p.r, p.dr) / p.r.squaredNorm();
  };
  auto abs_phi = [&](double u) { return std::abs(cam.pressure_angle(u)); };
  auto kappa = [&](double u) { return cam.pitch_curvature(u); };
  // −|ρ_contour| with ρ_contour = ρ_pitch − r_r, to be maximised; a straight
  // piece of pitch curve (κ = 0) has infinite radius.
  auto neg_abs_rho = [&](double u) {
    const double k = cam.pitch_curvature(u);
    return k == 0.0 ? -std::numeric_limits<double>::infinity() : -std::abs(1.0 / k - rr);
  };

  std::vector<double> v_star, v_phi, v_kappa, v_rho;
  for (const double u : us) {
    v_star.push_back(neg_star(u));
    v_phi.push_back(abs_phi(u));
    v_kappa.push_back(kappa(u));
    v_rho.push_back(neg_abs_rho(u));
  }
  const auto at = [](double u) { return " at cam angle " + num(to_deg_0_360(u)) + "°"; };

  const Extremum worst_star = refine_max(neg_star, us, v_star);
  if (worst_star.value >= 0.0)
    throw InputError(file, path,
                     "the pitch curve turns back about the cam centre" + at(worst_star.u) +
                         " (offset too large for the law's velocity): the cam cannot be made");
  const Extremum worst_kappa = refine_max(kappa, us, v_kappa);
  if (worst_kappa.value * rr >= 1.0)
    throw InputError(file, path,
                     "the pitch curve's radius of curvature " + num(1.0 / worst_kappa.value) +
                         " m is not larger than the roller radius " + num(rr) + " m" + at(worst_kappa.u) +
                         ": the cam contour has a cusp or undercut (use a larger base radius, a "
                         "smaller roller or a gentler law)");

  const Extremum phi = refine_max(abs_phi, us, v_phi);
  const Extremum rho = refine_max(neg_abs_rho, us, v_rho);
  CamGeometryReport report;
  report.max_pressure_angle_deg = phi.value * (180.0 / std::numbers::pi);
  report.max_pressure_angle_at_deg = to_deg_0_360(phi.u);
  report.min_radius_of_curvature = -rho.value;
  report.min_radius_of_curvature_at_deg = to_deg_0_360(rho.u);
  return report;
}

}  // namespace camdyn
