#include "geometry/contour_cam.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/bspline.h"
#include "geometry/check_text.h"
#include "geometry/vec2.h"

namespace camdyn {

namespace {

constexpr double kInvPhi = 0.6180339887498949;  // golden section

using check_text::num;

/// J·v: v turned by +90°.

/// Polar angle of p in [0, 360) [deg].
double polar_deg(const Eigen::Vector2d& p) {
  double deg = std::atan2(p.y(), p.x()) * (180.0 / std::numbers::pi);
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

/// x reduced to [0, 2π).
double wrap_2pi(double x) {
  double y = x - kTwoPi * std::floor(x / kTwoPi);
  if (y >= kTwoPi) y -= kTwoPi;
  return y < 0.0 ? 0.0 : y;
}

/// x reduced to (−π, π].
double wrap_pi(double x) {
  const double y = wrap_2pi(x + std::numbers::pi) - std::numbers::pi;
  return y <= -std::numbers::pi ? y + kTwoPi : y;
}

std::string point_name(int i, const Eigen::Vector2d& p) {
  return "point " + std::to_string(i) + " (" + num(p.x()) + ", " + num(p.y()) + ") at polar angle " +
         num(polar_deg(p)) + "°";
}

/// Golden-section search for the maximum of g on [a, b]: returns the argument.
template <class G>
double golden_max(const G& g, double a, double b, double tolerance) {
  double c = b - kInvPhi * (b - a), d = a + kInvPhi * (b - a);
  double gc = g(c), gd = g(d);
  for (int it = 0; it < 200 && b - a > tolerance; ++it) {
    if (gc > gd) {
      b = d;
      d = c;
      gd = gc;
      c = b - kInvPhi * (b - a);
      gc = g(c);
    } else {
      a = c;
      c = d;
      gc = gd;
      d = a + kInvPhi * (b - a);
      gd = g(d);
    }
  }
  return gc > gd ? c : d;
}

/// Evaluation of a periodic uniform B-spline curve of degree p with m control
/// points: knots (k − p)·2π/m, basis function i used as i mod m.
CurvePoint eval_curve(int p, int m, const std::vector<double>& knots, const std::vector<Eigen::Vector2d>& coefficients,
                      double u) {
  const double x = wrap_2pi(u);
  const int span = find_span(m + p, p, x, knots);
  const BasisDerivatives b = basis_derivatives(span, x, p, knots);
  CurvePoint out{Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  for (int j = 0; j <= p; ++j) {
    const Eigen::Vector2d& c = coefficients[(span - p + j) % m];
    out.r += b.ders[0][j] * c;
    out.dr += b.ders[1][j] * c;
    out.d2r += b.ders[2][j] * c;
    out.d3r += b.ders[3][j] * c;
  }
  return out;
}

/// Validated points: finite, not at the centre, not repeated, star-shaped.
/// Drops a closing point equal to the first. Returns the orientation (+1 ccw).
int validate_points(std::vector<Eigen::Vector2d>& pts, const std::string& file, const std::string& where) {
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!pts[i].allFinite())
      throw InputError(
          file, where,
          "point " + std::to_string(i) + " is not finite (" + num(pts[i].x()) + ", " + num(pts[i].y()) + ")");
  }
  double scale = 0.0;
  for (const auto& p : pts) scale = std::max(scale, p.norm());
  const double same = 1e-9 * scale;  // [m] closer than this counts as the same point
  if (pts.size() > 1 && (pts.back() - pts.front()).norm() <= same) pts.pop_back();
  const int n = static_cast<int>(pts.size());
  if (n < kMinContourPoints)
    throw InputError(
        file, where,
        "needs at least " + std::to_string(kMinContourPoints) + " distinct points, got " + std::to_string(n));
  for (int i = 0; i < n; ++i) {
    if (pts[i].norm() <= same)
      throw InputError(file, where, "point " + std::to_string(i) + " is at the cam centre (0, 0)");
  }
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    if ((pts[j] - pts[i]).norm() <= same)
      throw InputError(file, where, point_name(j, pts[j]) + " repeats point " + std::to_string(i));
  }
  // Star-shaped about the centre: every step turns the polar angle the same
  // way, and the steps add up to exactly one turn.
  double total = 0.0;
  int sense = 0;
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    const double step = wrap_pi(std::atan2(pts[j].y(), pts[j].x()) - std::atan2(pts[i].y(), pts[i].x()));
    const int s = step > 0.0 ? 1 : step < 0.0 ? -1 : 0;
    if (i == 0) sense = s;
    if (s == 0 || s != sense)
      throw InputError(file, where,
                       point_name(j, pts[j]) + " does not continue the polar angle of point " + std::to_string(i) +
                           " (" + num(polar_deg(pts[i])) +
                           "°) in the same sense: the points must go once around the cam centre, in order "
                           "(a star-shaped contour about the origin)");
    total += step;
  }
  if (std::abs(std::abs(total) - kTwoPi) > 1e-6)
    throw InputError(file, where,
                     "the points wind " + num(total / kTwoPi) +
                         " times around the cam centre; a contour goes around it exactly once");
  return sense;
}

