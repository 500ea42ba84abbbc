// Regularised Coulomb friction (docs/model.md §4): |F_t| ≤ μ F_n, opposing the
// slip velocity, smoothed near zero slip so that the ODE stays smooth.
#pragma once

#include <cmath>

#include "geometry/vec2.h"  // value()

namespace camdyn {

struct FrictionLaw {
  double mu = 0.0;                        ///< Coulomb coefficient [-]
  double regularization_velocity = 1e-4;  ///< v_reg [m/s] > 0
  bool linear_ramp = false;               ///< false: tanh(v/v_reg); true: clamp(v/v_reg, −1, 1)

  /// Friction coefficient actually acting at slip velocity v_s [m/s], in [−μ, μ],
  /// with the sign of v_s (the force is −coefficient · F_n along the slip direction).
  double coefficient(double slip) const { return coefficient_t(slip); }

  /// coefficient() for any scalar type S (double or the dual numbers of dynamics/dual.h).
  template <class S>
  S coefficient_t(const S& slip) const {
    using std::tanh;
    const S x = slip / regularization_velocity;
    const double xv = value(x);
    const S shape = linear_ramp ? (xv > 1.0 ? S(1.0) : (xv < -1.0 ? S(-1.0) : x)) : tanh(x);
    return mu * shape;
  }
};

}  // namespace camdyn
