#include "integrate/rk4_integrator.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"

namespace camdyn {

Rk4Integrator::Rk4Integrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0)
    : system_(system), size_(system_.size()), h_(options.fixed_step), roots_(system, system.size()) {
  if (!(h_ > 0.0)) throw NumericalError("rk4 needs a fixed step > 0 (integrator.step)");
  for (auto* v : {&y_, &f_, &y0_, &f0_, &y1_, &f1_, &k_, &stage_, &scratch_}) v->assign(size_, 0.0);
  reinit(t0, y0);
  counters_.reinitialisations = 0;
}

void Rk4Integrator::evaluate_rhs(double t, const std::vector<double>& y, std::vector<double>& f) {
  ++counters_.rhs_evaluations;
  const int flag = system_.rhs(t, y.data(), f.data());
  if (flag != 0)
    throw NumericalError("rk4: the right-hand side failed (flag " + std::to_string(flag) +
                         ") at t = " + std::to_string(t) + " s; a fixed step cannot be retried smaller");
}

void Rk4Integrator::reinit(double t, const double* y) {
  std::copy(y, y + size_, y_.begin());
  t_ = t0_ = t1_ = t;
  evaluate_rhs(t, y_, f_);
  y0_ = y1_ = y_;
  f0_ = f1_ = f_;
  roots_.restart(t, y_.data());
  ++counters_.reinitialisations;
}

void Rk4Integrator::hermite(double t, std::vector<double>& out) const {
  const double h = t1_ - t0_;
  if (h <= 0.0) {
    out = y1_;
    return;
  }
  const double s = (t - t0_) / h, s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  for (int i = 0; i < size_; ++i) out[i] = h00 * y0_[i] + h10 * h * f0_[i] + h01 * y1_[i] + h11 * h * f1_[i];
}

Integrator::Result Rk4Integrator::step(double t_stop) {
  const double t0 = t_;
  const double h = std::min(h_, t_stop - t0);
  y0_ = y_;
  f0_ = f_;
  // Classical RK4.
  const std::vector<double>& k1 = f0_;
  for (int i = 0; i < size_; ++i) stage_[i] = y0_[i] + 0.5 * h * k1[i];
  evaluate_rhs(t0 + 0.5 * h, stage_, k_);
  for (int i = 0; i < size_; ++i) y1_[i] = y0_[i] + h / 6.0 * k1[i] + h / 3.0 * k_[i];  // accumulate
  for (int i = 0; i < size_; ++i) stage_[i] = y0_[i] + 0.5 * h * k_[i];
  evaluate_rhs(t0 + 0.5 * h, stage_, k_);
  for (int i = 0; i < size_; ++i) y1_[i] += h / 3.0 * k_[i];
  for (int i = 0; i < size_; ++i) stage_[i] = y0_[i] + h * k_[i];
  evaluate_rhs(t0 + h, stage_, k_);
  for (int i = 0; i < size_; ++i) y1_[i] += h / 6.0 * k_[i];
  const double t1 = (h == t_stop - t0) ? t_stop : t0 + h;
  evaluate_rhs(t1, y1_, f1_);
  t0_ = t0;
  t1_ = t1;
  ++counters_.steps;

  double t_root = 0.0;
  if (roots_.locate(*this, t0, t1, y1_.data(), t_root)) {
    hermite(t_root, y_);
    t_ = t_root;
    evaluate_rhs(t_, y_, f_);
    return Result::root;
  }
  y_ = y1_;
  f_ = f1_;
  t_ = t1;
  return t1 >= t_stop ? Result::stop : Result::step;
}

void Rk4Integrator::dense(double t, double* out) const {
  hermite(t, scratch_);
  std::copy(scratch_.begin(), scratch_.end(), out);
}

}  // namespace camdyn
