// Hertz line contact (contact/hertz_pressure.h) against Johnson's own route
// to the peak pressure: the half-width b = √(4 P R / (π L E*)) and
// p₀ = 2P / (π b L), and the elliptical pressure's integral, which must
// carry the load: (π/2) p₀ b L = P.
#include "contact/hertz_pressure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/constants.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::kRoundoff;  // a few operations on O(1) ratios

TEST(HertzPressure, EffectiveModulusOfSteelOnSteel) {
  // 1/E* = 2 (1 − 0.3²) / 210 GPa.
  EXPECT_NEAR(effective_modulus(210e9, 0.3, 210e9, 0.3) / (210e9 / (2.0 * 0.91)), 1.0, kRoundoff);
}

TEST(HertzPressure, LineContactMatchesTheHalfWidthRouteAndCarriesTheLoad) {
  const double e_star = effective_modulus(210e9, 0.3, 200e9, 0.29);  // [Pa]
  for (const double force : {10.0, 1e3, 5e4}) {                      // [N]
    for (const double radius : {0.005, 0.04, 1.0}) {                 // R of 1/R = κ₁ + κ₂ [m]
      const double width = 0.012;                                    // [m]
      const double b = std::sqrt(4.0 * force * radius / (kPi * width * e_star));
      const double p0 = hertz_line_pressure(force, width, e_star, 1.0 / radius);
      EXPECT_NEAR(p0 / (2.0 * force / (kPi * b * width)), 1.0, kRoundoff);
      EXPECT_NEAR(0.5 * kPi * p0 * b * width / force, 1.0, kRoundoff);
    }
  }
}

TEST(HertzPressure, NoPressureWithoutLoadOrWhereTheSurfacesConform) {
  EXPECT_EQ(hertz_line_pressure(0.0, 0.01, 1e11, 100.0), 0.0);
  EXPECT_EQ(hertz_line_pressure(-5.0, 0.01, 1e11, 100.0), 0.0);
  EXPECT_EQ(hertz_line_pressure(5.0, 0.01, 1e11, 0.0), 0.0);
  EXPECT_EQ(hertz_line_pressure(5.0, 0.01, 1e11, -3.0), 0.0);
}

}  // namespace
}  // namespace camdyn
