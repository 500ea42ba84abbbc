// The periodic response of a linear follower train and its jump speed
// (docs/model.md §12) against closed forms written here: a single mass on a
// compliant cam contact (its 1-dof transfer function by hand), the rigid
// limit, two masses solved by Cramer's rule, and the row-by-row reference of
// linear_train_reference.h for chains of 1–3 bodies with springs with mass.
#include "dynamics/linear_train_response.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "common/constants.h"
#include "linear_train_reference.h"
#include "tests/geometry/law_checks.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using Complex = std::complex<double>;

/// A response solved two ways (a linear solve each, extremes refined to round-off): relative to the force.
constexpr double kSameResponse = test::kAmplifiedRoundoff;
/// Jump speeds: both bisections stop at ≤ 1e−10 relative.
constexpr double kSameRoot = test::kConverged;

/// The lift h/2 (1 − cos θ) as harmonics: mean h/2, S₁ = −h/2.
LiftHarmonics cosine_lift(double h) { return {0.5 * h, {Complex(-0.5 * h, 0.0)}}; }

// ---- A generic builder: each element stamps its gradient, unlike the reference's rows. ----

/// A force F = k d + c ḋ + F₀ of an element with d = g·x + g_s s; the
/// coordinates receive −g F (virtual work), so K += k g gᵀ, C += c g gᵀ and
/// the inputs −g (k g_s s + c g_s ṡ + F₀).
class TrainBuilder {
 public:
  explicit TrainBuilder(int n) {
    t_.M = t_.C = t_.K = Eigen::MatrixXd::Zero(n, n);
    t_.f0 = t_.k_in = t_.c_in = Eigen::VectorXd::Zero(n);
  }
  void mass(int i, double m) { t_.M(i, i) += m; }
  LinearForce element(const std::vector<std::pair<int, double>>& gradient, double g_s, double k, double c,
                      double preload = 0.0) {
    Eigen::VectorXd g = Eigen::VectorXd::Zero(t_.K.rows());
    for (const auto& [i, v] : gradient) g(i) += v;
    t_.K += k * g * g.transpose();
    t_.C += c * g * g.transpose();
    t_.k_in -= k * g_s * g;
    t_.c_in -= c * g_s * g;
    t_.f0 -= preload * g;
    LinearForce f;
    f.a = k * g, f.b = c * g, f.e = k * g_s, f.f = c * g_s, f.constant = preload;
    return f;
  }
  LinearTrain& train() { return t_; }

 private:
  LinearTrain t_;
};

