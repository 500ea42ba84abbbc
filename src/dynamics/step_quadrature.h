// The work quadratures of docs/model.md §7 (drive, damper, hysteresis and
// friction work, the separation integral), integrated beside the state one
// integrator step at a time by Simpson's rule: the integrand at the step's
// start, middle and end, each from an evaluation the run makes anyway. Inside
// a step the integral is that of the parabola through the three, so an
// output time between two steps reads the quadratures without a solver call.
//
// Simpson's error on a step of length h is h⁵ f⁗ / 2880: far below the
// state's own error at the steps its tolerance allows (Boole's rule on five
// points gives the same energy balance to three digits). The quadratures are
// not integrated by the integrator's own formula on purpose: a linear
// multistep method applied to the state and to q' = −dE/dt together keeps
// E(y) + q constant to first order whatever the state's error, so such a
// balance hides the integration error it is meant to show.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>

#include "dynamics/model.h"

namespace camdyn {

class StepQuadrature {
 public:
  using Values = std::array<double, Model::kQuadratures>;

  /// (Re)starts at t [s] with the integrals `q` and the integrand `f` there:
  /// at the run's start, and after an event or a flight changed the state.
  void start(double t, const Values& q, const Values& f) {
    t0_ = t1_ = t;
    q0_ = q1_ = q;
    f0_ = fm_ = f1_ = f;
  }

  /// The step from the last end to t1 [s]: `f_mid` at its middle, `f_end` at t1.
  void step(double t1, const Values& f_mid, const Values& f_end) {
    t0_ = t1_;
    q0_ = q1_;
    f0_ = f1_;
    fm_ = f_mid;
    f1_ = f_end;
    t1_ = t1;
    integral_to(1.0, q1_.data());
  }

  /// The integrals at t in [start of the last step, its end] [s]; at the end
  /// exactly the value the next step starts from.
  void at(double t, double* q) const {
    if (t >= t1_) {
      std::copy(q1_.begin(), q1_.end(), q);
      return;
    }
    const double h = t1_ - t0_;
    integral_to(h > 0.0 ? (t - t0_) / h : 0.0, q);
  }

 private:
  // q0 + ∫ of the parabola through (0, f0), (½, fm), (1, f1) from 0 to s,
  // s the fraction of the step; at s = 1 Simpson's h (f0 + 4 fm + f1) / 6.
  void integral_to(double s, double* q) const {
    const double h = t1_ - t0_;
    const double s2 = s * s, s3 = s2 * s;
    const double w0 = h * 2.0 * (s3 / 3.0 - 0.75 * s2 + 0.5 * s);
    const double wm = h * -4.0 * (s3 / 3.0 - 0.5 * s2);
    const double w1 = h * 2.0 * (s3 / 3.0 - 0.25 * s2);
    for (std::size_t i = 0; i < q0_.size(); ++i) q[i] = q0_[i] + w0 * f0_[i] + wm * fm_[i] + w1 * f1_[i];
  }

  double t0_ = 0.0, t1_ = 0.0;  // the last step [s]
  Values q0_{}, q1_{};          // the integrals at its ends
  Values f0_{}, fm_{}, f1_{};   // the integrand at its start, middle and end
};

}  // namespace camdyn
