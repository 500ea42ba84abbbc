// ARKODE and the RK4 baseline have no separate quadratures: they integrate
// the quadratures as extra states appended to the system's state. This
// adaptor presents [y; q] as one ODE with the roots and Jacobian of y.
#pragma once

#include <cstddef>
#include <vector>

#include "integrate/ode_system.h"

namespace camdyn {

class AugmentedSystem final : public OdeSystem {
 public:
  explicit AugmentedSystem(OdeSystem& inner)
      : inner_(inner),
        n_(inner.size()),
        nq_(inner.quadrature_size()),
        jacobian_(static_cast<std::size_t>(n_) * static_cast<std::size_t>(n_)) {}

  int inner_size() const { return n_; }
  int size() const override { return n_ + nq_; }
  int quadrature_size() const override { return 0; }
  int root_count() const override { return inner_.root_count(); }
  int rhs(double t, const double* y, double* y_dot) override {
    const int flag = inner_.rhs(t, y, y_dot);
    if (flag != 0 || nq_ == 0) return flag;
    return inner_.quadrature(t, y, y_dot + n_);
  }
  int quadrature(double, const double*, double*) override { return 0; }
  int roots(double t, const double* y, double* g) override { return inner_.roots(t, y, g); }
  bool has_jacobian() const override { return inner_.has_jacobian(); }
  /// The state block is the inner system's Jacobian; the quadrature rows are
  /// left zero (an approximate Jacobian: q̇ does not depend on q, so the Newton
  /// iteration still converges, one iteration later at most).
  int jacobian(double t, const double* y, double* J) override {
    const int flag = inner_.jacobian(t, y, jacobian_.data());
    if (flag != 0) return flag;
    const int m = size();
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        J[i + m * j] = (i < n_ && j < n_) ? jacobian_[static_cast<std::size_t>(i + n_ * j)] : 0.0;
    return 0;
  }

 private:
  OdeSystem& inner_;
  int n_, nq_;
  std::vector<double> jacobian_;  // allocated once, here
};

}  // namespace camdyn
