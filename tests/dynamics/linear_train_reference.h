// An independent reference for the linear follower train of docs/model.md §12,
// for end-to-end tests: a translating flat follower on a Kelvin–Voigt cam
// contact (F = K_c δ + c_c δ̇, δ = s − q), its damper and return spring, and a
// chain of 0–3 bodies, each driven through a two-sided link (ratio r_i,
// stiffness K_i, damping c_i, no lash) and held by its own damper and spring.
// A spring is massless (F₀ + k x) or has its mass lumped in N coils joined by
// N + 1 segments of stiffness k_s = (N + 1) k and stiffness-proportional
// damping c_s = 2 ζ k_s / ω₁. The lift is one harmonic, s(θ) = h/2 (1 − cos θ),
// so every force is its mean plus one harmonic and its extremes are
// mean ∓ |first harmonic| in closed form.
//
// Deliberately NOT built on dynamics/linear_train_response: each coordinate's
// equation of motion is written out as its own row (body, then its spring's
// lumps), in complex amplitudes at one frequency, so that the two derivations
// check each other.
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <limits>
#include <numbers>
#include <vector>

namespace camdyn::test {

/// A return spring on a body, pushing it towards −x.
struct ReferenceSpring {
  double rate = 0.0;     ///< k [N/m], ≥ 0
  double preload = 0.0;  ///< F₀ at the body's rest position [N]
  double mass = 0.0;     ///< m_s [kg]; 0: massless (F₀ + k x)
  int coils = 0;         ///< N lumps of m_s / N, ≥ 1 when mass > 0
  double zeta = 0.0;     ///< ζ, damping ratio of the chain's first fixed-fixed mode
  bool lumped() const { return mass > 0.0; }
};

/// A body of the chain after the follower.
struct ReferenceBody {
  double ratio = 1.0;           ///< r_i of the link [m/m]
  double link_stiffness = 0.0;  ///< K_i [N/m]
  double link_damping = 0.0;    ///< c_i [N s/m]
  double mass = 0.0;            ///< m_i [kg]
  double damper = 0.0;          ///< d_i to the frame [N s/m]
  ReferenceSpring spring;
};

/// The follower, its cam contact and the chain of bodies.
struct ReferenceTrain {
  double mass = 0.0;               ///< M [kg]
  double damper = 0.0;             ///< c₀ [N s/m]
  ReferenceSpring spring;          ///< the follower's return spring (may be k = F₀ = 0)
  double contact_stiffness = 0.0;  ///< K_c [N/m]
  double contact_damping = 0.0;    ///< c_c [N s/m]
  std::vector<ReferenceBody> bodies;
};

/// First fixed-fixed mode of N lumps m_s / N joined by N + 1 segments k_s = (N + 1) k [rad/s]:
/// ω₁ = 2 √(k_s N / m_s) sin(π / (2 (N + 1))).
inline double surge_omega1(double rate, double spring_mass, int coils) {
  const double k_s = (coils + 1) * rate;
  return 2.0 * std::sqrt(k_s * coils / spring_mass) * std::sin(std::numbers::pi / (2.0 * (coils + 1)));
}

/// The extremes over one revolution [N].
struct ReferenceResponse {
  double min_contact = 0.0;
  std::vector<double> min_link;     ///< link i at [i − 1]
  std::vector<double> peak_spring;  ///< frame-end force: the follower's at [0], body i's at [i]
};

namespace reference_detail {

using Complex = std::complex<double>;

/// Where each body's coordinate and its spring's lumps sit: body b at at[b], its lumps after it.
struct Layout {
  std::vector<int> at;
  int size = 0;
  explicit Layout(const ReferenceTrain& t) {
    const std::size_t bodies = t.bodies.size() + 1;
    for (std::size_t b = 0; b < bodies; ++b) {
      at.push_back(size);
      const ReferenceSpring& sp = b == 0 ? t.spring : t.bodies[b - 1].spring;
      size += 1 + (sp.lumped() ? sp.coils : 0);
    }
  }
};

inline const ReferenceSpring& spring_of(const ReferenceTrain& t, std::size_t b) {
  return b == 0 ? t.spring : t.bodies[b - 1].spring;
}
inline double mass_of(const ReferenceTrain& t, std::size_t b) { return b == 0 ? t.mass : t.bodies[b - 1].mass; }
inline double damper_of(const ReferenceTrain& t, std::size_t b) { return b == 0 ? t.damper : t.bodies[b - 1].damper; }

/// A segment's complex stiffness k_s + i w c_s [N/m].
inline Complex segment_impedance(const ReferenceSpring& sp, double w) {
  const double k_s = (sp.coils + 1) * sp.rate;
  const double c_s = 2.0 * sp.zeta * k_s / surge_omega1(sp.rate, sp.mass, sp.coils);
  return {k_s, w * c_s};
}

/// The equations of motion at frequency w [rad/s] as rows A X = rhs: A is the
/// dynamic stiffness K + i w C − w² M of the coordinates in Layout order.
struct Rows {
  Eigen::MatrixXcd A;
  Eigen::VectorXcd rhs;
};

/// The rows for a lift amplitude `lift` [m]; with `preloads` the F₀ enter
/// (the mean state: w = 0, lift = mean).
inline Rows rows(const ReferenceTrain& t, double w, Complex lift, bool preloads) {
  const Layout L(t);
  Eigen::MatrixXcd A = Eigen::MatrixXcd::Zero(L.size, L.size);
  Eigen::VectorXcd rhs = Eigen::VectorXcd::Zero(L.size);
  const Complex iw(0.0, w);
  const std::size_t bodies = t.bodies.size() + 1;
  for (std::size_t b = 0; b < bodies; ++b) {
    const int p = L.at[b];
    // m ẍ = [contact or link in] − [r · link out] − d ẋ − spring.
    A(p, p) += -mass_of(t, b) * w * w + iw * damper_of(t, b);
    if (b == 0) {
      // Contact F = z_c (S − Q): +F on the follower.
      const Complex z_c = t.contact_stiffness + iw * t.contact_damping;
      A(p, p) += z_c;
      rhs(p) += z_c * lift;
    } else {
      // Link in F_b = z (r X_{b−1} − X_b): +F_b on body b.
      const ReferenceBody& in = t.bodies[b - 1];
      const Complex z = in.link_stiffness + iw * in.link_damping;
      A(p, p) += z;
      A(p, L.at[b - 1]) -= in.ratio * z;
    }
    if (b + 1 < bodies) {
      // Link out F_{b+1} = z (r X_b − X_{b+1}): −r F_{b+1} on body b.
      const ReferenceBody& out = t.bodies[b];
      const Complex z = out.link_stiffness + iw * out.link_damping;
      A(p, p) += out.ratio * out.ratio * z;
      A(p, L.at[b + 1]) -= out.ratio * z;
    }
    const ReferenceSpring& sp = spring_of(t, b);
    if (preloads) rhs(p) -= sp.preload;  // −F₀ on the body; the lumps' F₀ cancel
    if (!sp.lumped()) {
      A(p, p) += sp.rate;  // −k x
      continue;
    }
    // Body: −F_1 = −z_s (Z_0 − Z_1). Lump j: F_j − F_{j+1} = z_s (Z_{j−1} − Z_j) − z_s (Z_j − Z_{j+1}), Z_{N+1} = 0.
    const Complex z_s = segment_impedance(sp, w);
    A(p, p) += z_s;
    A(p, p + 1) -= z_s;
    const double m_lump = sp.mass / sp.coils;
    for (int j = 1; j <= sp.coils; ++j) {
      A(p + j, p + j) = -m_lump * w * w + 2.0 * z_s;
      A(p + j, p + j - 1) = -z_s;
      if (j < sp.coils) A(p + j, p + j + 1) = -z_s;
    }
  }
  return {A, rhs};
}

/// The amplitudes at frequency w [rad/s] for a lift amplitude `lift` [m]; with
/// `preloads` the F₀ enter (the mean state: w = 0, lift = mean).
inline Eigen::VectorXcd solve_rows(const ReferenceTrain& t, double w, Complex lift, bool preloads) {
  const Rows r = rows(t, w, lift, preloads);
  return r.A.partialPivLu().solve(r.rhs);
}

/// One force as mean + Re(amplitude e^{iθ}) [N].
struct Harmonic {
  double mean = 0.0;
  Complex amplitude = 0.0;
  double min() const { return mean - std::abs(amplitude); }
  double max() const { return mean + std::abs(amplitude); }
};

struct Forces {
  Harmonic contact;
  std::vector<Harmonic> links, springs;
};

/// Every monitored force at cam speed ω on the lift h/2 (1 − cos θ).
inline Forces forces(const ReferenceTrain& t, double lift, double omega) {
  const Layout L(t);
  const double s_mean = 0.5 * lift;
  const Complex s_1 = -0.5 * lift;  // −h/2 cos θ = Re(−h/2 e^{iθ})
  const Eigen::VectorXcd xm = solve_rows(t, 0.0, s_mean, true);
  const Eigen::VectorXcd x1 = solve_rows(t, omega, s_1, false);
  const Complex iw(0.0, omega);
  Forces f;
  f.contact.mean = t.contact_stiffness * (s_mean - xm(0).real());
  f.contact.amplitude = (t.contact_stiffness + iw * t.contact_damping) * (s_1 - x1(0));
  for (std::size_t b = 1; b <= t.bodies.size(); ++b) {
    const ReferenceBody& body = t.bodies[b - 1];
    const int p = L.at[b], q = L.at[b - 1];
    f.links.push_back({body.link_stiffness * (body.ratio * xm(q).real() - xm(p).real()),
                       (body.link_stiffness + iw * body.link_damping) * (body.ratio * x1(q) - x1(p))});
  }
  for (std::size_t b = 0; b <= t.bodies.size(); ++b) {
    const ReferenceSpring& sp = spring_of(t, b);
    const int p = L.at[b];
    if (!sp.lumped()) {
      f.springs.push_back({sp.preload + sp.rate * xm(p).real(), sp.rate * x1(p)});
    } else {  // F_{N+1} = F₀ + k_s z_N + c_s ż_N
      const int last = p + sp.coils;
      f.springs.push_back(
          {sp.preload + (sp.coils + 1) * sp.rate * xm(last).real(), segment_impedance(sp, omega) * x1(last)});
    }
  }
  return f;
}

/// The smallest held force (contact, links) over a revolution [N].
inline double smallest_held(const ReferenceTrain& t, double lift, double omega) {
  const Forces f = forces(t, lift, omega);
  double least = f.contact.min();
  for (const Harmonic& link : f.links) least = std::min(least, link.min());
  return least;
}

}  // namespace reference_detail

/// Min contact and link forces, and peak spring frame-end forces, over one
/// revolution at cam speed `omega` [rad/s] on the lift h/2 (1 − cos θ), h = `lift` [m].
inline ReferenceResponse reference_response(const ReferenceTrain& train, double lift, double omega) {
  const reference_detail::Forces f = reference_detail::forces(train, lift, omega);
  ReferenceResponse r;
  r.min_contact = f.contact.min();
  for (const auto& link : f.links) r.min_link.push_back(link.min());
  for (const auto& spring : f.springs) r.peak_spring.push_back(spring.max());
  return r;
}

/// The lowest ω ≤ omega_max [rad/s] at which the min contact or link force
/// reaches 0: a scan of `steps` equal steps, then bisection to 1e−13 relative.
/// 0 if it fails statically, +inf if it holds up to omega_max.
inline double reference_jump_speed(const ReferenceTrain& train, double lift, double omega_max, int steps = 4000) {
  using reference_detail::smallest_held;
  if (!(smallest_held(train, lift, 0.0) > 0.0)) return 0.0;
  for (int j = 1; j <= steps; ++j) {
    double hi = omega_max * j / steps;
    if (smallest_held(train, lift, hi) > 0.0) continue;
    double lo = omega_max * (j - 1) / steps;
    while (hi - lo > 1e-13 * hi) {
      const double mid = 0.5 * (lo + hi);
      (smallest_held(train, lift, mid) > 0.0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  return std::numeric_limits<double>::infinity();
}

/// The eigenvalues λ of the train's first-order state matrix [[0, I], [−M⁻¹K, −M⁻¹C]]
/// with every contact and link held [1/s]: K, C and M read off the rows'
/// dynamic stiffness, which is K + i w C − w² M exactly (K = Re Z(0), C = Im Z(1),
/// M = K − Re Z(1)). The Poincaré map of the held train is affine, and its
/// Jacobian over one revolution of period T is exp(A T), whose eigenvalues
/// (the Floquet multipliers) are exp(λ T).
inline Eigen::VectorXcd state_matrix_eigenvalues(const ReferenceTrain& train) {
  const Eigen::MatrixXcd z0 = reference_detail::rows(train, 0.0, 0.0, false).A;
  const Eigen::MatrixXcd z1 = reference_detail::rows(train, 1.0, 0.0, false).A;
  const Eigen::MatrixXd K = z0.real(), C = z1.imag(), M = K - z1.real();
  const Eigen::Index n = K.rows();
  const Eigen::MatrixXd M_inv = M.inverse();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -M_inv * K;
  A.bottomRightCorner(n, n) = -M_inv * C;
  return Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues();
}

}  // namespace camdyn::test