struct Fit {
  std::vector<double> knots;
  std::vector<Eigen::Vector2d> coefficients;
};

/// Least-squares periodic spline through points at parameters t (plus the
/// penalty). Returns false when the normal equations are (nearly) singular.
bool least_squares(int p, int m, double smoothing, const std::vector<Eigen::Vector2d>& pts,
                   const std::vector<double>& t, Fit& fit) {
  const int n = static_cast<int>(pts.size());
  const double h = kTwoPi / m;
  fit.knots.resize(m + 2 * p + 1);
  for (int k = 0; k < m + 2 * p + 1; ++k) fit.knots[k] = (k - p) * h;
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(m, m);
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
  for (int i = 0; i < n; ++i) {
    const double x = wrap_2pi(t[i]);
    const int span = find_span(m + p, p, x, fit.knots);
    const BasisDerivatives b = basis_derivatives(span, x, p, fit.knots);
    for (int a = 0; a <= p; ++a) {
      const int ia = (span - p + a) % m;
      rhs(ia, 0) += b.ders[0][a] * pts[i].x();
      rhs(ia, 1) += b.ders[0][a] * pts[i].y();
      for (int c = 0; c <= p; ++c) normal(ia, (span - p + c) % m) += b.ders[0][a] * b.ders[0][c];
    }
  }
  if (smoothing > 0.0) {
    // Cyclic third differences c_k − 3c_{k+1} + 3c_{k+2} − c_{k+3}, weighted
    // relative to the mean data weight of one control point (trace / m).
    const double weight = smoothing * normal.trace() / m;
    constexpr double kD[4] = {1.0, -3.0, 3.0, -1.0};
    for (int k = 0; k < m; ++k)
      for (int a = 0; a < 4; ++a)
        for (int c = 0; c < 4; ++c) normal((k + a) % m, (k + c) % m) += weight * kD[a] * kD[c];
  }
  const Eigen::LLT<Eigen::MatrixXd> llt(normal);
  if (llt.info() != Eigen::Success || !(llt.rcond() > 1e-13)) return false;
  const Eigen::MatrixXd c = llt.solve(rhs);
  if (!c.allFinite()) return false;
  fit.coefficients.resize(m);
  for (int k = 0; k < m; ++k) fit.coefficients[k] = Eigen::Vector2d(c(k, 0), c(k, 1));
  return true;
}

/// Foot point of q on the curve by Newton on (C − q)·C' = 0 from t, each
/// step at most max_step. Returns the parameter (unchanged if Newton fails).
template <class Curve>
double project(const Curve& curve, const Eigen::Vector2d& q, double t, double max_step) {
  for (int it = 0; it < 30; ++it) {
    const CurvePoint c = curve(t);
    const Eigen::Vector2d d = c.r - q;
    const double phi = d.dot(c.dr), dphi = c.dr.squaredNorm() + d.dot(c.d2r);
    if (!(dphi > 0.0)) break;
    const double step = std::clamp(-phi / dphi, -max_step, max_step);
    t += step;
    if (std::abs(step) <= 1e-15 * kTwoPi) break;
  }
  return t;
}

