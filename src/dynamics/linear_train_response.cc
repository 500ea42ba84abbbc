#include "dynamics/linear_train_response.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "common/constants.h"
#include "dynamics/jump_speed_scan.h"

namespace camdyn {

namespace {

using Complex = std::complex<double>;

/// Fewest lift samples of the DFT, and samples per harmonic.
constexpr int kMinLiftSamples = 1024, kLiftSamplesPerHarmonic = 8;
/// Fewest angles of the extremum grid, and angles per harmonic (16 per period of the highest one).
constexpr int kMinAngles = 720, kAnglesPerHarmonic = 16;
/// Relative width at which the jump-speed bisection stops.
constexpr double kSpeedTolerance = 1e-10;

/// Mismatched sizes are input errors, with the offending sizes.
void check_sizes(const LinearTrain& train) {
  const Eigen::Index n = train.K.rows();
  auto fail = [&](const std::string& what, Eigen::Index rows, Eigen::Index cols) {
    throw std::invalid_argument("linear train with " + std::to_string(n) + " coordinates: " + what + " is " +
                                std::to_string(rows) + "×" + std::to_string(cols));
  };
  if (n == 0 || train.K.cols() != n) fail("K", train.K.rows(), train.K.cols());
  if (train.M.rows() != n || train.M.cols() != n) fail("M", train.M.rows(), train.M.cols());
  if (train.C.rows() != n || train.C.cols() != n) fail("C", train.C.rows(), train.C.cols());
  if (train.f0.size() != n) fail("f0", train.f0.size(), 1);
  if (train.k_in.size() != n) fail("k_in", train.k_in.size(), 1);
  if (train.c_in.size() != n) fail("c_in", train.c_in.size(), 1);
  for (const std::vector<LinearForce>* forces : {&train.held, &train.peaks}) {
    for (const LinearForce& force : *forces) {
      if (force.a.size() != n) fail("force '" + force.name + "'.a", force.a.size(), 1);
      if (force.b.size() != n) fail("force '" + force.name + "'.b", force.b.size(), 1);
    }
  }
}

/// x̄ with K x̄ = f0 + k_in·mean [m]; throws for a singular K.
Eigen::VectorXd mean_state(const LinearTrain& train, const LiftHarmonics& lift) {
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(train.K);
  if (!lu.isInvertible())
    throw std::invalid_argument("linear train: K is singular (rank " + std::to_string(lu.rank()) + " of " +
                                std::to_string(train.K.rows()) + "): a coordinate no spring holds");
  return lu.solve(train.f0 + train.k_in * lift.mean);
}

/// X_h = (K − (hω)² M + i hω C)⁻¹ (k_in + i hω c_in) S_h [m], h = 1 … H; one LU per frequency.
std::vector<Eigen::VectorXcd> harmonic_amplitudes(const LinearTrain& train, const LiftHarmonics& lift, double omega) {
  const Eigen::Index n = train.K.rows();
  std::vector<Eigen::VectorXcd> X(lift.S.size(), Eigen::VectorXcd::Zero(n));
  for (std::size_t h = 1; h <= lift.S.size(); ++h) {
    if (lift.S[h - 1] == 0.0) continue;
    const double w = static_cast<double>(h) * omega;  // [rad/s]
    const Eigen::MatrixXcd Z =
        train.K.cast<Complex>() - (w * w) * train.M.cast<Complex>() + Complex(0.0, w) * train.C.cast<Complex>();
    const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(Z);
    const Eigen::VectorXcd input = train.k_in.cast<Complex>() + Complex(0.0, w) * train.c_in.cast<Complex>();
    X[h - 1] = lu.solve(input * lift.S[h - 1]);
  }
  return X;
}

/// One force over the revolution: F(θ) = mean + Re Σ_h phi[h−1] e^{ihθ} [N].
struct ForceSeries {
  double mean = 0.0;
  std::vector<Complex> phi;

