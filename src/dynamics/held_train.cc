#include "dynamics/held_train.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "dynamics/model.h"
#include "dynamics/train_jump_speed.h"

namespace camdyn {

namespace {

using Complex = std::complex<double>;

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kOversampling = 16;  ///< samples of a signal's DFT per grid angle
constexpr int kFewestHarmonics = 16;
constexpr int kSpeedSteps = 400;  ///< equal steps of the jump-speed scan
/// A harmonic whose |U_h| is below this share of the largest adds no resonance to the scan.
constexpr double kSignificantHarmonic = 1e-3;

/// In-place radix-2 FFT of a power-of-two length: X_k = Σ_j x_j e^{sign 2πi jk/N}.
void fft(std::vector<Complex>& x, double sign) {
  const std::size_t n = x.size();
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const Complex w_len = std::polar(1.0, sign * kTwoPi / static_cast<double>(len));
    for (std::size_t i = 0; i < n; i += len) {
      Complex w = 1.0;
      for (std::size_t k = 0; k < len / 2; ++k) {
        const Complex u = x[i + k], v = x[i + k + len / 2] * w;
        x[i + k] = u + v;
        x[i + k + len / 2] = u - v;
        w *= w_len;
      }
    }
  }
}

bool power_of_two(int n) { return n >= 16 && (n & (n - 1)) == 0; }

/// The part of quantity q that acts on the free coordinates, from a force of
/// the full linear train (coordinate 0 = the follower, prescribed).
HeldQuantity from_force(const LinearForce& f, HeldQuantity::Kind kind, int body) {
  HeldQuantity q;
  q.kind = kind;
  q.name = f.name;
  q.body = body;
  q.alpha = f.a[0];
  q.beta = f.b[0];
  const Eigen::Index m = f.a.size() - 1;
  q.a = f.a.tail(m);
  q.b = f.b.tail(m);
  q.constant = f.constant;
  return q;
}

/// Position and velocity of each body with a seat.
void add_seat_quantities(const Model& model, int m, HeldTrain& held) {
  for (std::size_t i = 0; i < model.train.bodies.size(); ++i) {
    const TrainBody& body = model.train.bodies[i];
    if (body.seat < 0) continue;
    HeldQuantity pos, vel;
    pos.kind = HeldQuantity::Kind::seat_position;
    vel.kind = HeldQuantity::Kind::seat_velocity;
    pos.name = vel.name = "seat " + body.name;
    pos.body = vel.body = static_cast<int>(i);
    pos.seat = model.train.elements[static_cast<std::size_t>(body.seat)].offset;
    pos.a = pos.b = vel.a = vel.b = Eigen::VectorXd::Zero(m);
    if (body.coordinate == 0) {
      pos.alpha = 1.0;
      vel.beta = 1.0;
    } else {
      pos.a[body.coordinate - 1] = 1.0;
      vel.b[body.coordinate - 1] = 1.0;
    }
    held.quantities.push_back(pos);
    held.quantities.push_back(vel);
  }
}

/// Index of the body whose force this is ("link valve" → the body named valve).
int body_named(const Model& model, const std::string& force_name) {
  for (std::size_t i = 0; i < model.train.bodies.size(); ++i) {
    const std::string& name = model.train.bodies[i].name;
    if (force_name.size() > name.size() && force_name.compare(force_name.size() - name.size(), name.size(), name) == 0)
      return static_cast<int>(i);
  }
  return 0;
}

}  // namespace

HeldTrain held_train(const Model& model) {
  const LinearTrain full = linear_train_without_contact(model);
  const Eigen::Index n = full.M.rows(), m = n - 1;
  HeldTrain held;
  held.M = full.M.bottomRightCorner(m, m);
  held.C = full.C.bottomRightCorner(m, m);
  held.K = full.K.bottomRightCorner(m, m);
  // Rows 1…: M_yy ÿ + C_yy ẏ + K_yy y = f0_y − K_y0 s − C_y0 ṡ (M is diagonal).
  held.f0 = full.f0.tail(m);
  held.k_in = -full.K.col(0).tail(m);
  held.c_in = -full.C.col(0).tail(m);
  // Row 0: the cam's force P = M₀₀ s̈ + C₀₀ ṡ + K₀₀ s + C_0y ẏ + K_0y y − f0₀.
  HeldQuantity contact;
  contact.name = "cam contact";
  contact.alpha = full.K(0, 0);
  contact.beta = full.C(0, 0);
  contact.gamma = full.M(0, 0);
  contact.a = full.K.row(0).tail(m).transpose();
  contact.b = full.C.row(0).tail(m).transpose();
  contact.constant = -full.f0[0];
  held.quantities.push_back(contact);
  for (const LinearForce& f : full.held)
    held.quantities.push_back(from_force(f, HeldQuantity::Kind::link, body_named(model, f.name)));
  for (const LinearForce& f : full.peaks)
    held.quantities.push_back(from_force(f, HeldQuantity::Kind::spring_end, body_named(model, f.name)));
  add_seat_quantities(model, static_cast<int>(m), held);
  return held;
}