/// Throws InputError (at `path`) for a degree, smoothing or number of
/// parameter corrections out of range.
void check_fit_options(const ContourFitOptions& options, const std::string& file, const std::string& path) {
  if (options.degree < 3 || options.degree > kMaxSplineDegree)
    throw InputError(file, path + ".degree",
                     "must be in [3, " + std::to_string(kMaxSplineDegree) + "], got " + std::to_string(options.degree));
  if (!(options.smoothing >= 0.0) || !std::isfinite(options.smoothing))
    throw InputError(file, path + ".smoothing", "must be a finite number >= 0, got " + num(options.smoothing));
  if (options.parameter_corrections < 0 || options.parameter_corrections > 50)
    throw InputError(file, path + ".parameter_corrections",
                     "must be in [0, 50], got " + std::to_string(options.parameter_corrections));
}

/// The number of control points m for n points: the given one, or with 0 about
/// one per two points (at least 2 (p + 1), at most 400). Throws InputError.
int control_point_count(const ContourFitOptions& options, int n, const std::string& file, const std::string& path) {
  const int p = options.degree;
  int m = options.control_points;
  if (m == 0) m = std::min(n, std::clamp(n / 2, 2 * (p + 1), 400));
  if (m < p + 1 || m > n)
    throw InputError(file, path + ".control_points",
                     "must be 0 (automatic) or in [degree + 1, number of points] = [" + std::to_string(p + 1) + ", " +
                         std::to_string(n) + "], got " + std::to_string(m));
  return m;
}

/// Chord-length parameters of the closed polygon `pts`, scaled to [0, 2π) [rad].
std::vector<double> chord_parameters(const std::vector<Eigen::Vector2d>& pts) {
  const int n = static_cast<int>(pts.size());
  std::vector<double> t(n, 0.0);
  double length = 0.0;
  for (int i = 0; i < n; ++i) length += (pts[(i + 1) % n] - pts[i]).norm();
  for (int i = 1; i < n; ++i) t[i] = t[i - 1] + kTwoPi * (pts[i] - pts[i - 1]).norm() / length;
  return t;
}

/// The least-squares spline of degree p with m control points, its point
/// parameters t [rad] corrected to the foot points after each of the
/// options.parameter_corrections + 1 fits. Throws InputError (at `where`)
/// when a fit is singular.
Fit fit_with_corrections(int p, int m, const ContourFitOptions& options, const std::vector<Eigen::Vector2d>& pts,
                         std::vector<double>& t, const std::string& file, const std::string& where) {
  const int n = static_cast<int>(pts.size());
  Fit fit;
  const double h = kTwoPi / m;
  for (int round = 0;; ++round) {
    if (!least_squares(p, m, options.smoothing, pts, t, fit))
      throw InputError(file, where,
                       "the least-squares fit with " + std::to_string(m) +
                           " control points is singular (points too unevenly spaced along the contour): give fewer "
                           "'control_points' or some 'smoothing'");
    const auto curve = [&](double u) { return eval_curve(p, m, fit.knots, fit.coefficients, u); };
    for (int i = 0; i < n; ++i) t[i] = project(curve, pts[i], t[i], 0.5 * h);
    if (round >= options.parameter_corrections) break;
  }
  return fit;
}

/// Index of the point of `pts` nearest to r (the first of equals).
int nearest_point(const std::vector<Eigen::Vector2d>& pts, const Eigen::Vector2d& r) {
  int best = 0;
  for (int i = 1; i < static_cast<int>(pts.size()); ++i)
    if ((pts[i] - r).norm() < (pts[best] - r).norm()) best = i;
  return best;
}

/// RMS and largest distance [m] of the points from the curve at their parameters t.
void measure_residuals(const ContourCam& cam, const std::vector<Eigen::Vector2d>& pts, const std::vector<double>& t,
                       ContourFitReport& rep) {
  const int n = static_cast<int>(pts.size());
  double sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double d = (cam.at(t[i]).r - pts[i]).norm();
    sum2 += d * d;
    if (d > rep.max_residual) {
      rep.max_residual = d;
      rep.max_residual_point = i;
    }
  }
  rep.rms_residual = std::sqrt(sum2 / n);
}

/// Curvature κ [1/m] of the fitted curve at evenly spaced parameters u [rad].
struct CurvatureSamples {
  std::vector<double> u, kappa;
  double du = 0.0;  ///< spacing of u [rad]
};

