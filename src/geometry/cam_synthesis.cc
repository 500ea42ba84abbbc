#include "geometry/cam_synthesis.h"

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

/// A function of θ and its first three θ-derivatives (truncated Taylor arithmetic).
struct Jet {
  double v = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;
};
Jet operator+(const Jet& a, const Jet& b) { return {a.v + b.v, a.d1 + b.d1, a.d2 + b.d2, a.d3 + b.d3}; }
Jet operator*(double k, const Jet& a) { return {k * a.v, k * a.d1, k * a.d2, k * a.d3}; }
Jet operator+(double k, const Jet& a) { return {k + a.v, a.d1, a.d2, a.d3}; }
Jet operator*(const Jet& a, const Jet& b) {  // Leibniz
  return {a.v * b.v, a.d1 * b.v + a.v * b.d1, a.d2 * b.v + 2.0 * a.d1 * b.d1 + a.v * b.d2,
          a.d3 * b.v + 3.0 * a.d2 * b.d1 + 3.0 * a.d1 * b.d2 + a.v * b.d3};
}
/// F(x) from F, F', F'', F''' at x.v (Faà di Bruno to third order).
Jet compose(const Jet& x, double f0, double f1, double f2, double f3) {
  return {f0, f1 * x.d1, f2 * x.d1 * x.d1 + f1 * x.d2, f3 * x.d1 * x.d1 * x.d1 + 3.0 * f2 * x.d1 * x.d2 + f1 * x.d3};
}
/// cos x and sin x of a jet, from one sine and cosine of its value.
void cos_sin(const Jet& x, Jet& cos_x, Jet& sin_x) {
  const double c = std::cos(x.v), s = std::sin(x.v);
  cos_x = compose(x, c, -s, -c, s);
  sin_x = compose(x, s, c, -s, -c);
}
Jet reciprocal(const Jet& x) {
  const double r = 1.0 / x.v;
  return compose(x, r, -r * r, 2.0 * r * r * r, -6.0 * r * r * r * r);
}
struct JetVec {
  Jet x, y;
};

using check_text::num;
using check_text::sibling;
using check_text::to_deg_0_360;

/// The world contact path of the follower on the law (circle: the centre; flat: the contact point).
JetVec world_path(const MotionLaw& law, const FollowerGeometry& f, int sigma, double theta) {
  const LawSample l = law.eval(theta);
  const Jet s{l.s, l.ds, l.d2s, l.d3s}, ds{l.ds, l.d2s, l.d3s, l.d4s};
  const Eigen::Vector2d& A = f.pivot;
  if (!f.oscillating()) {
    if (f.circle()) return {Jet{f.offset}, f.y0 + s};
    return {static_cast<double>(sigma) * ds, f.base_radius + s};
  }
  const Jet psi = f.psi0 + static_cast<double>(f.kappa) * s;
  Jet c, sn;
  cos_sin(psi, c, sn);
  if (f.circle()) return {A.x() + f.arm_length * c, A.y() + f.arm_length * sn};
  const Jet along = A.x() * c + A.y() * sn;  // d·A
  const Jet mu = -1.0 * along * reciprocal(1.0 + static_cast<double>(-sigma * f.kappa) * ds);
  return {A.x() + mu * c, A.y() + mu * sn};
}

}  // namespace

SynthesisedCam::SynthesisedCam(std::shared_ptr<const MotionLaw> law, const FollowerGeometry& follower, int direction)
    : law_(std::move(law)), follower_(follower), direction_(direction) {
  assert(law_ != nullptr && (direction == 1 || direction == -1));
}

CurvePoint SynthesisedCam::at(double u) const {
  const JetVec w = world_path(*law_, follower_, direction_, u);
  const double sg = direction_;
  const Eigen::Vector2d q(w.x.v, w.y.v), q1(w.x.d1, w.y.d1), q2(w.x.d2, w.y.d2), q3(w.x.d3, w.y.d3);
  // r = R(−σu) q with dR(−σu)/du = −σ R J: r^(k) = R (d/du − σJ)^k q.
  // sin(−σu) = −sin(σu) exactly (glibc's sine is odd to the bit): one sincos.
  const double c = std::cos(sg * u), s = -std::sin(sg * u);
  auto rot = [&](const Eigen::Vector2d& v) { return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y()); };
  CurvePoint p;
  p.r = rot(q);
  p.dr = rot(q1 - sg * perp(q));
  p.d2r = rot(q2 - 2.0 * sg * perp(q1) - q);
  p.d3r = rot(q3 - 3.0 * sg * perp(q2) - 3.0 * q1 + sg * perp(q));
  return p;
}

