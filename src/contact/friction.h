// Regularised Coulomb friction (physics.md §3): |F_t| ≤ μ F_n, opposing the
// slip velocity, smoothed near zero slip so that the ODE stays smooth.
#pragma once

#include <cmath>

namespace camdyn {

struct FrictionLaw {
  double mu = 0.0;                  ///< Coulomb coefficient [-]
  double regularization_velocity = 1e-4;  ///< v_reg [m/s] > 0
  bool linear_ramp = false;         ///< false: tanh(v/v_reg); true: clamp(v/v_reg, −1, 1)

  /// Friction coefficient actually acting at slip velocity v_s [m/s], in [−μ, μ],
  /// with the sign of v_s (the force is −coefficient · F_n along the slip direction).
  double coefficient(double slip) const {
    const double x = slip / regularization_velocity;
    const double shape = linear_ramp ? (x > 1.0 ? 1.0 : (x < -1.0 ? -1.0 : x)) : std::tanh(x);
    return mu * shape;
  }
};

}  // namespace camdyn
