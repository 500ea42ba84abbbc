#include "dynamics/held_train.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "common/constants.h"
#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/jump_speed_scan.h"
#include "dynamics/model.h"
#include "dynamics/train_jump_speed.h"

namespace camdyn {

namespace {

using Complex = std::complex<double>;

constexpr int kOversampling = 4;  ///< samples of a signal's DFT per grid angle
constexpr int kFewestHarmonics = 16;
constexpr std::size_t kCachedSpeeds = 64;  ///< responses kept (each holds angles × signals per quantity)

/// In-place radix-2 FFT of a power-of-two length: X_k = Σ_j x_j e^{sign 2πi jk/N}.
void fft(std::vector<Complex>& x, double sign) {
  const std::size_t n = x.size();
  // The N/2 roots e^{sign 2πi k/N}, made once per length and sign (per thread).
  thread_local std::map<std::pair<std::size_t, double>, std::vector<Complex>> tables;
  std::vector<Complex>& roots = tables[{n, sign}];
  if (roots.size() != n / 2) {
    roots.resize(n / 2);
    for (std::size_t k = 0; k < n / 2; ++k)
      roots[k] = std::polar(1.0, sign * kTwoPi * static_cast<double>(k) / static_cast<double>(n));
  }
  for (std::size_t i = 1, j = 0; i < n; ++i) {
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const std::size_t half = len / 2, stride = n / len;
    for (std::size_t i = 0; i < n; i += len) {
      for (std::size_t k = 0; k < half; ++k) {
        const Complex u = x[i + k], v = x[i + k + half] * roots[k * stride];
        x[i + k] = u + v;
        x[i + k + half] = u - v;
      }
    }
  }
}

bool power_of_two(int n) { return n >= 16 && (n & (n - 1)) == 0; }

/// A quantity from a force of the linear train.
HeldQuantity from_force(const LinearForce& f, HeldQuantity::Kind kind, int body) {
  HeldQuantity q;
  q.kind = kind;
  q.name = f.name;
  q.body = body;
  q.alpha = f.e;
  q.beta = f.f;
  q.a = f.a;
  q.b = f.b;
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
    pos.a[body.coordinate] = 1.0;
    vel.b[body.coordinate] = 1.0;
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
  const LinearTrain lt = linearised_train(model);
  HeldTrain held;
  held.M = lt.M;
  held.C = lt.C;
  held.K = lt.K;
  held.f0 = lt.f0;
  held.k_in = lt.k_in;
  held.c_in = lt.c_in;
  for (std::size_t i = 0; i < lt.held.size(); ++i)
    held.quantities.push_back(from_force(lt.held[i], i == 0 ? HeldQuantity::Kind::contact : HeldQuantity::Kind::link,
                                         i == 0 ? 0 : body_named(model, lt.held[i].name)));
  for (const LinearForce& f : lt.peaks)
    held.quantities.push_back(from_force(f, HeldQuantity::Kind::spring_end, body_named(model, f.name)));
  add_seat_quantities(model, static_cast<int>(lt.M.rows()), held);
  return held;
}

GridSignal grid_signal(const std::function<LawSample(double)>& f, int angles) {
  if (!power_of_two(angles))
    throw std::invalid_argument("grid_signal: angles = " + std::to_string(angles) + " is not a power of two ≥ 16");
  std::vector<LawSample> samples(static_cast<std::size_t>(grid_signal_samples(angles)));
  for (std::size_t j = 0; j < samples.size(); ++j)
    samples[j] = f(kTwoPi * static_cast<double>(j) / static_cast<double>(samples.size()));
  return grid_signal_of_samples(samples, angles);
}

int grid_signal_samples(int angles) { return kOversampling * angles; }

GridSignal grid_signal_of_samples(const std::vector<LawSample>& samples, int angles) {
  if (!power_of_two(angles) || static_cast<int>(samples.size()) != grid_signal_samples(angles))
    throw std::invalid_argument("grid_signal_of_samples: " + std::to_string(samples.size()) + " samples for " +
                                std::to_string(angles) + " angles");
  GridSignal g;
  std::vector<Complex> x(samples.size());
  for (std::size_t j = 0; j < samples.size(); ++j) {
    x[j] = samples[j].s;
    if (j % kOversampling == 0) {
      g.u.push_back(samples[j].s);
      g.du.push_back(samples[j].ds);
    }
  }
  fft(x, -1.0);
  const double n = static_cast<double>(samples.size());
  g.U.resize(static_cast<std::size_t>(angles / 2));
  g.U[0] = x[0] / n;
  for (std::size_t h = 1; h < g.U.size(); ++h) g.U[h] = 2.0 * x[h] / n;
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
  if (cache_.size() >= kCachedSpeeds) cache_.clear();  // a bisection moves on: keep memory bounded
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
  for (int k = 0; k < K; ++k) T[k][0] = m > 0 ? train_.quantities[static_cast<std::size_t>(k)].a.dot(y_per_s_) : 0.0;
  // The truncation estimate: the last octave's Σ |T U| of the worst
  // quantity and signal, over the largest Σ_h |T U| plus exact part of any.
  auto octave_tail = [&](int H) {
    double tail = 0.0, size = 1e-300;
    for (int k = 0; k < K; ++k) {
      const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
      for (int j = 0; j < J; ++j) {
        const GridSignal& g = signals_[static_cast<std::size_t>(j)];
        double last = 0.0, all = std::abs(T[k][0] * g.U[0]);
        for (int h = 1; h <= H; ++h) {
          const Complex tu = T[k][h] * g.U[h];
          const double v = std::abs(tu.real()) + std::abs(tu.imag());  // within √2 of |T U|: an estimate
          all += v;
          if (2 * h > H) last += v;
        }
        for (int i = 0; i < R; i += 8) all = std::max(all, std::abs(q.alpha * g.u[i] + q.beta * omega * g.du[i]));
        tail = std::max(tail, last);
        size = std::max(size, all);
      }
    }
    return tail / size;
  };
  int H = 0;
  if (m > 0) {
    const Eigen::MatrixXcd Kc = train_.K.cast<Complex>(), Mc = train_.M.cast<Complex>(), Cc = train_.C.cast<Complex>();
    for (int target = kFewestHarmonics;; target = std::min(2 * target, top)) {
      for (int h = H + 1; h <= target; ++h) {
        const double w = h * omega;  // [rad/s]
        const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(Kc - (w * w) * Mc + Complex(0.0, w) * Cc);
        const Eigen::VectorXcd X =
            lu.solve(train_.k_in.cast<Complex>() + Complex(0.0, w) * train_.c_in.cast<Complex>());
        for (int k = 0; k < K; ++k) {
          const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
          T[k][h] = (q.a.cast<Complex>() + Complex(0.0, w) * q.b.cast<Complex>()).cwiseProduct(X).sum();
        }
      }
      H = target;
      out.truncation = octave_tail(H);
      if (out.truncation <= tolerance_ || H == top) break;
    }
  }
  out.harmonics = H;
  out.fixed.assign(static_cast<std::size_t>(K), Eigen::VectorXd::Zero(R));
  out.per_signal.assign(static_cast<std::size_t>(K), Eigen::MatrixXd::Zero(R, J));
  // Two signals per transform: their spectra made Hermitian, the one plus i
  // times the other, so that the real and imaginary parts of the inverse are
  // the two responses.
  std::vector<Complex> spectrum(static_cast<std::size_t>(R));
  for (int k = 0; k < K; ++k) {
    const HeldQuantity& q = train_.quantities[static_cast<std::size_t>(k)];
    out.fixed[k].setConstant(q.constant + (m > 0 ? q.a.dot(y_static_) : 0.0));
    for (int j = 0; j < J; j += 2) {
      const int pair = std::min(2, J - j);
      std::fill(spectrum.begin(), spectrum.end(), Complex(0.0));
      for (int p = 0; p < pair; ++p) {
        const GridSignal& g = signals_[static_cast<std::size_t>(j) + static_cast<std::size_t>(p)];
        const Complex unit = p == 0 ? Complex(1.0, 0.0) : Complex(0.0, 1.0);
        for (int h = 1; h <= H; ++h) {
          const Complex y = 0.5 * T[k][h] * g.U[h];
          spectrum[h] += unit * y;
          spectrum[R - h] += unit * std::conj(y);
        }
      }
      if (H > 0) fft(spectrum, 1.0);
      for (int p = 0; p < pair; ++p) {
        const GridSignal& g = signals_[static_cast<std::size_t>(j) + static_cast<std::size_t>(p)];
        const double mean = (T[k][0] * g.U[0]).real();
        for (int i = 0; i < R; ++i)
          out.per_signal[k](i, j + p) =
              q.alpha * g.u[i] + q.beta * omega * g.du[i] + mean + (p == 0 ? spectrum[i].real() : spectrum[i].imag());
      }
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

std::vector<double> resonance_speeds(const HeldTrain& train, const GridSignal& law, double omega_max) {
  std::vector<double> speeds;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(0.5 * (train.K + train.K.transpose()), train.M,
                                                                        Eigen::EigenvaluesOnly);
  double largest = 0.0;
  for (std::size_t h = 1; h < law.U.size(); ++h) largest = std::max(largest, std::abs(law.U[h]));
  for (const double lambda : modes.eigenvalues())
    for (int h = 1; lambda > 0.0 && h < static_cast<int>(law.U.size()); ++h)
      if (std::abs(law.U[h]) >= kJumpScanSignificantHarmonic * largest && std::sqrt(lambda) / h < omega_max)
        speeds.push_back(std::sqrt(lambda) / h);
  return speeds;
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
  for (int j = 1; j <= kJumpScanSpeedSteps; ++j) speeds.push_back(omega_max * j / kJumpScanSpeedSteps);
  if (train.free_coordinates() > 0) {  // undamped natural frequencies over each harmonic: resonances dip
    for (const double w : resonance_speeds(train, law, omega_max)) speeds.push_back(w);
    std::sort(speeds.begin(), speeds.end());
  }
  double lo = 0.0;
  for (const double w : speeds) {
    // A study's wall time caps this scan too (a train of many lumps costs
    // seconds: common/study_budget.h); without a study there is no deadline.
    if (study_budget_exhausted()) throw NumericalError(study_budget_text() + " in the held train's jump-speed scan");
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
