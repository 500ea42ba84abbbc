// Closed curves with exact derivatives, shared by the geometry and contact tests.
#pragma once

#include <cmath>

#include "geometry/planar_curve.h"

namespace camdyn::test {

/// x = a cos u, y = b sin u (counterclockwise), semi-axes a, b [m].
class Ellipse final : public PeriodicCurve {
 public:
  Ellipse(double a, double b) : a_(a), b_(b) {}
  double a() const { return a_; }
  double b() const { return b_; }
  CurvePoint at(double u) const override {
    const double c = std::cos(u), s = std::sin(u);
    return {{a_ * c, b_ * s}, {-a_ * s, b_ * c}, {-a_ * c, -b_ * s}, {a_ * s, -b_ * c}};
  }

 private:
  double a_, b_;
};

}  // namespace camdyn::test
