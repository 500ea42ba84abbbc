// The interface an integrator sees: an ODE y' = f(t, y) with quadratures
// q' = h(t, y) (integrated beside the state, not part of it) and root
// functions g(t, y) whose sign changes are located as events.
#pragma once

namespace camdyn {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  virtual int quadrature_size() const = 0;
  virtual int root_count() const = 0;
  /// Return 0 on success, > 0 for a recoverable failure (the step is retried
  /// smaller), < 0 for an unrecoverable one.
  virtual int rhs(double t, const double* y, double* y_dot) = 0;
  virtual int quadrature(double t, const double* y, double* q_dot) = 0;
  virtual int roots(double t, const double* y, double* g) = 0;
};

/// Solver counters, accumulated over re-initialisations.
struct SolverCounters {
  long steps = 0;
  long rhs_evaluations = 0;     ///< including those of finite-difference Jacobians
  long error_test_failures = 0;
  long nonlinear_iterations = 0;
  long jacobian_evaluations = 0;
  long reinitialisations = 0;
};

}  // namespace camdyn
