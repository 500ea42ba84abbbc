// SUNDIALS CVODES (6.4, SUNContext API) driven one internal step at a time,
// with root finding and dense output. Every SUNDIALS return code
// is checked; a failure throws NumericalError with the solver's flag name,
// its message and the time reached.
#pragma once

#include <memory>
#include <string>

#include "integrate/integrator.h"

namespace camdyn {

/// CVODES BDF (options.method "cvode_bdf", dense direct linear solver with the
/// system's analytic Jacobian when it has one) or Adams–Moulton ("cvode_adams",
/// Newton iteration as well, the CVODES default).
class CvodeIntegrator final : public Integrator {
 public:
  CvodeIntegrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0);
  ~CvodeIntegrator() override;
  CvodeIntegrator(const CvodeIntegrator&) = delete;
  CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

  Result step(double t_stop) override;
  double time() const override { return t_; }
  double last_step_start() const override { return t_prev_; }
  const double* state() const override;
  void dense(double t, double* out) const override;
  void root_info(int* directions) const override;
  void reinit(double t, const double* y) override;
  SolverCounters counters() const override;
  long steps() const override;

  /// Forward sensitivities by CVODES' staggered corrector: `count` columns
  /// s_j = ∂y/∂p_j (column-major size() × count in `s0`), driven by the
  /// system's sensitivity_rhs and error-controlled like the state (CVODES'
  /// estimated tolerances: scale the columns like the state). Once, before
  /// the first step.
  void enable_sensitivities(int count, const double* s0);
  /// The sensitivities at time(), column-major size() × count.
  void sensitivities(double* s) const;
  /// Restarts at (t, y) with the sensitivities `s` (column-major), e.g. after
  /// an event made them jump.
  void reinit(double t, const double* y, const double* s);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double t_ = 0.0, t_prev_ = 0.0;
};

}  // namespace camdyn
