// The shear stress of a helical spring's wire (docs/model.md §12, "Spring
// stress"): τ = K_W 8 F D / (π d³) with the Wahl factor
// K_W = (4C − 1) / (4C − 4) + 0.615 / C, C = D / d, the spring index.
#pragma once

#include <numbers>

namespace camdyn {

/// τ / F [Pa/N] of a spring of wire diameter d and mean coil diameter D [m]
/// (D > d): the Wahl-corrected shear stress per newton of spring force.
inline double wahl_stress_per_newton(double wire_diameter, double mean_diameter) {
  const double d = wire_diameter, D = mean_diameter, C = D / d;
  const double wahl = (4.0 * C - 1.0) / (4.0 * C - 4.0) + 0.615 / C;
  return wahl * 8.0 * D / (std::numbers::pi * d * d * d);
}

}  // namespace camdyn