/// Dense samples of the fitted curve (orientation `sense`): its curvature,
/// and a check that it stays star-shaped about the cam centre, else
/// InputError at `where` naming the nearest point.
CurvatureSamples sample_curvature(const ContourCam& cam, const std::vector<Eigen::Vector2d>& pts, int sense,
                                  const std::string& file, const std::string& where) {
  const int samples = std::max(2048, 16 * static_cast<int>(cam.control_points().size()));
  CurvatureSamples out;
  out.u.resize(samples);
  out.kappa.resize(samples);
  for (int k = 0; k < samples; ++k) {
    out.u[k] = kTwoPi * k / samples;
    const CurvePoint c = cam.at(out.u[k]);
    if (!(sense * cross(c.r, c.dr) > 0.0))
      throw InputError(file, where,
                       "the fitted contour turns back about the cam centre at polar angle " + num(polar_deg(c.r)) +
                           "° near point " + std::to_string(nearest_point(pts, c.r)) +
                           " (it must stay star-shaped): check the points there, add points or raise 'smoothing'");
    out.kappa[k] = cam.curvature(out.u[k]);
  }
  out.du = kTwoPi / samples;
  return out;
}

/// The smallest radius of curvature and the smallest convex one, refined
/// around the sampled maxima of |κ| and κ.
void find_min_radii(const ContourCam& cam, const CurvatureSamples& s, ContourFitReport& rep) {
  const auto curvature_fn = [&](double u) { return cam.curvature(u); };
  int k_abs = 0, k_max = 0;
  for (int k = 1; k < static_cast<int>(s.kappa.size()); ++k) {
    if (std::abs(s.kappa[k]) > std::abs(s.kappa[k_abs])) k_abs = k;
    if (s.kappa[k] > s.kappa[k_max]) k_max = k;
  }
  const double u_abs =
      golden_max([&](double u) { return std::abs(curvature_fn(u)); }, s.u[k_abs] - s.du, s.u[k_abs] + s.du, 1e-12);
  rep.min_radius_of_curvature = 1.0 / std::abs(curvature_fn(u_abs));
  rep.min_radius_of_curvature_angle_deg = polar_deg(cam.at(u_abs).r);
  if (s.kappa[k_max] > 0.0) {
    const double u_max = golden_max(curvature_fn, s.u[k_max] - s.du, s.u[k_max] + s.du, 1e-12);
    rep.min_convex_radius = 1.0 / curvature_fn(u_max);
    rep.min_convex_radius_angle_deg = polar_deg(cam.at(u_max).r);
  }
}

/// Where κ changes sign in [a, b] [rad], by bisection.
double curvature_zero(const ContourCam& cam, double a, double b) {
  const bool neg_a = cam.curvature(a) < 0.0;
  for (int it = 0; it < 60; ++it) {
    const double c = 0.5 * (a + b);
    if ((cam.curvature(c) < 0.0) == neg_a)
      a = c;
    else
      b = c;
  }
  return 0.5 * (a + b);
}

