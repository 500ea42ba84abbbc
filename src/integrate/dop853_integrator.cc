#include "integrate/dop853_integrator.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/errors.h"
#include "integrate/dop853_tables.h"

namespace camdyn {

namespace {

constexpr double kDop853Safety = 0.9;             // the step-size controller's safety factor
constexpr double kDop853LeastFactor = 1.0 / 3.0;  // bounds of h_new / h after an error test (Hairer's fac1, fac2)
constexpr double kDop853LargestFactor = 6.0;
constexpr double kDop853Exponent = 1.0 / 8.0;  // 1 / (order + 1), the error estimate being of order 7
constexpr int kDop853MostAttempts = 100;       // attempts at one step before the run gives up

std::string dop853_at(double t) { return " at t = " + std::to_string(t) + " s"; }

}  // namespace

Dop853Integrator::Dop853Integrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0)
    : system_(system),
      size_(system.size()),
      rtol_(options.rtol),
      atol_(options.atol),
      max_step_(options.max_step),
      roots_(system, system.size()) {
  for (auto* v : {&y_, &y0_, &y1_, &work_, &scratch_}) v->assign(size_, 0.0);
  k_.assign(static_cast<std::size_t>(dop853::kExtendedStages) * size_, 0.0);
  dense_.assign(static_cast<std::size_t>(dop853::kDensePower) * size_, 0.0);
  reinit(t0, y0);
  counters_.reinitialisations = 0;
}

int Dop853Integrator::evaluate_rhs(double t, const double* y, double* f) const {
  ++counters_.rhs_evaluations;
  const int flag = system_.rhs(t, y, f);
  if (flag < 0)
    throw NumericalError("dop853: the right-hand side failed (flag " + std::to_string(flag) + ")" + dop853_at(t));
  return flag;
}

void Dop853Integrator::stage_input(int s, const double* base, double h, double* w) const {
  for (int i = 0; i < size_; ++i) {
    double sum = 0.0;
    for (int j = 0; j < s; ++j) sum += dop853::kA[s][j] * stage(j)[i];
    w[i] = base[i] + h * sum;
  }
}

void Dop853Integrator::reinit(double t, const double* y) {
  std::copy(y, y + size_, y_.begin());
  y0_ = y1_ = y_;
  t_ = t0_ = t1_ = t;
  h_ = 0.0;
  fsal_ = false;
  dense_ready_ = false;
  roots_.restart(t, y_.data());
  ++counters_.reinitialisations;
}

// Hairer's starting step: the step over which an explicit Euler step's
// change, and the derivative's change over it, stay at 1 % of the tolerance.
double Dop853Integrator::initial_step() {
  const double* f0 = stage(0);
  double dnf = 0.0, dny = 0.0;
  for (int i = 0; i < size_; ++i) {
    const double sk = atol_ + rtol_ * std::abs(y_[i]);
    dnf += (f0[i] / sk) * (f0[i] / sk);
    dny += (y_[i] / sk) * (y_[i] / sk);
  }
  double h = (dnf <= 1e-10 || dny <= 1e-10) ? 1e-6 : 0.01 * std::sqrt(dny / dnf);  // [s]
  if (max_step_ > 0.0) h = std::min(h, max_step_);
  for (int i = 0; i < size_; ++i) work_[i] = y_[i] + h * f0[i];
  double* f1 = stage(1);
  if (evaluate_rhs(t_ + h, work_.data(), f1) != 0) return h;
  double der2 = 0.0;
  for (int i = 0; i < size_; ++i) {
    const double d = (f1[i] - f0[i]) / (atol_ + rtol_ * std::abs(y_[i]));
    der2 += d * d;
  }
  const double der12 = std::max(std::sqrt(der2) / h, std::sqrt(dnf));
  const double h1 = der12 <= 1e-15 ? std::max(1e-6, 1e-3 * h) : std::pow(0.01 / der12, kDop853Exponent);
  h = std::min(100.0 * h, h1);
  return max_step_ > 0.0 ? std::min(h, max_step_) : h;
}

double Dop853Integrator::attempt(double h) {
  const double* y = y_.data();
  double* w = work_.data();
  for (int s = 1; s < dop853::kStages; ++s) {
    stage_input(s, y, h, w);
    if (evaluate_rhs(t_ + dop853::kC[s] * h, w, stage(s)) != 0) return std::numeric_limits<double>::infinity();
  }
  for (int i = 0; i < size_; ++i) {
    double sum = 0.0;
    for (int j = 0; j < dop853::kStages; ++j) sum += dop853::kB[j] * stage(j)[i];
    y1_[i] = y[i] + h * sum;
  }
  if (evaluate_rhs(t_ + h, y1_.data(), stage(dop853::kStages)) != 0) return std::numeric_limits<double>::infinity();
  // Hairer's error: the order-5 estimate, kept from vanishing where the
  // order-3 one does not by the denominator.
  double err5 = 0.0, err3 = 0.0;
  for (int i = 0; i < size_; ++i) {
    double e5 = 0.0, e3 = 0.0;
    for (int j = 0; j <= dop853::kStages; ++j) {
      e5 += dop853::kE5[j] * stage(j)[i];
      e3 += dop853::kE3[j] * stage(j)[i];
    }
    const double sk = atol_ + rtol_ * std::max(std::abs(y[i]), std::abs(y1_[i]));
    err5 += (e5 / sk) * (e5 / sk);
    err3 += (e3 / sk) * (e3 / sk);
  }
  double deno = err5 + 0.01 * err3;
  if (deno <= 0.0) deno = 1.0;
  return std::abs(h) * err5 / std::sqrt(deno * size_);
}