GridSignal grid_signal(const std::function<LawSample(double)>& f, int angles) {
  if (!power_of_two(angles))
    throw std::invalid_argument("grid_signal: angles = " + std::to_string(angles) + " is not a power of two ≥ 16");
  GridSignal g;
  const int samples = kOversampling * angles;
  std::vector<Complex> x(static_cast<std::size_t>(samples));
  for (int j = 0; j < samples; ++j) {
    const LawSample s = f(kTwoPi * j / samples);
    x[static_cast<std::size_t>(j)] = s.s;
    if (j % kOversampling == 0) {
      g.u.push_back(s.s);
      g.du.push_back(s.ds);
      g.d2u.push_back(s.d2s);
    }
  }
  fft(x, -1.0);
  g.U.resize(static_cast<std::size_t>(angles / 2));
  g.U[0] = x[0] / static_cast<double>(samples);
  for (std::size_t h = 1; h < g.U.size(); ++h) g.U[h] = 2.0 * x[h] / static_cast<double>(samples);
  return g;
}

HeldTrainResponse::HeldTrainResponse(HeldTrain train, std::vector<GridSignal> signals, int angles, double tolerance)
    : train_(std::move(train)), signals_(std::move(signals)), angles_(angles), tolerance_(tolerance) {
  if (!power_of_two(angles_)) throw std::invalid_argument("HeldTrainResponse: angles is not a power of two ≥ 16");
  for (const GridSignal& s : signals_)
    if (static_cast<int>(s.u.size()) != angles_ || static_cast<int>(s.U.size()) != angles_ / 2)
      throw std::invalid_argument("HeldTrainResponse: a signal is not on the response grid");
  const int m = train_.free_coordinates();
  y_static_ = y_per_s_ = Eigen::VectorXd::Zero(m);
  if (m > 0) {
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(train_.K);
    if (!lu.isInvertible())
      throw std::invalid_argument("held train: K is singular (rank " + std::to_string(lu.rank()) + " of " +
                                  std::to_string(m) + "): a coordinate no spring or link holds");
    y_static_ = lu.solve(train_.f0);
    y_per_s_ = lu.solve(train_.k_in);
  }
}

const SpeedResponse& HeldTrainResponse::at(double omega) {
  const auto it = cache_.find(omega);
  if (it != cache_.end()) return it->second;
  return cache_.emplace(omega, compute(omega)).first->second;
}

