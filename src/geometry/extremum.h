// Largest value of a function over a closed (2π-periodic) parameter range,
// from samples refined by golden-section search: the extreme-value search of
// the cam geometry checks (pressure angle, curvature, cusps).
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

#include "common/constants.h"

namespace camdyn::geometry_detail {

struct Extremum {
  double u = 0.0, value = -std::numeric_limits<double>::infinity();
};

/// Largest g over the cyclic sorted samples `us` (values `gs`): the best few
/// local maxima are refined by golden-section search between their neighbours.
template <class G>
inline Extremum refine_max(const G& g, const std::vector<double>& us, const std::vector<double>& gs) {
  const std::size_t n = us.size();
  auto u_at = [&](std::ptrdiff_t i) {  // cyclic, continued across 2π
    const auto m = static_cast<std::ptrdiff_t>(n);
    const std::ptrdiff_t k = ((i % m) + m) % m;
    const std::ptrdiff_t wraps = (i - k) / m;  // exact: i − k is a multiple of m
    return us[k] + kTwoPi * static_cast<double>(wraps);
  };
  std::vector<std::size_t> peaks;
  for (std::size_t i = 0; i < n; ++i)
    if (gs[i] >= gs[(i + n - 1) % n] && gs[i] >= gs[(i + 1) % n]) peaks.push_back(i);
  std::sort(peaks.begin(), peaks.end(), [&](auto a, auto b) { return gs[a] > gs[b]; });
  constexpr std::size_t kRefined = 4;  // nearby rivals of the sampled maximum
  Extremum best;
  for (std::size_t r = 0; r < std::min(kRefined, peaks.size()); ++r) {
    const auto i = static_cast<std::ptrdiff_t>(peaks[r]);
    if (gs[peaks[r]] > best.value) best = {us[peaks[r]], gs[peaks[r]]};
    constexpr double kInvPhi = 0.6180339887498949;
    double a = u_at(i - 1), b = u_at(i + 1);
    double c = b - kInvPhi * (b - a), d = a + kInvPhi * (b - a);
    double gc = g(c), gd = g(d);
    for (int it = 0; it < 100 && b - a > 1e-13 * kTwoPi; ++it) {
      if (gc > gd) {  // the maximum is in [a, d]
        b = d;
        d = c;
        gd = gc;
        c = b - kInvPhi * (b - a);
        gc = g(c);
      } else {  // in [c, b]
        a = c;
        c = d;
        gc = gd;
        d = a + kInvPhi * (b - a);
        gd = g(d);
      }
    }
    if (gc > best.value) best = {c, gc};
    if (gd > best.value) best = {d, gd};
  }
  return best;
}

}  // namespace camdyn::geometry_detail
