// The exact rebound ratio of a hysteresis contact law (docs/model.md §10), the
// closed form the drop tests and the bouncing-ball orbit test check against.
#pragma once

#include <algorithm>
#include <cmath>

namespace camdyn::test {

/// The rebound ratio e* of F = K δ^n (1 + χ δ̇ / v₀) with v₀ the approach
/// speed: the root of ln((1 − χ e*)/(1 + χ)) + χ (1 + e*) = 0 in (0, 1],
/// by bisection to round-off.
inline double exact_rebound_ratio(double chi) {
  auto residual = [chi](double e) { return std::log((1 - chi * e) / (1 + chi)) + chi * (1 + e); };
  double lo = 0.0, hi = std::min(1.0, (1.0 - 1e-15) / chi);
  // residual(0) = χ − ln(1 + χ) > 0; residual decreases towards the upper end.
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (residual(mid) > 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace camdyn::test