/// The concave portions of the fitted curve: runs of sampled κ < 0, their
/// ends refined by bisection and their sharpest point by golden section.
std::vector<ConcavePortion> concave_portions(const ContourCam& cam, const std::vector<Eigen::Vector2d>& pts,
                                             const CurvatureSamples& s) {
  const std::vector<double>& us = s.u;
  const std::vector<double>& kappa = s.kappa;
  const double du = s.du;
  const int samples = static_cast<int>(kappa.size());
  std::vector<ConcavePortion> out;
  int start = 0;  // a convex sample to start the cyclic scan from
  while (start < samples && kappa[start] < 0.0) ++start;
  assert(start < samples);  // a closed curve turns once: it is convex somewhere
  for (int j = 1; j <= samples; ++j) {
    const int k = (start + j) % samples;
    if (!(kappa[k] < 0.0)) continue;
    // Portion begins between sample k − 1 and k; walk to its end.
    ConcavePortion portion;
    portion.u_begin = curvature_zero(cam, us[k] - du, us[k]);
    int worst = k;
    int e = j;
    while (e + 1 <= samples && kappa[(start + e + 1) % samples] < 0.0) {
      ++e;
      if (kappa[(start + e) % samples] < kappa[worst]) worst = (start + e) % samples;
    }
    const int last = (start + e) % samples;
    double u_last = us[last];
    if (u_last < us[k]) u_last += kTwoPi;
    portion.u_end = curvature_zero(cam, u_last, u_last + du);
    if (portion.u_begin < 0.0) {
      portion.u_begin += kTwoPi;
      portion.u_end += kTwoPi;
    }
    const double u_worst_0 = us[worst] < us[k] ? us[worst] + kTwoPi : us[worst];
    const double u_worst =
        golden_max([&](double u) { return -cam.curvature(u); }, u_worst_0 - du, u_worst_0 + du, 1e-12);
    portion.min_abs_radius = 1.0 / -cam.curvature(u_worst);
    portion.min_abs_radius_angle_deg = polar_deg(cam.at(u_worst).r);
    portion.angle_begin_deg = polar_deg(cam.at(portion.u_begin).r);
    portion.angle_end_deg = polar_deg(cam.at(portion.u_end).r);
    portion.point_begin = nearest_point(pts, cam.at(portion.u_begin).r);
    portion.point_end = nearest_point(pts, cam.at(portion.u_end).r);
    out.push_back(portion);
    j = e;
  }
  return out;
}

}  // namespace

// ---------------------------------------------------------------- fit

ContourCam ContourCam::fit(const std::vector<Eigen::Vector2d>& points, const ContourFitOptions& options,
                           const std::string& file, const std::string& path) {
  const std::string where = path + ".points";
  check_fit_options(options, file, path);

  ContourCam cam;
  cam.points_ = points;
  const int sense = validate_points(cam.points_, file, where);
  const auto& pts = cam.points_;
  const int n = static_cast<int>(pts.size());
  const int p = options.degree;
  const int m = control_point_count(options, n, file, path);

  std::vector<double> t = chord_parameters(pts);
  Fit fit = fit_with_corrections(p, m, options, pts, t, file, where);
  cam.degree_ = p;
  cam.m_ = m;
  cam.knots_ = std::move(fit.knots);
  cam.coefficients_ = std::move(fit.coefficients);
  cam.orientation_ = sense;

  ContourFitReport& rep = cam.report_;
  rep.points = n;
  rep.degree = p;
  rep.control_points = m;
  cam.parameters_.resize(n);
  for (int i = 0; i < n; ++i) cam.parameters_[i] = wrap_2pi(t[i]);
  measure_residuals(cam, pts, t, rep);

  // Dense samples of the fitted curve: star-shapedness and curvature.
  const CurvatureSamples samples = sample_curvature(cam, pts, sense, file, where);
  find_min_radii(cam, samples, rep);
  rep.concave = concave_portions(cam, pts, samples);
  return cam;
}

CurvePoint ContourCam::at(double u) const { return eval_curve(degree_, m_, knots_, coefficients_, u); }

double ContourCam::curvature(double u) const {
  const CurvePoint c = at(u);
  return orientation_ * cross(c.dr, c.d2r) / std::pow(c.dr.norm(), 3);
}

Eigen::Vector2d ContourCam::outward_normal(double u) const {
  const Eigen::Vector2d t = at(u).dr.normalized();
  return orientation_ * Eigen::Vector2d(t.y(), -t.x());
}

// ---------------------------------------------------------------- follower checks

void check_contour_for_follower(const ContourCam& cam, FollowerContact follower, double radius, const std::string& file,
                                const std::string& path, double min_convex_radius) {
  const std::string where = path + ".points";
  const ContourFitReport& rep = cam.report();
  const auto describe = [&](const ConcavePortion& c) {
    return "the fitted contour is concave from polar angle " + num(c.angle_begin_deg) + "° (near point " +
           std::to_string(c.point_begin) + ") to " + num(c.angle_end_deg) + "° (near point " +
           std::to_string(c.point_end) + "), smallest radius of curvature " + num(c.min_abs_radius) + " m at " +
           num(c.min_abs_radius_angle_deg) + "°";
  };
  for (const ConcavePortion& c : rep.concave) {
    if (follower == FollowerContact::line)
      throw InputError(file, where, describe(c) + ": a flat-faced follower cannot follow a concave flank");
    if (c.min_abs_radius < radius)
      throw InputError(file, where,
                       describe(c) + ", less than the follower radius " + num(radius) +
                           " m: the follower cannot reach into it (two-point contact)");
  }
  if (min_convex_radius > 0.0 && rep.min_convex_radius < min_convex_radius)
    throw InputError(file, where,
                     "the fitted contour's convex radius of curvature " + num(rep.min_convex_radius) + " m is below " +
                         num(min_convex_radius) + " m at polar angle " + num(rep.min_convex_radius_angle_deg) +
                         "°: the points probably have a corner there that the fit rounded off");
}

