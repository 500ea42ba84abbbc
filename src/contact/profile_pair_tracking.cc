#include "contact/profile_pair_tracking.h"

#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "common/constants.h"
#include "geometry/vec2.h"

namespace camdyn {

namespace {

/// J·v: v turned by +90°.

/// x reduced to (−π, π].
double wrap_pi(double x) {
  double y = x - kTwoPi * std::floor((x + std::numbers::pi) / kTwoPi);
  if (y > std::numbers::pi) y -= kTwoPi;
  return y;
}

CurvePoint circle_point(double radius, const Eigen::Vector2d& center, double v) {
  const double c = std::cos(v), s = std::sin(v);
  return {center + radius * Eigen::Vector2d(c, s), radius * Eigen::Vector2d(-s, c), radius * Eigen::Vector2d(-c, -s),
          radius * Eigen::Vector2d(s, -c)};
}

/// World-frame point, unit tangent, outward unit normal, speed |r'| and signed curvature.
struct Frame {
  Eigen::Vector2d r, t, n;
  double speed = 0.0, curvature = 0.0;
};

Frame world_frame(const CurvePoint& c, int side, const BodyMotion& m) {
  Frame f;
  f.r = m.rotation * c.r + m.position;
  f.speed = c.dr.norm();
  f.t = m.rotation * c.dr / f.speed;
  f.n = side * Eigen::Vector2d(f.t.y(), -f.t.x());
  f.curvature = side * cross(c.dr, c.d2r) / (f.speed * f.speed * f.speed);
  return f;
}

double merit_of(const PairEvaluation& p, double length) { return p.f(0) * p.f(0) + length * length * p.f(1) * p.f(1); }

bool in_domain(const ParameterDomain& d, double x) {
  if (d.periodic) return true;
  const double slack = 1e-12 * (1.0 + std::abs(d.upper - d.lower));
  return x >= d.lower - slack && x <= d.upper + slack;
}

/// Solves J x = b for a 2×2 J; false when J is (nearly) singular.
bool solve2(const Eigen::Matrix2d& j, const Eigen::Vector2d& b, Eigen::Vector2d& x) {
  const double det = j(0, 0) * j(1, 1) - j(0, 1) * j(1, 0);
  const double scale = std::abs(j(0, 0) * j(1, 1)) + std::abs(j(0, 1) * j(1, 0));
  if (!(std::abs(det) > 1e-13 * scale)) return false;
  x = Eigen::Vector2d(j(1, 1) * b(0) - j(0, 1) * b(1), -j(1, 0) * b(0) + j(0, 0) * b(1)) / det;
  return x.allFinite();
}

/// Sample parameters of a profile: periodic ones relative to the reference
/// (offsets in [−π, π)), open ones across the domain.
std::vector<double> sample_offsets(const ParameterDomain& d, int n) {
  std::vector<double> out(n);
  for (int k = 0; k < n; ++k)
    out[k] = d.periodic ? -std::numbers::pi + kTwoPi * k / n : d.lower + (d.upper - d.lower) * k / (n - 1);
  return out;
}

}  // namespace

// ---------------------------------------------------------------- profiles

int closed_curve_orientation(const PeriodicCurve& curve, int samples) {
  double area2 = 0.0;
  Eigen::Vector2d prev = curve.at(0.0).r;
  for (int k = 1; k <= samples; ++k) {
    const Eigen::Vector2d r = curve.at(kTwoPi * k / samples).r;
    area2 += cross(prev, r);
    prev = r;
  }
  return area2 >= 0.0 ? +1 : -1;
}

CurvePoint InwardOffsetProfile::at(double u) const {
  // n = side·N(T)/λ with N(a) = (a_y, −a_x), T = r', λ = |T|; differentiated twice.
  const CurvePoint b = base_->at(u);
  const auto N = [](const Eigen::Vector2d& a) { return Eigen::Vector2d(a.y(), -a.x()); };
  const double side = base_->outward_side();
  const Eigen::Vector2d &T = b.dr, &T1 = b.d2r, &T2 = b.d3r;
  const double lambda = T.norm(), l2sq = lambda * lambda;
  const double l1 = T.dot(T1) / lambda;                                    // λ'
  const double l2 = (T1.dot(T1) + T.dot(T2)) / lambda - l1 * l1 / lambda;  // λ''
  const Eigen::Vector2d n = side * N(T) / lambda;
  const Eigen::Vector2d n1 = side * (N(T1) / lambda - N(T) * l1 / l2sq);
  const Eigen::Vector2d n2 =
      side * (N(T2) / lambda - 2.0 * N(T1) * l1 / l2sq - N(T) * (l2 / l2sq - 2.0 * l1 * l1 / (l2sq * lambda)));
  return {b.r - distance_ * n, T - distance_ * n1, T1 - distance_ * n2, Eigen::Vector2d::Zero()};
}

CurvePoint CircleProfile::at(double v) const { return circle_point(radius_, center_, v); }

CurvePoint ArcProfile::at(double v) const { return circle_point(radius_, center_, v); }

CurvePoint SegmentProfile::at(double v) const {
  return {center_ + v * tangent_, tangent_, Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
}

BodyMotion BodyMotion::make(double angle, const Eigen::Vector2d& position, double angular_velocity,
                            const Eigen::Vector2d& velocity) {
  BodyMotion m;
  const double c = std::cos(angle), s = std::sin(angle);
  m.rotation << c, -s, s, c;
  m.position = position;
  m.angular_velocity = angular_velocity;
  m.velocity = velocity;
  return m;
}

// ---------------------------------------------------------------- evaluation

PairEvaluation evaluate_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                                     const BodyMotion& motion_b, double u, double v) {
  const Frame fa = world_frame(a.at(u), a.outward_side(), motion_a);
  const Frame fb = world_frame(b.at(v), b.outward_side(), motion_b);
  const Eigen::Vector2d d = fb.r - fa.r;
  PairEvaluation p;
  p.u = u;
  p.v = v;
  p.f = Eigen::Vector2d(fa.t.dot(d), fa.t.dot(fb.n));
  p.gap = fa.n.dot(d);
  const double tau = fa.t.dot(fb.t), nn = fa.n.dot(fb.n);
  p.jacobian << -fa.speed * (1.0 + fa.curvature * p.gap), fb.speed * tau,  //
      -fa.curvature * fa.speed * nn, fb.curvature * fb.speed * tau;
  // Material-point velocities; unit vectors fixed in a body turn with it (ṫ = ω J t).
  const Eigen::Vector2d va = motion_a.velocity + motion_a.angular_velocity * perp(fa.r - motion_a.position);
  const Eigen::Vector2d vb = motion_b.velocity + motion_b.angular_velocity * perp(fb.r - motion_b.position);
  const Eigen::Vector2d dv = vb - va;
  const double wa = motion_a.angular_velocity, wb = motion_b.angular_velocity;
  p.f_t = Eigen::Vector2d(wa * perp(fa.t).dot(d) + fa.t.dot(dv), wa * perp(fa.t).dot(fb.n) + wb * fa.t.dot(perp(fb.n)));
  p.gap_rate = wa * perp(fa.n).dot(d) + fa.n.dot(dv);
  p.normal_velocity = fa.n.dot(dv);
  p.tangential_velocity = fa.t.dot(dv);
  p.point_A_W = fa.r;
  p.point_B_W = fb.r;
  p.point_W = 0.5 * (fa.r + fb.r);
  p.normal_W = fa.n;
  p.tangent_W = fa.t;
  p.normal_B_W = fb.n;
  p.curvature_A = fa.curvature;
  p.curvature_B = fb.curvature;
  p.relative_curvature = fa.curvature + fb.curvature + p.gap * fa.curvature * fb.curvature;
  return p;
}

const char* to_string(PairStatus status) {
  switch (status) {
    case PairStatus::converged:
      return "converged";
    case PairStatus::not_converged:
      return "not converged";
    case PairStatus::singular:
      return "singular Jacobian";
    case PairStatus::invalid:
      return "invalid pair (normals not opposing or negative relative curvature)";
    case PairStatus::out_of_domain:
      return "pair outside a profile's parameter range";
  }
  return "unknown";
}

// ---------------------------------------------------------------- Newton

PairStatus newton_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                               const BodyMotion& motion_b, double& u, double& v, PairEvaluation& pair,
                               const PairNewtonOptions& options) {
  pair = evaluate_profile_pair(a, b, motion_a, motion_b, u, v);
  const double length = a.at(u).dr.norm();  // [m/rad], makes f2 commensurate with f1
  double merit = merit_of(pair, length);
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::Vector2d delta;
    if (!solve2(pair.jacobian, -pair.f, delta)) return PairStatus::singular;
    const double largest = delta.cwiseAbs().maxCoeff();
    if (largest > options.max_step) delta *= options.max_step / largest;
    const bool small = std::abs(delta(0)) <= options.step_tolerance * (1.0 + std::abs(u)) &&
                       std::abs(delta(1)) <= options.step_tolerance * (1.0 + std::abs(v));
    // Damping: halve the step until the merit does not grow; a step already
    // at the tolerance is taken as it is (the merit is then rounding noise).
    PairEvaluation trial;
    double trial_merit = merit, scale = 1.0;
    bool accepted = false;
    for (int h = 0; h <= options.max_halvings; ++h, scale *= 0.5) {
      trial = evaluate_profile_pair(a, b, motion_a, motion_b, u + scale * delta(0), v + scale * delta(1));
      trial_merit = merit_of(trial, length);
      if (trial_merit <= merit || small) {
        accepted = true;
        break;
      }
    }
    if (!accepted) return PairStatus::not_converged;
    u = trial.u;
    v = trial.v;
    pair = trial;
    merit = trial_merit;
    if (small) {  // taken undamped (see above)
      if (!in_domain(a.domain(), u) || !in_domain(b.domain(), v)) return PairStatus::out_of_domain;
      return pair.valid() ? PairStatus::converged : PairStatus::invalid;
    }
  }
  return PairStatus::not_converged;
}