/// Lowest fixed-fixed mode of a chain of N lumps m_s/N between N + 1 segments k_s, by an eigensolver [rad/s].
double chain_first_mode(double k_s, double m_s, int coils) {
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(coils, coils);
  for (int j = 0; j < coils; ++j) {
    K(j, j) = 2 * k_s;
    if (j > 0) K(j, j - 1) = K(j - 1, j) = -k_s;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> modes(K / (m_s / coils), Eigen::EigenvaluesOnly);
  return std::sqrt(modes.eigenvalues()(0));
}

/// The reference train stamped element by element: follower 0, bodies 1 … B, then each spring's lumps.
/// Held: contact, links 1 … B. Peaks: the spring frame ends, follower's first.
LinearTrain stamped(const test::ReferenceTrain& t) {
  const int bodies = static_cast<int>(t.bodies.size());
  auto spring_of = [&](int b) -> const test::ReferenceSpring& { return b == 0 ? t.spring : t.bodies[b - 1].spring; };
  int n = bodies + 1;
  std::vector<int> first_lump;
  for (int b = 0; b <= bodies; ++b) {
    first_lump.push_back(n);
    if (spring_of(b).lumped()) n += spring_of(b).coils;
  }
  TrainBuilder tb(n);
  tb.train().held.push_back(tb.element({{0, -1.0}}, 1.0, t.contact_stiffness, t.contact_damping));
  for (int b = 0; b <= bodies; ++b) {
    tb.mass(b, b == 0 ? t.mass : t.bodies[b - 1].mass);
    tb.element({{b, 1.0}}, 0.0, 0.0, b == 0 ? t.damper : t.bodies[b - 1].damper);
    if (b > 0) {
      const test::ReferenceBody& body = t.bodies[b - 1];
      tb.train().held.push_back(
          tb.element({{b - 1, body.ratio}, {b, -1.0}}, 0.0, body.link_stiffness, body.link_damping));
    }
    const test::ReferenceSpring& sp = spring_of(b);
    if (!sp.lumped()) {
      tb.train().peaks.push_back(tb.element({{b, 1.0}}, 0.0, sp.rate, 0.0, sp.preload));
      continue;
    }
    const int N = sp.coils;
    const double k_s = (N + 1) * sp.rate;
    const double c_s = 2 * sp.zeta * k_s / chain_first_mode(k_s, sp.mass, N);
    for (int j = 0; j < N; ++j) tb.mass(first_lump[b] + j, sp.mass / N);
    for (int j = 1; j <= N + 1; ++j) {  // segment j between z_{j−1} and z_j; z_0 the body, z_{N+1} the frame
      std::vector<std::pair<int, double>> g{{j == 1 ? b : first_lump[b] + j - 2, 1.0}};
      if (j <= N) g.push_back({first_lump[b] + j - 1, -1.0});
      const LinearForce f = tb.element(g, 0.0, k_s, c_s, sp.preload);
      if (j == N + 1) tb.train().peaks.push_back(f);
    }
  }
  return tb.train();
}

// ---- Lift harmonics ----

TEST(LinearTrainLift, HarmonicRiseAndReturnIsOneCosine) {
  // Harmonic rise over 0–180° and return over 180–360°: s = h/2 (1 − cos θ) exactly.
  constexpr double h = 0.012;  // [m]
  const MotionLaw law = test::build(
      test::segments({test::segment("rise", "harmonic", 180, h), test::segment("return", "harmonic", 360, h)}));
  const LiftHarmonics lift = lift_harmonics(law, 12);
  ASSERT_EQ(lift.S.size(), 12u);
  // A DFT of a few thousand samples sums a few thousand roundings of h.
  const double dft = test::kAmplifiedRoundoff * h;
  EXPECT_NEAR(lift.mean, 0.5 * h, dft);
  EXPECT_NEAR(std::abs(lift.S[0]), 0.5 * h, dft);
  EXPECT_NEAR(lift.S[0].real(), -0.5 * h, dft);  // −h/2 cos θ
  for (std::size_t k = 1; k < lift.S.size(); ++k) EXPECT_LT(std::abs(lift.S[k]), dft) << "harmonic " << k + 1;
}

TEST(LinearTrainLift, SeriesReproducesACycloidalLaw) {
  // A C² law: s''' jumps by J = 4π² h / β³ at both ends of each cycloidal piece of span β, so
  // |S_k| ≤ 2 · 4J / (2π k⁴), and leaving out k > K errs by at most their sum (the DFT's aliasing
  // of k ≥ 1024 − K is far smaller).
  constexpr double h = 0.01;
  constexpr int K = 64;
  const MotionLaw law = test::build(test::segments({test::segment("rise", "cycloidal", 120, h), test::dwell(180),
                                                    test::segment("return", "cycloidal", 300, h), test::dwell(360)}));
  const LiftHarmonics lift = lift_harmonics(law, K);
  const double beta = 2 * kPi / 3, jump = 4 * kPi * kPi * h / (beta * beta * beta);
  double tail = 0;
  for (int k = K + 1; k < 100000; ++k) tail += 4 * jump / (kPi * std::pow(k, 4));
  const double kTruncation = tail / h;
  for (double deg = 0; deg < 360; deg += 7.5) {
    const double th = deg * kDegToRad;
    double s = lift.mean;
    for (std::size_t k = 0; k < lift.S.size(); ++k)
      s += (lift.S[k] * std::polar(1.0, static_cast<double>(k + 1) * th)).real();
    EXPECT_NEAR(s, law.eval(th).s, kTruncation * h) << deg << "°";
  }
  EXPECT_THROW(lift_harmonics(law, -1), std::invalid_argument);
}

// ---- One mass on a compliant cam contact ----

struct OneMass {
  double m = 0.4, k = 15000, F0 = 150, Kc = 2e7, cc = 200, c0 = 5, h = 0.008;  // kg, N/m, N, N/m, N s/m, N s/m, m

  LinearTrain train() const {
    // m ẍ + (c0 + c_c) ẋ + (k + K_c) x = −F0 + K_c s + c_c ṡ; contact K_c (s − x) + c_c (ṡ − ẋ).
    LinearTrain t;
    t.M = Eigen::MatrixXd::Constant(1, 1, m);
    t.C = Eigen::MatrixXd::Constant(1, 1, c0 + cc);
    t.K = Eigen::MatrixXd::Constant(1, 1, k + Kc);
    t.f0 = Eigen::VectorXd::Constant(1, -F0);
    t.k_in = Eigen::VectorXd::Constant(1, Kc);
    t.c_in = Eigen::VectorXd::Constant(1, cc);
    LinearForce contact;
    contact.a = Eigen::VectorXd::Constant(1, -Kc);
    contact.b = Eigen::VectorXd::Constant(1, -cc);
    contact.e = Kc, contact.f = cc, contact.name = "contact";
    t.held.push_back(contact);
    LinearForce spring;
    spring.a = Eigen::VectorXd::Constant(1, k), spring.b = Eigen::VectorXd::Zero(1), spring.constant = F0;
    t.peaks.push_back(spring);
    return t;
  }
  /// Mean contact force: x̄ = (K_c h/2 − F0)/(k + K_c), F̄ = K_c (h/2 − x̄) [N].
  double mean_force() const { return Kc * (k * h / 2 + F0) / (k + Kc); }
  /// First harmonic of the contact force: z_c (S − X) with X = z_c S / D, so z_c S (k − mω² + iωc0) / D [N].
  Complex first_harmonic(double w) const {
    const Complex z_c(Kc, w * cc), S(-h / 2, 0.0);
    const Complex D(k + Kc - m * w * w, w * (c0 + cc));
    return z_c * S * Complex(k - m * w * w, w * c0) / D;
  }
  double min_contact(double w) const { return mean_force() - std::abs(first_harmonic(w)); }
};

TEST(LinearTrainOneMass, MinContactIsMeanLessFirstHarmonic) {
  const OneMass p;
  for (double w : {0.0, 100.0, 300.0, 450.0, 3000.0}) {
    const TrainResponse r = linear_train_response(p.train(), cosine_lift(p.h), w);
    ASSERT_EQ(r.min_held.size(), 1u);
    const double expected = p.min_contact(w);
    EXPECT_NEAR(r.min_held[0], expected, kSameResponse * p.mean_force()) << "ω = " << w;
    // The massless spring's frame end: F0 + k x, max = F0 + k (x̄ + |X₁|).
    const double x_mean = (p.Kc * p.h / 2 - p.F0) / (p.k + p.Kc);
    const Complex X1 = Complex(p.Kc, w * p.cc) * (-p.h / 2) / Complex(p.k + p.Kc - p.m * w * w, w * (p.c0 + p.cc));
    EXPECT_NEAR(r.max_peaks[0], p.F0 + p.k * (x_mean + std::abs(X1)), kSameResponse * p.mean_force());
  }
}

TEST(LinearTrainOneMass, JumpSpeedIsTheRootOfTheHandFormula) {
  const OneMass p;
  constexpr double omega_max = 2000;
  // The root of F̄ − |Φ₁(ω)| = 0: a fine scan of the hand formula, then bisection.
  double lo = 0, hi = 0;
  for (int j = 1; j <= 20000; ++j) {
    hi = omega_max * j / 20000;
    if (p.min_contact(hi) <= 0) break;
    lo = hi;
  }
  ASSERT_LT(lo, omega_max);
  while (hi - lo > 1e-14 * hi) (p.min_contact(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  const double expected = 0.5 * (lo + hi);
  const double got = linear_train_jump_speed(p.train(), cosine_lift(p.h), omega_max);
  EXPECT_NEAR(got / expected, 1.0, kSameRoot) << got << " vs " << expected;
  // Far below the contact resonance √((k + K_c)/m) ≈ 7e3 rad/s, near the rigid figure √(2 (F0 + k h)/(m h)) ≈ 411.
  EXPECT_NEAR(got, std::sqrt(2 * (p.F0 + p.k * p.h) / (p.m * p.h)), 0.05 * got);
  EXPECT_EQ(linear_train_jump_speed(p.train(), cosine_lift(p.h), 0.5 * expected),
            std::numeric_limits<double>::infinity());
}

TEST(LinearTrainRigidLimit, JumpSpeedIsTheRigidClosedForm) {
  // K_c → ∞: x = s, F = m s̈ + k s + F0 = F0 + k h/2 + (m ω² − k) h/2 cos θ, s̈ = ω² h/2 cos θ.
  // Past m ω² = k its minimum is at θ = π (the top, decelerating): F0 + k h − m ω² h/2,
  // zero at ω² = 2 (F0 + k h) / (m h).
  OneMass p;
  p.m = 0.5, p.k = 20000, p.F0 = 200, p.h = 0.01, p.Kc = 1e12, p.cc = 0, p.c0 = 0;
  // The compliance shifts the figures by O(m ω²/K_c, k/K_c) ≈ 1e−7.
  constexpr double kRigidLimit = 1e-6;
  const double rigid = std::sqrt(2 * (p.F0 + p.k * p.h) / (p.m * p.h));  // 400 rad/s
  EXPECT_NEAR(linear_train_jump_speed(p.train(), cosine_lift(p.h), 1000) / rigid, 1.0, kRigidLimit);
  for (double w : {100.0, 300.0}) {
    const double F_min = p.F0 + p.k * p.h / 2 - std::abs(p.m * w * w - p.k) * p.h / 2;
    EXPECT_NEAR(linear_train_response(p.train(), cosine_lift(p.h), w).min_held[0], F_min, kRigidLimit * p.F0);
  }
}

// ---- Two masses: the follower and one body through a two-sided link ----

struct TwoMasses {
  double m0 = 0.2, c0 = 2, k0 = 3000, F00 = 30;     // follower [kg, N s/m, N/m, N]
  double Kc = 4e7, cc = 250;                        // cam contact [N/m, N s/m]
  double r = 1.4, K1 = 1.5e7, c1 = 120;             // link [-, N/m, N s/m]
  double m1 = 0.09, d1 = 3, k1 = 25000, F01 = 220;  // body [kg, N s/m, N/m, N]
  double h = 0.007;                                 // [m]

  test::ReferenceTrain reference() const {
    test::ReferenceTrain t;
    t.mass = m0, t.damper = c0, t.spring.rate = k0, t.spring.preload = F00;
    t.contact_stiffness = Kc, t.contact_damping = cc;
    test::ReferenceBody b;
    b.ratio = r, b.link_stiffness = K1, b.link_damping = c1, b.mass = m1, b.damper = d1;
    b.spring.rate = k1, b.spring.preload = F01;
    t.bodies.push_back(b);
    return t;
  }
  /// Mean state by Cramer: (k0 + K_c + r² K1) q − r K1 x = K_c h/2 − F00; −r K1 q + (k1 + K1) x = −F01.
  std::pair<double, double> mean_state() const {
    const double a00 = k0 + Kc + r * r * K1, a01 = -r * K1, a11 = k1 + K1;
    const double b0 = Kc * h / 2 - F00, b1 = -F01, det = a00 * a11 - a01 * a01;
    return {(b0 * a11 - a01 * b1) / det, (a00 * b1 - a01 * b0) / det};
  }
  /// Amplitudes (Q, X) at frequency w for a lift amplitude S, by Cramer.
  std::pair<Complex, Complex> amplitudes(double w, Complex S) const {
    const Complex zc(Kc, w * cc), z1(K1, w * c1);
    const Complex a00 = -m0 * w * w + Complex(0, w * c0) + k0 + zc + r * r * z1, a01 = -r * z1, a10 = -r * z1;
    const Complex a11 = -m1 * w * w + Complex(0, w * d1) + k1 + z1;
    const Complex det = a00 * a11 - a01 * a10;
    return {zc * S * a11 / det, -a10 * zc * S / det};
  }
};

TEST(LinearTrainTwoMasses, MatchesTheHandSolvedTwoByTwo) {
  const TwoMasses p;
  const LinearTrain train = stamped(p.reference());
  const auto [q, x] = p.mean_state();
  for (double w : {50.0, 400.0, 900.0}) {
    const auto [Q, X] = p.amplitudes(w, -p.h / 2);
    const double contact = p.Kc * (p.h / 2 - q) - std::abs(Complex(p.Kc, w * p.cc) * (-p.h / 2 - Q));
    const double link = p.K1 * (p.r * q - x) - std::abs(Complex(p.K1, w * p.c1) * (p.r * Q - X));
    const double spring = p.F01 + p.k1 * (x + std::abs(X));
    const TrainResponse resp = linear_train_response(train, cosine_lift(p.h), w);
    const double scale = p.F01;  // the forces are of the size of the preload
    EXPECT_NEAR(resp.min_held[0], contact, kSameResponse * scale) << "ω = " << w;
    EXPECT_NEAR(resp.min_held[1], link, kSameResponse * scale) << "ω = " << w;
    EXPECT_NEAR(resp.max_peaks[1], spring, kSameResponse * scale) << "ω = " << w;
  }
}

TEST(LinearTrainTwoMasses, TwoHarmonicLiftMinimumMatchesNewtonOnTheHandSeries) {
  // With two harmonics the minimum has no closed form: F(θ) = F̄ + Re Σ Φ_h e^{ihθ}
  // from the hand amplitudes, minimised by a grid and Newton on F'(θ) = 0.
  const TwoMasses p;
  LiftHarmonics lift = cosine_lift(p.h);
  lift.S.push_back(std::polar(0.15 * p.h, 0.7));
  const LinearTrain train = stamped(p.reference());
  const auto [q, x] = p.mean_state();
  constexpr double w = 600;
  std::vector<Complex> contact, link;
  for (int hh = 1; hh <= 2; ++hh) {
    const auto [Q, X] = p.amplitudes(hh * w, lift.S[hh - 1]);
    contact.push_back(Complex(p.Kc, hh * w * p.cc) * (lift.S[hh - 1] - Q));
    link.push_back(Complex(p.K1, hh * w * p.c1) * (p.r * Q - X));
  }
  auto minimum = [](double mean, const std::vector<Complex>& phi) {
    auto derivative = [&](double th, int order) {  // d^order/dθ^order of Re Σ Φ_h e^{ihθ}
      double v = 0;
      for (int hh = 1; hh <= 2; ++hh)
        v += (phi[hh - 1] * std::pow(Complex(0, hh), order) * std::polar(1.0, hh * th)).real();
      return v;
    };
    double best = 0, best_v = std::numeric_limits<double>::infinity();
    for (int i = 0; i < 3600; ++i)
      if (derivative(2 * kPi * i / 3600, 0) < best_v)
        best_v = derivative(2 * kPi * i / 3600, 0), best = 2 * kPi * i / 3600;
    for (int it = 0; it < 30; ++it) best -= derivative(best, 1) / derivative(best, 2);
    return mean + derivative(best, 0);
  };
  const TrainResponse resp = linear_train_response(train, lift, w);
  const double scale = p.F01;
  EXPECT_NEAR(resp.min_held[0], minimum(p.Kc * (p.h / 2 - q), contact), kSameResponse * scale);
  EXPECT_NEAR(resp.min_held[1], minimum(p.K1 * (p.r * q - x), link), kSameResponse * scale);
}

// ---- The row-by-row reference against the production solver, 1–3 bodies ----

test::ReferenceTrain reference_chain(int bodies) {
  test::ReferenceTrain t;
  t.mass = 0.25, t.damper = 3, t.spring.rate = 2000, t.spring.preload = 20;
  t.contact_stiffness = 5e7, t.contact_damping = 300;
  test::ReferenceBody b1;  // a rocker-like body with a spring with mass
  b1.ratio = 1.5, b1.link_stiffness = 2e7, b1.link_damping = 150, b1.mass = 0.08, b1.damper = 2;
  b1.spring = {.rate = 30000, .preload = 250, .mass = 0.04, .coils = 6, .zeta = 0.05};
  test::ReferenceBody b2;  // a massless spring, lightly preloaded: with 2 bodies link 2 lets go before the cam
  b2.ratio = 0.8, b2.link_stiffness = 1.5e7, b2.link_damping = 100, b2.mass = 0.05, b2.damper = 1;
  b2.spring = {.rate = 8000, .preload = 40};
  test::ReferenceBody b3;  // another spring with mass
  b3.ratio = 1.2, b3.link_stiffness = 1e7, b3.link_damping = 80, b3.mass = 0.03, b3.damper = 1;
  b3.spring = {.rate = 10000, .preload = 80, .mass = 0.02, .coils = 4, .zeta = 0.08};
  const std::vector<test::ReferenceBody> all{b1, b2, b3};
  t.bodies.assign(all.begin(), all.begin() + bodies);
  return t;
}

constexpr double kChainLift = 0.006;     // [m]
constexpr double kChainOmegaMax = 4000;  // [rad/s], above the springs' surge

class LinearTrainReference : public ::testing::TestWithParam<int> {};

TEST_P(LinearTrainReference, ResponseAgreesWithTheProductionSolver) {
  const test::ReferenceTrain ref = reference_chain(GetParam());
  const LinearTrain train = stamped(ref);
  const double jump = test::reference_jump_speed(ref, kChainLift, kChainOmegaMax);
  ASSERT_TRUE(std::isfinite(jump));
  for (double share : {0.0, 0.4, 0.8, 1.5}) {
    const double w = share * jump;
    const test::ReferenceResponse r = test::reference_response(ref, kChainLift, w);
    const TrainResponse got = linear_train_response(train, cosine_lift(kChainLift), w);
    ASSERT_EQ(got.min_held.size(), ref.bodies.size() + 1);
    ASSERT_EQ(got.max_peaks.size(), ref.bodies.size() + 1);
    // Relative to the largest preload: the forces are of its size, and a min force may pass near zero.
    const double scale = kSameRoot * ref.bodies[0].spring.preload;
    EXPECT_NEAR(got.min_held[0], r.min_contact, scale) << "contact at ω = " << w;
    for (std::size_t i = 0; i < ref.bodies.size(); ++i) {
      EXPECT_NEAR(got.min_held[i + 1], r.min_link[i], scale) << "link " << i + 1 << " at ω = " << w;
      EXPECT_NEAR(got.max_peaks[i + 1], r.peak_spring[i + 1], scale) << "spring " << i + 1 << " at ω = " << w;
    }
    EXPECT_NEAR(got.max_peaks[0], r.peak_spring[0], scale) << "follower spring at ω = " << w;
  }
}

TEST_P(LinearTrainReference, JumpSpeedAgreesWithTheProductionSolver) {
  const test::ReferenceTrain ref = reference_chain(GetParam());
  const double expected = test::reference_jump_speed(ref, kChainLift, kChainOmegaMax);
  const double got = linear_train_jump_speed(stamped(ref), cosine_lift(kChainLift), kChainOmegaMax);
  EXPECT_NEAR(got / expected, 1.0, kSameRoot) << got << " vs " << expected;
}

INSTANTIATE_TEST_SUITE_P(LinearTrainBodies, LinearTrainReference, ::testing::Values(1, 2, 3));

TEST(LinearTrainReferenceSpring, SurgeClosedFormIsTheChainsFirstMode) {
  constexpr double k = 30000, m_s = 0.04;  // [N/m, kg]
  for (int N : {1, 2, 6, 20}) {
    const double k_s = (N + 1) * k;
    EXPECT_NEAR(test::surge_omega1(k, m_s, N) / chain_first_mode(k_s, m_s, N), 1.0, test::kAmplifiedRoundoff)
        << N << " coils";
  }
  // The continuous spring's surge π √(k/m_s) as N grows: ω₁ = π √(k/m_s) √(N/(N+1)) sinc(π/(2(N+1))),
  // low by about 1/(2N).
  for (int N : {20, 400}) {
    const double error = 1.0 - test::surge_omega1(k, m_s, N) / (kPi * std::sqrt(k / m_s));
    EXPECT_GT(error, 0.0) << N << " coils";
    EXPECT_LT(error, 1.0 / N) << N << " coils";
  }
}

// ---- Input errors ----

TEST(LinearTrainInput, SingularStiffnessThrows) {
  // A body driven by no link and held by no spring: K has a zero row.
  LinearTrain t = OneMass().train();
  t.M = Eigen::MatrixXd::Identity(2, 2);
  t.C = t.K = Eigen::MatrixXd::Zero(2, 2);
  t.K(0, 0) = 1e6;
  t.f0 = t.k_in = t.c_in = Eigen::VectorXd::Zero(2);
  t.held.clear(), t.peaks.clear();
  EXPECT_THROW(linear_train_response(t, cosine_lift(0.01), 100), std::invalid_argument);
  EXPECT_THROW(linear_train_jump_speed(t, cosine_lift(0.01), 100), std::invalid_argument);
}

TEST(LinearTrainInput, MismatchedSizesThrow) {
  const OneMass p;
  LinearTrain t = p.train();
  t.k_in = Eigen::VectorXd::Zero(2);
  EXPECT_THROW(linear_train_response(t, cosine_lift(p.h), 100), std::invalid_argument);
  t = p.train();
  t.held[0].b = Eigen::VectorXd::Zero(3);
  EXPECT_THROW(linear_train_jump_speed(t, cosine_lift(p.h), 100), std::invalid_argument);
  t = p.train();
  t.M = Eigen::MatrixXd::Zero(1, 2);
  EXPECT_THROW(linear_train_response(t, cosine_lift(p.h), 100), std::invalid_argument);
  EXPECT_THROW(linear_train_response(p.train(), cosine_lift(p.h), -1), std::invalid_argument);
}

}  // namespace
}  // namespace camdyn
