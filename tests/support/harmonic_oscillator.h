// x'' = −ω² x as an OdeSystem (state x [m], v [m/s]): the contact vibration
// of the stiff undamped scene in its simplest form, for the integrators'
// tests. With `crossings` its one root function is x itself, whose zeros are
// at t = (k + ½) π / ω.
#pragma once

#include "integrate/ode_system.h"

namespace camdyn::test {

class HarmonicOscillator final : public OdeSystem {
 public:
  explicit HarmonicOscillator(double omega, bool crossings = false) : omega_(omega), crossings_(crossings) {}
  int size() const override { return 2; }
  int root_count() const override { return crossings_ ? 1 : 0; }
  int rhs(double /*t*/, const double* y, double* y_dot) override {
    y_dot[0] = y[1];
    y_dot[1] = -omega_ * omega_ * y[0];
    return 0;
  }
  int roots(double /*t*/, const double* y, double* g) override {
    if (crossings_) g[0] = y[0];
    return 0;
  }
  int jacobian(double /*t*/, const double* /*y*/, double* j) override {
    j[0] = 0.0, j[1] = -omega_ * omega_, j[2] = 1.0, j[3] = 0.0;
    return 0;
  }
  bool has_jacobian() const override { return true; }

 private:
  double omega_;  // [rad/s]
  bool crossings_;
};

}  // namespace camdyn::test