SynthesisedCam::Kinematics SynthesisedCam::kinematics(double theta) const {
  const FollowerGeometry& f = follower_;
  const double sg = direction_;
  const LawSample l = law_->eval(theta);
  const CurvePoint p = at(theta);
  Kinematics k;
  Vec2<double> origin, dir;
  f.face_frame(l.s, origin, dir);
  Eigen::Vector2d rate;  // velocity direction of the follower's contact point per unit q̇
  if (f.circle()) {
    // Outward pitch normal (σ J P' / |P'|, away from the cam centre), turned into the world.
    const Eigen::Vector2d n_cam = sg * perp(p.dr) / p.dr.norm();
    k.normal = rotate(n_cam, sg * theta);
    Vec2<double> c, c_q;
    f.centre(l.s, c, c_q);
    rate = to_eigen(c_q);
    k.contact = to_eigen(c) - f.radius * k.normal;
    k.g_q = k.normal.dot(rate);
    const double kappa = -sg * cross(p.dr, p.d2r) / std::pow(p.dr.norm(), 3);  // pitch curvature, convex > 0
    k.radius_of_curvature = kappa == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / kappa - f.radius;
  } else {
    Vec2<double> pf, m, p_q, m_q;
    f.face(l.s, pf, m, p_q, m_q);
    k.contact = rotate(p.r, sg * theta);
    k.normal = -to_eigen(m);
    rate = to_eigen(f.body_point_rate(Vec2<double>(k.contact)));
    k.g_q = to_eigen(m_q).dot(k.contact - to_eigen(pf)) - to_eigen(m).dot(to_eigen(p_q));
    // r' = ρ_s t with t = J m (cam frame); radius of curvature ρ_s / (σ − β'), β' = κ s' the face's turning rate.
    const Eigen::Vector2d t_cam = rotate(perp(to_eigen(m)), -sg * theta);
    const double rho_s = t_cam.dot(p.dr);
    const double turn = f.oscillating() ? f.kappa * l.ds : 0.0;
    k.radius_of_curvature = rho_s / (sg - turn);
  }
  const Eigen::Vector2d v = rate.normalized();
  k.pressure_angle = std::atan2(cross(v, k.normal), v.dot(k.normal));
  k.face_offset = (k.contact - to_eigen(origin)).dot(to_eigen(dir));
  return k;
}

CamGeometryReport check_cam(const SynthesisedCam& cam, const std::string& file, const std::string& path, int samples) {
  const FollowerGeometry& f = cam.follower();
  const MotionLaw& law = cam.law();
  const double sg = cam.direction();

  const int n_uniform = std::max(samples, 360);
  std::vector<double> us;
  for (int i = 0; i < n_uniform; ++i) us.push_back(kTwoPi * i / n_uniform);
  for (const auto& piece : law.pieces()) {
    constexpr int kPerPiece = 16;
    for (int k = 0; k < kPerPiece; ++k) us.push_back(piece.start + (piece.end - piece.start) * (k + 0.5) / kPerPiece);
  }
  std::sort(us.begin(), us.end());
  auto maximum = [&](auto g) {
    std::vector<double> values;
    values.reserve(us.size());
    for (const double u : us) values.push_back(g(u));
    return refine_max(g, us, values);
  };
  const auto at = [](double u) { return " at cam angle " + num(to_deg_0_360(u)) + "°"; };

  if (f.circle()) {
    const Extremum star = maximum([&](double u) {
      const CurvePoint p = cam.at(u);
      return sg * cross(p.r, p.dr) / p.r.squaredNorm();
    });
    if (star.value >= 0.0)
      throw InputError(file, path,
                       "the pitch curve turns back about the cam centre" + at(star.u) +
                           " (offset or arm geometry too extreme for the law's velocity): the cam cannot be made");
    const Extremum kappa = maximum([&](double u) {
      const CurvePoint p = cam.at(u);
      return -sg * cross(p.dr, p.d2r) / std::pow(p.dr.norm(), 3);
    });
    if (kappa.value * f.radius >= 1.0)
      throw InputError(file, path,
                       "the pitch curve's radius of curvature " + num(1.0 / kappa.value) +
                           " m is not larger than the " + std::string(f.traits().label) + " radius " + num(f.radius) +
                           " m" + at(kappa.u) +
                           ": the cam contour has a cusp or undercut (use a larger base radius, a smaller radius "
                           "or a gentler law)");
  } else {
    if (f.oscillating()) {
      const Extremum turn = maximum([&](double u) { return sg * f.kappa * law.eval(u).ds - 1.0; });
      if (turn.value >= 0.0)
        throw InputError(file, path,
                         "the flat face turns as fast as the cam" + at(turn.u) +
                             " (|ds/dθ| reaches 1 rad/rad): no cam contour exists");
    }
    const Extremum cusp = maximum([&](double u) { return -cam.kinematics(u).radius_of_curvature; });
    if (cusp.value >= 0.0) {
      std::string hint;
      if (!f.oscillating()) {
        // ρ = r_b + s + s'': the smallest base radius without a cusp is max(−(s + s'')).
        hint =
            "; r_b + s + s'' must stay > 0, which needs a base radius above " + num(f.base_radius + cusp.value) + " m";
      }
      throw InputError(file, path,
                       "the flat-faced follower's cam contour has a cusp" + at(cusp.u) + " (radius of curvature " +
                           num(-cusp.value) + " m ≤ 0" + hint + ")");
    }
  }

  const Extremum phi = maximum([&](double u) { return std::abs(cam.kinematics(u).pressure_angle); });
  const Extremum rho = maximum([&](double u) {
    const double r = cam.kinematics(u).radius_of_curvature;
    return std::isfinite(r) ? -std::abs(r) : -std::numeric_limits<double>::infinity();
  });
  CamGeometryReport report;
  report.max_pressure_angle_deg = phi.value * (180.0 / std::numbers::pi);
  report.max_pressure_angle_at_deg = to_deg_0_360(phi.u);
  report.min_radius_of_curvature = -rho.value;
  report.min_radius_of_curvature_at_deg = to_deg_0_360(rho.u);
  if (!f.circle()) {
    const Extremum offset = maximum([&](double u) { return std::abs(cam.kinematics(u).face_offset); });
    report.max_face_offset = offset.value;
    report.max_face_offset_at_deg = to_deg_0_360(offset.u);
    if (offset.value > 0.5 * f.face_width)
      throw InputError(file, sibling(path, "follower.shape.face_width"),
                       "face_width " + num(f.face_width) + " m is too small: the contact point reaches " +
                           num(offset.value) + " m from the face centre" + at(offset.u) +
                           " and leaves the face (needs a face_width above " + num(2.0 * offset.value) + " m)");
  }
  return report;
}

}  // namespace camdyn
