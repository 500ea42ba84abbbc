// The Halton sequence (a low-discrepancy, space-filling design): its k-th
// point in base b is k's digits in base b mirrored about the radix point.
// Used for the starts of a multi-start search over a box (identify's
// solver.starts, the layout search), one prime base per dimension.
#pragma once

#include <array>

namespace camdyn::optim {

/// Bases for up to 16 dimensions.
inline constexpr std::array<int, 16> kHaltonBases = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53};

/// The k-th point (k ≥ 1) of the Halton sequence in base `base`, in (0, 1).
inline double halton(int k, int base) {
  double f = 1.0, x = 0.0;
  for (int i = k; i > 0; i /= base) {
    f /= base;
    x += f * (i % base);
  }
  return x;
}

}  // namespace camdyn::optim
