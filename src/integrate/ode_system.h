// The interface an integrator sees: an ODE y' = f(t, y) and root functions
// g(t, y) whose sign changes are located as events.
#pragma once

namespace camdyn {

class OdeSystem {
 public:
  virtual ~OdeSystem() = default;
  virtual int size() const = 0;
  virtual int root_count() const = 0;
  /// Return 0 on success, > 0 for a recoverable failure (the step is retried
  /// smaller), < 0 for an unrecoverable one.
  virtual int rhs(double t, const double* y, double* y_dot) = 0;
  virtual int roots(double t, const double* y, double* g) = 0;
  /// Analytic Jacobian ∂f/∂y, column-major (J[i + n j] = ∂f_i/∂y_j); return
  /// -1 when the system has none (a finite-difference one is used instead).
  virtual int jacobian(double /*t*/, const double* /*y*/, double* /*J*/) { return -1; }
  virtual bool has_jacobian() const { return false; }
  /// Half-bandwidth b of ∂f/∂y (∂f_i/∂y_j = 0 for |i − j| > b) when a banded
  /// linear solver pays (a chain of lumped masses); −1: dense.
  virtual int bandwidth() const { return -1; }
  /// Forward sensitivities (CvodeIntegrator::enable_sensitivities): ṡ_j for
  /// the `count` columns s_j = ∂y/∂p_j at (t, y), each of size(): ∂f/∂y s_j
  /// plus whatever else drives them. Return as rhs(); −1 when the system has
  /// none.
  virtual int sensitivity_rhs(double /*t*/, const double* /*y*/, int /*count*/, const double* const* /*s*/,
                              double* const* /*s_dot*/) {
    return -1;
  }
};

/// Solver counters, accumulated over re-initialisations.
struct SolverCounters {
  long steps = 0;
  long rhs_evaluations = 0;  ///< including those of finite-difference Jacobians
  long error_test_failures = 0;
  long nonlinear_iterations = 0;
  long jacobian_evaluations = 0;
  long reinitialisations = 0;

  /// Adds the counts of another integration (a restart resets SUNDIALS' own).
  SolverCounters& operator+=(const SolverCounters& other) {
    steps += other.steps;
    rhs_evaluations += other.rhs_evaluations;
    error_test_failures += other.error_test_failures;
    nonlinear_iterations += other.nonlinear_iterations;
    jacobian_evaluations += other.jacobian_evaluations;
    reinitialisations += other.reinitialisations;
    return *this;
  }
};

}  // namespace camdyn
