// Central finite differences with an error bound, for checking hand-written
// derivatives (docs/architecture.md, "Checking derivatives").
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace camdyn::test {

/// A finite-difference derivative and the largest error it can have.
struct FdEstimate {
  double value = 0.0;
  double tolerance = 0.0;
};

/// D(h) = (g(x + h) − g(x − h)) / 2h = g'(x) + g'''(x) h²/6 + O(h⁴).
/// Truncation: the h² term is estimated by Richardson extrapolation,
/// (D(2h) − D(h)) / 3, and allowed twice over (the O(h⁴) rest is far smaller
/// for the smooth functions checked, away from their breakpoints).
/// Rounding: each g carries at most kEvalUlps·ε·scale, where scale is the
/// larger of |g| nearby and `g_scale`, the typical size of g's terms (a sum
/// like Σ c_i N_i''(x) can cancel to far below its terms); D(h) divides it by h.
template <class G>
FdEstimate central_difference(const G& g, double x, double h, double g_scale = 0.0) {
  constexpr double kEvalUlps = 64.0;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  const double gp1 = g(x + h), gm1 = g(x - h), gp2 = g(x + 2 * h), gm2 = g(x - 2 * h);
  const double d1 = (gp1 - gm1) / (2 * h);
  const double d2 = (gp2 - gm2) / (4 * h);
  const double scale = std::max({std::abs(gp1), std::abs(gm1), std::abs(gp2), std::abs(gm2), g_scale});
  const double truncation = 2.0 * std::abs(d2 - d1) / 3.0;
  const double rounding = kEvalUlps * eps * scale / h;
  return {d1, truncation + rounding};
}

}  // namespace camdyn::test