SpeedResponse HeldTrainResponse::compute(double omega) const {
  if (!(omega >= 0.0) || !std::isfinite(omega))
    throw std::invalid_argument("held train response: omega = " + std::to_string(omega) + " rad/s");
  const int R = angles_, m = train_.free_coordinates(), K = static_cast<int>(train_.quantities.size());
  const int J = static_cast<int>(signals_.size()), top = R / 2 - 1;
  SpeedResponse out;
  out.omega = omega;
  // Transfer of each quantity's y part per unit lift harmonic: T_k(h) = (a + i hω b)·Z(hω)⁻¹ (k_in + i hω c_in).
  std::vector<std::vector<Complex>> T(static_cast<std::size_t>(K), std::vector<Complex>(top + 1, 0.0));
  for (int k = 0; k < K; ++k)
    T[k][0] = m > 0 ? train_.quantities[static_cast<std::size_t>(k)].a.dot(y_per_s_) : 0.0;
  // The rigid parts' scale, for the truncation estimate.
  double scale = 1e-300;
  for (int k = 0; k < K; ++k) {
    const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
    for (int j = 0; j < J; ++j)
      for (int i = 0; i < R; ++i)
        scale = std::max(scale, std::abs(q.alpha * signals_[j].u[i] + q.beta * omega * signals_[j].du[i] +
                                         q.gamma * omega * omega * signals_[j].d2u[i]));
  }
  auto octave_tail = [&](int from, int to) {  // Σ_{h ∈ (from, to]} |T U| over the worst quantity and signal
    double worst = 0.0;
    for (int k = 0; k < K; ++k)
      for (int j = 0; j < J; ++j) {
        double sum = 0.0;
        for (int h = from + 1; h <= to; ++h) sum += std::abs(T[k][h] * signals_[j].U[h]);
        worst = std::max(worst, sum);
      }
    return worst;
  };
  int H = 0;
  if (m > 0) {
    const Eigen::MatrixXcd Kc = train_.K.cast<Complex>(), Mc = train_.M.cast<Complex>(), Cc = train_.C.cast<Complex>();
    for (int target = kFewestHarmonics;; target = std::min(2 * target, top)) {
      for (int h = H + 1; h <= target; ++h) {
        const double w = h * omega;  // [rad/s]
        const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(Kc - (w * w) * Mc + Complex(0.0, w) * Cc);
        const Eigen::VectorXcd X = lu.solve(train_.k_in.cast<Complex>() + Complex(0.0, w) * train_.c_in.cast<Complex>());
        for (int k = 0; k < K; ++k) {
          const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
          T[k][h] = (q.a.cast<Complex>() + Complex(0.0, w) * q.b.cast<Complex>()).cwiseProduct(X).sum();
        }
      }
      H = target;
      out.truncation = octave_tail(H / 2, H) / scale;
      if (out.truncation <= tolerance_ || H == top) break;
    }
  }
  out.harmonics = H;
  out.fixed.assign(static_cast<std::size_t>(K), Eigen::VectorXd::Zero(R));
  out.per_signal.assign(static_cast<std::size_t>(K), Eigen::MatrixXd::Zero(R, J));
  std::vector<Complex> spectrum(static_cast<std::size_t>(R));
  for (int k = 0; k < K; ++k) {
    const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
    out.fixed[k].setConstant(q.constant + (m > 0 ? q.a.dot(y_static_) : 0.0));
    for (int j = 0; j < J; ++j) {
      const GridSignal& g = signals_[static_cast<std::size_t>(j)];
      std::fill(spectrum.begin(), spectrum.end(), Complex(0.0));
      for (int h = 1; h <= H; ++h) spectrum[h] = T[k][h] * g.U[h];
      if (H > 0) fft(spectrum, 1.0);
      const double mean = (T[k][0] * g.U[0]).real();
      for (int i = 0; i < R; ++i)
        out.per_signal[k](i, j) = q.alpha * g.u[i] + q.beta * omega * g.du[i] + q.gamma * omega * omega * g.d2u[i] +
                                  mean + spectrum[i].real();
    }
  }
  return out;
}

std::vector<Eigen::VectorXd> held_train_values(const HeldTrain& train, const GridSignal& signal, double omega,
                                               int* harmonics) {
  HeldTrainResponse response(train, {signal}, static_cast<int>(signal.u.size()));
  const SpeedResponse& r = response.at(omega);
  if (harmonics) *harmonics = r.harmonics;
  std::vector<Eigen::VectorXd> out;
  for (std::size_t k = 0; k < r.fixed.size(); ++k) out.push_back(r.fixed[k] + r.per_signal[k].col(0));
  return out;
}

double held_train_jump_speed(const HeldTrain& train, const GridSignal& law, double omega_max, double contact_floor,
                             double link_floor, double rtol) {
  HeldTrainResponse response(train, {law}, static_cast<int>(law.u.size()));
  auto least_margin = [&](double omega) {
    const SpeedResponse& r = response.at(omega);
    double least = kInf;
    for (std::size_t k = 0; k < r.fixed.size(); ++k) {
      const HeldQuantity& q = train.quantities[k];
      if (!q.held()) continue;
      const double floor = q.kind == HeldQuantity::Kind::contact ? contact_floor : link_floor;
      least = std::min(least, (r.fixed[k] + r.per_signal[k].col(0)).minCoeff() - floor);
    }
    return least;
  };
  if (!(least_margin(0.0) > 0.0)) return 0.0;
  std::vector<double> speeds;
  for (int j = 1; j <= kSpeedSteps; ++j) speeds.push_back(omega_max * j / kSpeedSteps);
  if (train.free_coordinates() > 0) {  // undamped natural frequencies over each harmonic: resonances dip
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(0.5 * (train.K + train.K.transpose()),
                                                                           train.M, Eigen::EigenvaluesOnly);
    double largest = 0.0;
    for (std::size_t h = 1; h < law.U.size(); ++h) largest = std::max(largest, std::abs(law.U[h]));
    for (const double lambda : modes.eigenvalues())
      for (int h = 1; lambda > 0.0 && h < static_cast<int>(law.U.size()); ++h)
        if (std::abs(law.U[h]) >= kSignificantHarmonic * largest && std::sqrt(lambda) / h < omega_max)
          speeds.push_back(std::sqrt(lambda) / h);
    std::sort(speeds.begin(), speeds.end());
  }
  double lo = 0.0;
  for (const double w : speeds) {
    if (least_margin(w) > 0.0) {
      lo = w;
      continue;
    }
    double hi = w;
    while (hi - lo > rtol * hi) {
      const double mid = 0.5 * (lo + hi);
      (least_margin(mid) > 0.0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  return kInf;
}

}  // namespace camdyn
