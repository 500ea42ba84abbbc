// The classical fixed-step fourth-order Runge–Kutta method: the baseline a
// hand-written script would use. Dense output is the cubic Hermite
// interpolant of the step ends (fourth-order accurate, like the method);
// events are located on it (StepRootLocator).
#pragma once

#include <vector>

#include "integrate/integrator.h"
#include "integrate/step_root_locator.h"

namespace camdyn {

class Rk4Integrator final : public Integrator {
 public:
  Rk4Integrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0);

  Result step(double t_stop) override;
  double time() const override { return t_; }
  double last_step_start() const override { return t0_; }
  const double* state() const override { return y_.data(); }
  void dense(double t, double* out) const override;
  void root_info(int* directions) const override { roots_.directions(directions); }
  void reinit(double t, const double* y) override;
  SolverCounters counters() const override { return counters_; }

 private:
  void evaluate_rhs(double t, const std::vector<double>& y, std::vector<double>& f);
  void hermite(double t, std::vector<double>& out) const;

  OdeSystem& system_;
  int size_;
  double h_;
  double t_ = 0.0;              // current time (step end or root)
  double t0_ = 0.0, t1_ = 0.0;  // last step, over which the Hermite interpolant is valid
  std::vector<double> y_, f_;   // state and its derivative at t_
  std::vector<double> y0_, f0_, y1_, f1_, k_, stage_;
  mutable std::vector<double> scratch_;  // dense-output buffer
  StepRootLocator roots_;
  SolverCounters counters_;
};

}  // namespace camdyn