// ---------------------------------------------------------------- rigid follower

namespace {

/// Y(θ, u) and its partial derivatives, for the rigid-lift maximisation.
struct LiftTerms {
  bool valid = false;  ///< the point is within reach of the roller (always, for a flat face)
  double y = 0.0, y_u = 0.0, y_uu = 0.0, y_t = 0.0, y_tt = 0.0, y_tu = 0.0;
  Eigen::Vector2d q = Eigen::Vector2d::Zero();
};

LiftTerms lift_terms(const CurvePoint& c, double theta, int sigma, bool flat, double rho, double e) {
  const double cs = std::cos(sigma * theta), sn = std::sin(sigma * theta);
  const auto rot = [&](const Eigen::Vector2d& v) {
    return Eigen::Vector2d(cs * v.x() - sn * v.y(), sn * v.x() + cs * v.y());
  };
  const Eigen::Vector2d q = rot(c.r), q_u = rot(c.dr), q_uu = rot(c.d2r);
  const Eigen::Vector2d q_t = sigma * perp(q), q_tt = -q, q_tu = sigma * perp(q_u);
  LiftTerms out;
  out.q = q;
  out.y = q.y();
  out.y_u = q_u.y();
  out.y_uu = q_uu.y();
  out.y_t = q_t.y();
  out.y_tt = q_tt.y();
  out.y_tu = q_tu.y();
  if (flat) {
    out.valid = true;
    return out;
  }
  // + w, w = sqrt(ρ² − ξ²), ξ = q_x − e: w_a = −ξ ξ_a / w,
  // w_ab = −(ξ_a ξ_b + ξ ξ_ab) / w − ξ² ξ_a ξ_b / w³.
  const double xi = q.x() - e, w2 = rho * rho - xi * xi;
  if (!(w2 > 0.0)) return out;
  const double w = std::sqrt(w2);
  const double x_u = q_u.x(), x_t = q_t.x();
  const auto second = [&](double xa, double xb, double xab) {
    return -(xa * xb + xi * xab) / w - xi * xi * xa * xb / (w2 * w);
  };
  out.valid = true;
  out.y += w;
  out.y_u += -xi * x_u / w;
  out.y_t += -xi * x_t / w;
  out.y_uu += second(x_u, x_u, q_uu.x());
  out.y_tt += second(x_t, x_t, q_tt.x());
  out.y_tu += second(x_u, x_t, q_tu.x());
  return out;
}

}  // namespace

RigidFollowerLift::RigidFollowerLift(const PeriodicCurve& curve, FollowerContact follower, double radius, double offset,
                                     int direction, int samples, const std::string& file,
                                     const std::string& offset_path)
    : curve_(&curve), follower_(follower), radius_(radius), offset_(offset), direction_(direction) {
  assert(direction == 1 || direction == -1);
  assert(follower == FollowerContact::line || radius > 0.0);
  assert(samples >= 16);
  sample_u_.resize(samples);
  sample_r_.resize(samples);
  for (int k = 0; k < samples; ++k) {
    sample_u_[k] = kTwoPi * k / samples;
    sample_r_[k] = curve.at(sample_u_[k]).r;
  }
  constexpr int kAngles = 720;
  if (follower != FollowerContact::line) {
    // The roller must reach the cam at every angle: some contour point within ρ of its axis.
    for (int i = 0; i < kAngles; ++i) {
      const double th = kTwoPi * i / kAngles, cs = std::cos(direction * th), sn = std::sin(direction * th);
      bool reached = false;
      for (const Eigen::Vector2d& r : sample_r_)
        reached = reached || std::abs(cs * r.x() - sn * r.y() - offset) < radius;
      if (!reached)
        throw InputError(file, offset_path,
                         "the follower axis x = " + num(offset) + " m passes the cam at cam angle " +
                             num(360.0 * i / kAngles) + "° farther than the follower radius " + num(radius) +
                             " m: reduce the offset");
    }
  }
  // Lowest position: sampled over a turn, refined by golden section.
  int best = 0;
  double best_y = INFINITY;
  for (int i = 0; i < kAngles; ++i) {
    const double y = at(kTwoPi * i / kAngles).y;
    if (y < best_y) {
      best_y = y;
      best = i;
    }
  }
  const double step = kTwoPi / kAngles;
  lowest_angle_ = golden_max([&](double th) { return -at(th).y; }, kTwoPi * best / kAngles - step,
                             kTwoPi * best / kAngles + step, 1e-12);
  lowest_ = at(lowest_angle_).y;
  lowest_angle_ = wrap_2pi(lowest_angle_);
}