PairStatus profile_pair_rates(const PairEvaluation& pair, double alpha, double& u_dot, double& v_dot) {
  Eigen::Vector2d rates;
  if (!solve2(pair.jacobian, -pair.f_t - alpha * pair.f, rates)) {
    u_dot = v_dot = 0.0;
    return PairStatus::singular;
  }
  u_dot = rates(0);
  v_dot = rates(1);
  return PairStatus::converged;
}

// ---------------------------------------------------------------- global search

PairTrackerWorkspace::PairTrackerWorkspace(const PairProfile& a, const PairProfile& b, const PairSearchOptions& search)
    : options(search) {
  assert(search.samples_a >= 8 && search.samples_b >= 8 && search.candidates >= 1);
  a_offset = sample_offsets(a.domain(), search.samples_a);
  b_offset = sample_offsets(b.domain(), search.samples_b);
  // Periodic profiles are sampled at the offsets themselves (the reference
  // shifts them by whole turns only, see global_profile_pair).
  for (double x : a_offset) a_samples.push_back(a.at(x));
  for (double x : b_offset) b_samples.push_back(b.at(x));
  merit.resize(a_offset.size() * b_offset.size());
  candidate_cells.resize(search.candidates + 1);
}

bool global_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                         const BodyMotion& motion_b, double u_ref, double v_ref, PairTrackerWorkspace& ws, double& u,
                         double& v, PairEvaluation& pair) {
  ++ws.global_searches;
  const ParameterDomain da = a.domain(), db = b.domain();
  const int na = static_cast<int>(ws.a_offset.size()), nb = static_cast<int>(ws.b_offset.size());
  // Sample k of a periodic profile is at offset x_k; the copy of it nearest
  // the reference is x_k + 2π·round((ref − x_k)/2π) (the ±π window shifts
  // with the reference, the samples do not).
  const auto unwrap = [](const ParameterDomain& d, double x, double ref) {
    return d.periodic ? ref + wrap_pi(x - ref) : x;
  };
  const int side_a = a.outward_side(), side_b = b.outward_side();
  double length = 0.0;
  for (const CurvePoint& c : ws.a_samples) length += c.dr.norm() / na;
  // Merit on the grid; equal-facing normals are excluded.
  int closest = 0;
  double closest_distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < na; ++i) {
    const Frame fa = world_frame(ws.a_samples[i], side_a, motion_a);
    for (int j = 0; j < nb; ++j) {
      const CurvePoint& cb = ws.b_samples[j];
      const Eigen::Vector2d r_b = motion_b.rotation * cb.r + motion_b.position;
      const Eigen::Vector2d t_b = motion_b.rotation * cb.dr.normalized();
      const Eigen::Vector2d n_b = side_b * Eigen::Vector2d(t_b.y(), -t_b.x());
      const Eigen::Vector2d d = r_b - fa.r;
      double& m = ws.merit[i * nb + j];
      if (fa.n.dot(n_b) < 0.0) {
        const double f1 = fa.t.dot(d), f2 = fa.t.dot(n_b);
        m = f1 * f1 + length * length * f2 * f2;
      } else {
        m = std::numeric_limits<double>::infinity();
      }
      if (d.norm() < closest_distance && m < std::numeric_limits<double>::infinity()) {
        closest_distance = d.norm();
        closest = i * nb + j;
      }
    }
  }
  // Candidates: the best local minima of the merit (neighbours wrap on
  // periodic profiles), kept sorted in a fixed-size list, plus the closest pair.
  const int k_max = ws.options.candidates;
  int count = 0;
  const auto neighbour = [&](int i, int j, int di, int dj) -> double {
    int ii = i + di, jj = j + dj;
    if (da.periodic) ii = (ii + na) % na;
    if (db.periodic) jj = (jj + nb) % nb;
    if (ii < 0 || ii >= na || jj < 0 || jj >= nb) return std::numeric_limits<double>::infinity();
    return ws.merit[ii * nb + jj];
  };
  for (int i = 0; i < na; ++i) {
    for (int j = 0; j < nb; ++j) {
      const double m = ws.merit[i * nb + j];
      if (!(m < std::numeric_limits<double>::infinity())) continue;
      bool minimum = true;
      for (int di = -1; di <= 1 && minimum; ++di)
        for (int dj = -1; dj <= 1 && minimum; ++dj)
          if ((di != 0 || dj != 0) && neighbour(i, j, di, dj) < m) minimum = false;
      if (!minimum) continue;
      // Insert into the sorted list of the best k_max.
      if (count == k_max && !(m < ws.merit[ws.candidate_cells[count - 1]])) continue;
      int pos = count < k_max ? count++ : k_max - 1;
      while (pos > 0 && ws.merit[ws.candidate_cells[pos - 1]] > m) {
        ws.candidate_cells[pos] = ws.candidate_cells[pos - 1];
        --pos;
      }
      ws.candidate_cells[pos] = i * nb + j;
    }
  }
  if (closest_distance < std::numeric_limits<double>::infinity()) ws.candidate_cells[count++] = closest;

  const double spacing_a = da.periodic ? kTwoPi / na : (da.upper - da.lower) / (na - 1);
  const double spacing_b = db.periodic ? kTwoPi / nb : (db.upper - db.lower) / (nb - 1);
  PairNewtonOptions newton;
  newton.max_iterations = 50;
  newton.max_step = 4.0 * std::max(spacing_a, spacing_b);
  bool found = false;
  for (int c = 0; c < count; ++c) {
    const int cell = ws.candidate_cells[c];
    double uc = unwrap(da, ws.a_offset[cell / nb], u_ref), vc = unwrap(db, ws.b_offset[cell % nb], v_ref);
    PairEvaluation trial;
    if (newton_profile_pair(a, b, motion_a, motion_b, uc, vc, trial, newton) != PairStatus::converged) continue;
    if (!found || std::abs(trial.gap) < std::abs(pair.gap)) {
      found = true;
      pair = trial;
    }
  }
  if (!found) return false;
  // Back onto the branches nearest the references.
  u = unwrap(da, pair.u, u_ref);
  v = unwrap(db, pair.v, v_ref);
  pair.u = u;
  pair.v = v;
  return true;
}

bool track_profile_pair(const PairProfile& a, const PairProfile& b, const BodyMotion& motion_a,
                        const BodyMotion& motion_b, PairTrackerWorkspace& ws, double& u, double& v,
                        PairEvaluation& pair, const PairNewtonOptions& options) {
  double uu = u, vv = v;
  if (newton_profile_pair(a, b, motion_a, motion_b, uu, vv, pair, options) == PairStatus::converged) {
    u = uu;
    v = vv;
    return true;
  }
  ++ws.newton_failures;
  if (!global_profile_pair(a, b, motion_a, motion_b, u, v, ws, uu, vv, pair)) return false;
  u = uu;
  v = vv;
  return true;
}

}  // namespace camdyn
