// ARKODE's ARKStep as an explicit adaptive Runge–Kutta method ("arkode_erk",
// the default order-4 embedded pair) or a diagonally implicit one
// ("arkode_dirk", default order-4 SDIRK, dense direct linear solver with the
// analytic Jacobian when the system has one).
#pragma once

#include <memory>

#include "integrate/integrator.h"

namespace camdyn {

class ArkodeIntegrator final : public Integrator {
 public:
  ArkodeIntegrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0);
  ~ArkodeIntegrator() override;
  ArkodeIntegrator(const ArkodeIntegrator&) = delete;
  ArkodeIntegrator& operator=(const ArkodeIntegrator&) = delete;

  Result step(double t_stop) override;
  double time() const override { return t_; }
  double last_step_start() const override { return t_prev_; }
  const double* state() const override;
  void dense(double t, double* out) const override;
  void root_info(int* directions) const override;
  void reinit(double t, const double* y) override;
  SolverCounters counters() const override;
  long steps() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double t_ = 0.0, t_prev_ = 0.0;
};

}  // namespace camdyn
