// A smooth planar curve r(u) in its body's frame, with u-derivatives to third
// order (docs/model.md §1): the one interface through which contact tracking sees
// a cam profile, whether synthesised from a motion law (a pitch curve or a
// contour) or fitted to measured contour points.
#pragma once

#include <Eigen/Core>

namespace camdyn {

/// A point of a planar curve and its derivatives with respect to the curve parameter.
struct CurvePoint {
  Eigen::Vector2d r, dr, d2r, d3r;
};

/// A closed curve, periodic in u with period 2π [rad] (the parameter need not
/// be the polar angle). Implementations are immutable and evaluate without
/// allocating, so they can be called from the ODE right-hand side.
class PeriodicCurve {
 public:
  virtual ~PeriodicCurve() = default;
  /// r(u) and its first three u-derivatives [m, m/rad, m/rad², m/rad³].
  virtual CurvePoint at(double u) const = 0;
};

}  // namespace camdyn
