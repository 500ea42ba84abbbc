// Hertz's elastic contact between two bodies: the effective modulus and the
// peak pressure of a line contact (two cylinders, or a cylinder on a plane,
// pressed together along a width L). Johnson, Contact Mechanics (1985), §4.3:
// half-width b = √(4 P R / (π L E*)), peak pressure p₀ = 2P / (π b L)
// = √(P E* / (π L R)), with 1/R = κ₁ + κ₂ the sum of the two curvatures
// (convex positive, concave negative) and 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂.
// The peak shear stress lies below the surface, 0.30 p₀ at depth 0.78 b.
// A point contact (§4.2, two bodies of revolution, or a sphere on a plane)
// has p₀ = (6 P E*² / (π³ R²))^{1/3}.
#pragma once

#include <cmath>
#include <numbers>

namespace camdyn {

/// E* [Pa] of two elastic bodies (Young's moduli E [Pa], Poisson ratios ν [-]).
inline double effective_modulus(double E1, double nu1, double E2, double nu2) {
  return 1.0 / ((1.0 - nu1 * nu1) / E1 + (1.0 - nu2 * nu2) / E2);
}

/// Peak Hertz pressure p₀ [Pa] of a line contact carrying `force` [N] over
/// `width` [m], with effective modulus `e_star` [Pa] and curvature sum
/// κ₁ + κ₂ [1/m]. Zero without a compressive force or where the surfaces
/// conform (κ₁ + κ₂ ≤ 0: no Hertz contact).
inline double hertz_line_pressure(double force, double width, double e_star, double curvature_sum) {
  if (!(force > 0.0) || !(curvature_sum > 0.0)) return 0.0;
  return std::sqrt(force * e_star * curvature_sum / (std::numbers::pi * width));
}

/// Peak Hertz pressure p₀ [Pa] of a point contact carrying `force` [N] with
/// effective modulus `e_star` [Pa] and curvature sum κ₁ + κ₂ [1/m], taken
/// alike in both directions (the contact a stiffness from materials without
/// a width models). Zero as hertz_line_pressure is.
inline double hertz_point_pressure(double force, double e_star, double curvature_sum) {
  if (!(force > 0.0) || !(curvature_sum > 0.0)) return 0.0;
  constexpr double pi3 = std::numbers::pi * std::numbers::pi * std::numbers::pi;
  return std::cbrt(6.0 * force * e_star * e_star * curvature_sum * curvature_sum / pi3);
}

/// A contact's elastic data for its pressure: E* [Pa], and the width L [m] of
/// a line contact (0: a point contact).
struct HertzContact {
  double e_star = 0.0;
  double width = 0.0;
  bool line() const { return width > 0.0; }
};

/// Peak Hertz pressure p₀ [Pa] of `contact` carrying `force` [N] at the
/// curvature sum κ₁ + κ₂ [1/m]: line or point contact.
inline double hertz_pressure(const HertzContact& contact, double force, double curvature_sum) {
  return contact.line() ? hertz_line_pressure(force, contact.width, contact.e_star, curvature_sum)
                        : hertz_point_pressure(force, contact.e_star, curvature_sum);
}

}  // namespace camdyn