void Dop853Integrator::prepare_dense() const {
  if (dense_ready_) return;
  const double h = t1_ - t0_;
  double* w = scratch_.data();
  for (int s = dop853::kStages + 1; s < dop853::kExtendedStages; ++s) {
    stage_input(s, y0_.data(), h, w);
    const int flag = evaluate_rhs(t0_ + dop853::kC[s] * h, w, stage(s));
    if (flag != 0)
      throw NumericalError("dop853: the right-hand side failed (flag " + std::to_string(flag) +
                           ") in the dense output" + dop853_at(t0_ + dop853::kC[s] * h));
  }
  const double* f0 = stage(0);
  const double* f1 = stage(dop853::kStages);
  double* F = dense_.data();
  const auto n = static_cast<std::size_t>(size_);
  for (std::size_t i = 0; i < n; ++i) {
    const double dy = y1_[i] - y0_[i];
    F[i] = dy;
    F[n + i] = h * f0[i] - dy;
    F[2 * n + i] = 2.0 * dy - h * (f1[i] + f0[i]);
    for (std::size_t r = 0; r < 4; ++r) {
      double sum = 0.0;
      for (int j = 0; j < dop853::kExtendedStages; ++j) sum += dop853::kD[r][j] * stage(j)[i];
      F[(3 + r) * n + i] = h * sum;
    }
  }
  dense_ready_ = true;
}

void Dop853Integrator::dense(double t, double* out) const {
  const double h = t1_ - t0_;
  if (h <= 0.0) {
    std::copy(y1_.begin(), y1_.end(), out);
    return;
  }
  prepare_dense();
  const double x = (t - t0_) / h, x1 = 1.0 - x;
  const auto n = static_cast<std::size_t>(size_);
  const double* F = dense_.data();
  for (std::size_t i = 0; i < n; ++i) {
    const double p = F[6 * n + i] * x + F[5 * n + i];
    const double q = (((p * x1 + F[4 * n + i]) * x + F[3 * n + i]) * x1 + F[2 * n + i]) * x + F[n + i];
    out[i] = y0_[i] + x * (F[i] + x1 * q);
  }
}

Integrator::Result Dop853Integrator::step(double t_stop) {
  // f at the start: the last step's end, or evaluated after a root or a restart.
  if (fsal_)
    std::copy(stage(dop853::kStages), stage(dop853::kStages) + size_, stage(0));
  else if (evaluate_rhs(t_, y_.data(), stage(0)) != 0)
    throw NumericalError("dop853: the right-hand side failed at a step's start" + dop853_at(t_));
  fsal_ = false;
  if (h_ <= 0.0) h_ = initial_step();
  bool rejected = false;
  double h = 0.0;
  bool clipped = false;
  for (int attempts = 0;; ++attempts) {
    h = max_step_ > 0.0 ? std::min(h_, max_step_) : h_;
    clipped = t_ + 1.01 * h >= t_stop;  // a step that would leave under 1 % of itself takes the rest too
    if (clipped) h = std::max(0.0, t_stop - t_);
    // The step falling to round-off is a failure, unless it is what is left
    // to t_stop (an event a hair before it).
    const bool too_small = !(h > 16.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(t_)));
    if ((too_small && !clipped) || attempts >= kDop853MostAttempts)
      throw NumericalError("dop853: the step fell to " + std::to_string(h) + " s after " + std::to_string(attempts) +
                           " failed attempts" + dop853_at(t_));
    const double err = attempt(h);
    if (err <= 1.0) {
      double factor = err > 0.0 ? kDop853Safety * std::pow(err, -kDop853Exponent) : kDop853LargestFactor;
      factor = std::clamp(factor, kDop853LeastFactor, kDop853LargestFactor);
      if (rejected) factor = std::min(factor, 1.0);
      h_ = clipped && factor >= 1.0 ? std::max(h_, h * factor) : h * factor;
      break;
    }
    ++counters_.error_test_failures;
    rejected = true;
    h_ = std::isfinite(err) ? h * std::max(kDop853LeastFactor, kDop853Safety * std::pow(err, -kDop853Exponent))
                            : 0.25 * h;
  }
  ++counters_.steps;
  t0_ = t_;
  t1_ = clipped ? t_stop : t_ + h;
  y0_ = y_;
  dense_ready_ = false;

  double t_root = 0.0;
  if (roots_.locate(*this, t0_, t1_, y1_.data(), t_root)) {
    dense(t_root, y_.data());
    t_ = t_root;
    return Result::root;
  }
  y_ = y1_;
  t_ = t1_;
  fsal_ = true;
  return t_ >= t_stop ? Result::stop : Result::step;
}

}  // namespace camdyn