  double operator()(double theta) const {
    const Complex step = std::polar(1.0, theta);
    Complex power = step;
    double value = mean;
    for (const Complex& c : phi) {
      value += (c * power).real();
      power *= step;
    }
    return value;
  }
  bool finite() const {
    return std::isfinite(mean) &&
           std::all_of(phi.begin(), phi.end(), [](Complex c) { return std::isfinite(std::abs(c)); });
  }
};

/// F = a·x + b·ẋ + e s + f ṡ + constant as a series in θ at cam speed ω (ẋ = ω dx/dθ).
ForceSeries force_series(const LinearForce& force, const Eigen::VectorXd& x_mean,
                         const std::vector<Eigen::VectorXcd>& X, const LiftHarmonics& lift, double omega) {
  ForceSeries series;
  series.mean = force.a.dot(x_mean) + force.e * lift.mean + force.constant;
  series.phi.resize(lift.S.size());
  for (std::size_t h = 1; h <= lift.S.size(); ++h) {
    const Complex iw(0.0, static_cast<double>(h) * omega);  // d/dt of e^{ihθ} [1/s]
    const Eigen::VectorXcd gain = force.a.cast<Complex>() + iw * force.b.cast<Complex>();
    series.phi[h - 1] = gain.cwiseProduct(X[h - 1]).sum() + (force.e + iw * force.f) * lift.S[h - 1];
  }
  return series;
}

/// min over θ of sign·F(θ) [N]: the best of a grid, refined by golden section
/// between its neighbours; −inf for a series that is not finite.
double smallest(const ForceSeries& force, double sign) {
  if (!force.finite()) return -kInf;
  if (force.phi.empty()) return sign * force.mean;
  const int angles = std::max(kMinAngles, kAnglesPerHarmonic * static_cast<int>(force.phi.size()));
  const double dtheta = kTwoPi / angles;
  auto g = [&](double theta) { return sign * force(theta); };
  double best = kInf;
  int best_i = 0;
  for (int i = 0; i < angles; ++i) {
    const double v = g(dtheta * i);
    if (v < best) best = v, best_i = i;
  }
  double a = dtheta * (best_i - 1), b = dtheta * (best_i + 1);
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  double x1 = b - r * (b - a), x2 = a + r * (b - a), g1 = g(x1), g2 = g(x2);
  for (int it = 0; it < 100 && b - a > 1e-13; ++it) {
    if (g1 < g2) {
      b = x2, x2 = x1, g2 = g1, x1 = b - r * (b - a), g1 = g(x1);
    } else {
      a = x1, x1 = x2, g1 = g2, x2 = a + r * (b - a), g2 = g(x2);
    }
  }
  return std::min({best, g1, g2, g(0.5 * (a + b))});
}

/// The cam speeds of the jump scan [rad/s]: equal steps up to ω_max and each
/// undamped natural frequency ω_n / h of a significant harmonic h below it
/// (a lightly damped resonance can dip between two steps).
std::vector<double> scan_speeds(const LinearTrain& train, const LiftHarmonics& lift, double omega_max) {
  std::vector<double> speeds;
  for (int j = 1; j <= kJumpScanSpeedSteps; ++j) speeds.push_back(omega_max * j / kJumpScanSpeedSteps);
  const Eigen::LLT<Eigen::MatrixXd> mass(train.M);
  double largest = 0.0;
  for (const Complex& s : lift.S) largest = std::max(largest, std::abs(s));
  if (mass.info() == Eigen::Success && largest > 0.0) {
    const Eigen::MatrixXd K_sym = 0.5 * (train.K + train.K.transpose());
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(K_sym, train.M, Eigen::EigenvaluesOnly);
    for (const double lambda : modes.eigenvalues()) {
      if (!(lambda > 0.0)) continue;
      for (std::size_t h = 1; h <= lift.S.size(); ++h) {
        const double w = std::sqrt(lambda) / static_cast<double>(h);  // [rad/s]
        if (std::abs(lift.S[h - 1]) >= kJumpScanSignificantHarmonic * largest && w < omega_max) speeds.push_back(w);
      }
    }
  }
  std::sort(speeds.begin(), speeds.end());
  return speeds;
}

}  // namespace

LiftHarmonics lift_harmonics(const MotionLaw& law, int harmonics) {
  if (harmonics < 0) throw std::invalid_argument("lift_harmonics: harmonics = " + std::to_string(harmonics) + " < 0");
  const int samples = std::max(kMinLiftSamples, kLiftSamplesPerHarmonic * harmonics);
  std::vector<double> s(samples);
  std::vector<Complex> twiddle(samples);  // e^{−2πik/N}
  double sum = 0.0;
  for (int j = 0; j < samples; ++j) {
    s[j] = law.eval(kTwoPi * j / samples).s;
    sum += s[j];
    twiddle[j] = std::polar(1.0, -kTwoPi * j / samples);
  }
  LiftHarmonics lift;
  lift.mean = sum / samples;
  lift.S.resize(harmonics);
  for (int h = 1; h <= harmonics; ++h) {
    Complex c = 0.0;
    for (int j = 0; j < samples; ++j) c += s[j] * twiddle[(static_cast<std::int64_t>(h) * j) % samples];
    lift.S[h - 1] = 2.0 * c / static_cast<double>(samples);  // both ±h of a real series
  }
  return lift;
}

TrainResponse linear_train_response(const LinearTrain& train, const LiftHarmonics& lift, double omega) {
  check_sizes(train);
  if (!(omega >= 0.0) || !std::isfinite(omega))
    throw std::invalid_argument("linear_train_response: omega = " + std::to_string(omega) + " rad/s");
  const Eigen::VectorXd x_mean = mean_state(train, lift);
  const std::vector<Eigen::VectorXcd> X = harmonic_amplitudes(train, lift, omega);
  TrainResponse out;
  for (const LinearForce& force : train.held)
    out.min_held.push_back(smallest(force_series(force, x_mean, X, lift, omega), 1.0));
  for (const LinearForce& force : train.peaks)
    out.max_peaks.push_back(-smallest(force_series(force, x_mean, X, lift, omega), -1.0));
  return out;
}

double linear_train_jump_speed(const LinearTrain& train, const LiftHarmonics& lift, double omega_max) {
  check_sizes(train);
  if (!(omega_max > 0.0) || !std::isfinite(omega_max))
    throw std::invalid_argument("linear_train_jump_speed: omega_max = " + std::to_string(omega_max) + " rad/s");
  const Eigen::VectorXd x_mean = mean_state(train, lift);
  if (train.held.empty()) return kInf;
  auto smallest_held = [&](double omega) {
    const std::vector<Eigen::VectorXcd> X = harmonic_amplitudes(train, lift, omega);
    double least = kInf;
    for (const LinearForce& force : train.held)
      least = std::min(least, smallest(force_series(force, x_mean, X, lift, omega), 1.0));
    return least;
  };
  if (!(smallest_held(0.0) > 0.0)) return 0.0;
  double lo = 0.0;  // the highest speed known to hold [rad/s]
  for (const double w : scan_speeds(train, lift, omega_max)) {
    if (smallest_held(w) > 0.0) {
      lo = w;
      continue;
    }
    double hi = w;
    while (hi - lo > kSpeedTolerance * hi) {
      const double mid = 0.5 * (lo + hi);
      (smallest_held(mid) > 0.0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  return kInf;
}

}  // namespace camdyn
