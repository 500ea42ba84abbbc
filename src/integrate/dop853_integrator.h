// Dormand and Prince's explicit Runge–Kutta pair of order 8(5,3) with
// Hairer's step-size control and his dense output of order 7 ("dop853",
// docs/model.md §6), written for camdyn's small states: no vector library,
// every buffer made once, nothing allocated in a step. On a smooth motion
// whose vibration must be resolved anyway (an undamped contact) its large
// steps beat the multistep methods; on a stiff one (a damped contact, a
// stiffer spring) stability holds it to tiny steps, as any explicit method.
//
// A step evaluates the right-hand side 11 times (the 12th stage is the last
// step's end); the dense output three more times, once per step and only
// when asked. Events: the root functions' sign changes over a step are
// located on the dense output (StepRootLocator).
#pragma once

#include <vector>

#include "integrate/integrator.h"
#include "integrate/step_root_locator.h"

namespace camdyn {

class Dop853Integrator final : public Integrator {
 public:
  Dop853Integrator(OdeSystem& system, const IntegratorOptions& options, double t0, const double* y0);

  Result step(double t_stop) override;
  double time() const override { return t_; }
  double last_step_start() const override { return t0_; }
  const double* state() const override { return y_.data(); }
  void dense(double t, double* out) const override;
  void root_info(int* directions) const override { roots_.directions(directions); }
  void reinit(double t, const double* y) override;
  SolverCounters counters() const override { return counters_; }

 private:
  // f(t, y) into `f`; the flag of OdeSystem::rhs, a negative one thrown.
  // Const for the dense output's stages: the system and the counters are not
  // the integrator's state.
  int evaluate_rhs(double t, const double* y, double* f) const;
  // The state stage s is evaluated at: base + h Σ_{j<s} a_sj k_j, into w.
  void stage_input(int s, const double* base, double h, double* w) const;
  double initial_step();
  // One attempt from (t_, y_) over h: the new state in y1_, its derivative
  // in stage 12; returns the scaled error (≤ 1: accept), +inf when the
  // right-hand side failed recoverably.
  double attempt(double h);
  // The interpolant's coefficients for the last step (three more stages).
  void prepare_dense() const;
  double* stage(int i) const { return k_.data() + static_cast<std::size_t>(i) * size_; }

  OdeSystem& system_;
  const int size_;
  const double rtol_, atol_, max_step_;
  double h_ = 0.0;              // the next step to try [s]
  double t_ = 0.0;              // current time (step end or root)
  double t0_ = 0.0, t1_ = 0.0;  // last step, over which the dense output is valid
  std::vector<double> y_, y0_, y1_, work_;
  mutable std::vector<double> k_;      // the 16 stage derivatives of the last step
  mutable std::vector<double> dense_;  // the interpolant's 7 coefficient vectors
  mutable std::vector<double> scratch_;
  mutable bool dense_ready_ = false;
  bool fsal_ = false;  // stage 12 holds f(t_, y_): the last step's end, which starts the next
  StepRootLocator roots_;
  mutable SolverCounters counters_;  // the dense output's stages count too
};

}  // namespace camdyn
