#include "optim/identify/finite_differences.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace camdyn::optim {

bool FitEvaluator::evaluate(const double* z, bool jacobian, bool central) {
  std::lock_guard<std::mutex> lock(mutex_);
  central = central || !problem_.solver.forward_differences();
  const bool same = !z_.empty() && std::equal(z_.begin(), z_.end(), z);
  if (same && (!ok_ || !jacobian || (!j_.empty() && (j_central_ || !central)))) return ok_;
  try {
    ok_ = compute(z, jacobian, same && ok_, central);
    j_central_ = central;
  } catch (...) {
    if (!exception_) exception_ = std::current_exception();
    ok_ = false;
  }
  z_.assign(z, z + p_);
  if (!ok_) j_.clear();
  return ok_;
}

bool FitEvaluator::compute(const double* z, bool jacobian, bool have_residuals, bool central) {
  std::vector<double> centre(p_);
  for (std::size_t i = 0; i < p_; ++i) centre[i] = to_value(problem_.parameters[i], z[i]);

  std::vector<std::vector<double>> points;
  if (!have_residuals) points.push_back(centre);
  std::vector<double> z_plus(p_), z_minus(p_);
  std::vector<int> plus_index(p_, -1), minus_index(p_, -1);
  if (jacobian) {
    const double h = problem_.solver.fd_relative_step;
    for (std::size_t i = 0; i < p_; ++i) {
      const FitParameter& par = problem_.parameters[i];
      const double step = par.log_scale ? h : h * std::max(std::abs(centre[i]), par.scale);
      const double lo = scaled_lower(par), hi = scaled_upper(par);
      z_plus[i] = z[i] + step;
      z_minus[i] = central ? z[i] - step : z[i];
      if (z_plus[i] > hi) {  // backward difference at the upper bound
        z_plus[i] = z[i];
        z_minus[i] = z[i] - step;
      }
      if (z_minus[i] < lo) z_minus[i] = z[i];  // forward difference at the lower bound
      if (z_plus[i] == z[i] && z_minus[i] == z[i]) {
        // Bounds closer than one step: use the whole interval.
        z_plus[i] = hi;
        z_minus[i] = lo;
      }
      auto add_point = [&](double zi, std::vector<int>& index) {
        if (zi == z[i]) return;  // the centre itself
        std::vector<double> point = centre;
        point[i] = to_value(par, zi);
        index[i] = static_cast<int>(points.size());
        points.push_back(std::move(point));
      };
      add_point(z_plus[i], plus_index);
      add_point(z_minus[i], minus_index);
    }
  }

  const std::vector<std::vector<FitRun>> runs = simulator_.run(points);
  for (const auto& point_runs : runs) {
    for (const FitRun& run : point_runs) {
      if (run.ok) continue;
      ++failures_;
      last_failure_ = run.error;
      if (run.input_error && !input_error_) input_error_ = run.input_error;
      return false;
    }
  }
  if (!have_residuals) {
    r_.assign(n_, 0.0);
    assembler_.assemble(runs[0], smoothing_, r_.data());
  }
  j_.clear();
  if (!jacobian) return true;

  j_.assign(n_ * p_, 0.0);
  std::vector<double> r_plus(n_), r_minus(n_);
  for (std::size_t i = 0; i < p_; ++i) {
    if (plus_index[i] >= 0)
      assembler_.assemble(runs[static_cast<std::size_t>(plus_index[i])], smoothing_, r_plus.data());
    else
      r_plus = r_;
    if (minus_index[i] >= 0)
      assembler_.assemble(runs[static_cast<std::size_t>(minus_index[i])], smoothing_, r_minus.data());
    else
      r_minus = r_;
    const double dz = z_plus[i] - z_minus[i];
    for (std::size_t row = 0; row < n_; ++row) j_[row * p_ + i] = (r_plus[row] - r_minus[row]) / dz;
  }
  return true;
}

}  // namespace camdyn::optim
