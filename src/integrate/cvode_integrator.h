// SUNDIALS CVODES (6.4, SUNContext API) driven one internal step at a time,
// with root finding, quadratures and dense output. Every SUNDIALS return code
// is checked; a failure throws NumericalError with the solver's flag name,
// its message and the time reached.
#pragma once

#include <memory>
#include <string>

#include "integrate/ode_system.h"

namespace camdyn {

struct CvodeOptions {
  bool bdf = true;         ///< BDF (stiff) or Adams–Moulton
  double rtol = 1e-8;      ///< relative tolerance
  double atol = 1e-12;     ///< absolute tolerance of the state
  double quadrature_atol = 1e-12;  ///< absolute tolerance of the quadratures
  double max_step = 0.0;   ///< 0: unlimited [s]
  long max_steps_per_call = 100000;
};

class CvodeIntegrator {
 public:
  enum class Result { step, root, stop };

  CvodeIntegrator(OdeSystem& system, const CvodeOptions& options, double t0, const double* y0, const double* q0);
  ~CvodeIntegrator();
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  /// Takes one internal step towards t_stop (never past it). `root` when a
  /// root function changed sign: the integrator then stands at the root.
  Result step(double t_stop);
  /// Time the integrator stands at (the returned step end or root) [s].
  double time() const { return t_; }
  /// Start of the last internal step [s] (dense output is valid in [start, end]).
  double last_step_start() const { return t_prev_; }
  /// State at time(), after step().
  const double* state() const;
  /// Dense output of the state (k = 0) or its k-th derivative, t within the last step.
  void dense(double t, double* out) const;
  void dense_quadrature(double t, double* out) const;
  /// Which roots fired at the last `root` result: +1 rising, −1 falling, 0 none.
  void root_info(int* directions) const;
  /// Restarts at (t, y, q), e.g. after an event changed the right-hand side.
  void reinit(double t, const double* y, const double* q);
  SolverCounters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double t_ = 0.0, t_prev_ = 0.0;
};

}  // namespace camdyn