RigidLift RigidFollowerLift::at(double theta) const {
  const bool flat = follower_ == FollowerContact::line;
  const int n = static_cast<int>(sample_u_.size());
  const double cs = std::cos(direction_ * theta), sn = std::sin(direction_ * theta);
  // Sampled Y(θ, u_k) without derivatives: the best two local maxima.
  const auto sampled = [&](int k) {
    const Eigen::Vector2d& r = sample_r_[k];
    const double qx = cs * r.x() - sn * r.y(), qy = sn * r.x() + cs * r.y();
    if (flat) return qy;
    const double xi = qx - offset_, w2 = radius_ * radius_ - xi * xi;
    return w2 > 0.0 ? qy + std::sqrt(w2) : -INFINITY;
  };
  int first = -1, second = -1;
  double v_first = -INFINITY, v_second = -INFINITY;
  double prev = sampled(n - 1), cur = sampled(0);
  for (int k = 0; k < n; ++k) {
    const double next = sampled((k + 1) % n);
    if (cur >= prev && cur >= next && cur > -INFINITY) {
      if (cur > v_first) {
        second = first;
        v_second = v_first;
        first = k;
        v_first = cur;
      } else if (cur > v_second) {
        second = k;
        v_second = cur;
      }
    }
    prev = cur;
    cur = next;
  }
  if (first < 0) {
    // Unreachable after the constructor's check (the roller always reaches
    // the cam); stay finite rather than fail inside a right-hand side.
    assert(false);
    first = 0;
  }
  const double h = kTwoPi / n;
  const auto terms = [&](double u) { return lift_terms(curve_->at(u), theta, direction_, flat, radius_, offset_); };
  const auto refine = [&](int k) {
    // Newton on Y_u = 0 within one sample spacing; golden section if it fails.
    double u = sample_u_[k];
    bool ok = false;
    for (int it = 0; it < 40; ++it) {
      const LiftTerms t = terms(u);
      if (!t.valid || !(t.y_uu < 0.0)) break;
      const double step = -t.y_u / t.y_uu;
      if (std::abs(u + step - sample_u_[k]) > h) break;
      u += step;
      if (std::abs(step) <= 1e-15 * kTwoPi) {
        ok = true;
        break;
      }
    }
    if (!ok)
      u = golden_max(
          [&](double x) {
            const LiftTerms t = terms(x);
            return t.valid ? t.y : -INFINITY;
          },
          sample_u_[k] - h, sample_u_[k] + h, 1e-14);
    return u;
  };
  double u = refine(first);
  if (second >= 0 && v_first - v_second < 1e-3 * (std::abs(v_first) + radius_)) {
    const double u2 = refine(second);
    if (terms(u2).y > terms(u).y) u = u2;
  }
  const LiftTerms t = terms(u);
  RigidLift out;
  out.u = wrap_2pi(u);
  out.y = t.y;
  out.dy = t.y_t;  // envelope theorem: Y_u = 0 at the maximum
  // y'' = Y_tt + Y_tu du/dθ with du/dθ = −Y_tu / Y_uu.
  out.d2y = t.y_uu < 0.0 ? t.y_tt - t.y_tu * t.y_tu / t.y_uu : t.y_tt;
  out.contact_W = t.q;
  return out;
}

}  // namespace camdyn
