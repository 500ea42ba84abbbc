// Shared checks for motion-law tests: config builders, continuity across a
// boundary, derivatives against finite differences, InputError paths.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "finite_difference.h"
#include "geometry/motion_law.h"
#include "tolerance.h"

namespace camdyn::test {

inline const std::string kConfigFile = "scene.json";
inline const std::string kLawPath = "mechanism.cam.motion_law";

/// A segment as a config writes it (law "" = none).
inline SegmentConfig segment(const std::string& type, const std::string& law, double end_deg,
                             std::optional<double> lift = std::nullopt) {
  SegmentConfig s;
  s.type = parse_enum<SegmentType>(type);
  s.law = law.empty() ? SegmentLaw::none : parse_enum<SegmentLaw>(law);
  s.end_deg = end_deg;
  s.lift = lift;
  return s;
}

inline SegmentConfig dwell(double end_deg) { return segment("dwell", "", end_deg); }

inline MotionLawConfig segments(std::vector<SegmentConfig> segs) {
  MotionLawConfig c;
  c.segments = std::move(segs);
  return c;
}

inline MotionLaw build(const MotionLawConfig& c) { return build_motion_law(c, kConfigFile, kLawPath); }

/// Largest |s'|, |s''|, |s'''| found on a dense grid (bounds for the continuity test).
struct RateBounds {
  double ds = 0.0, d2s = 0.0, d3s = 0.0;
};
inline RateBounds sampled_bounds(const MotionLaw& law) {
  RateBounds b;
  for (int i = 0; i < 36000; ++i) {
    const LawSample l = law.eval(2 * std::numbers::pi * i / 36000.0);
    b.ds = std::max(b.ds, std::abs(l.ds));
    b.d2s = std::max(b.d2s, std::abs(l.d2s));
    b.d3s = std::max(b.d3s, std::abs(l.d3s));
  }
  return b;
}

/// s, s', s'' continuous at θ_b: by the mean value theorem a continuous g
/// changes by at most 2δ·max|g'| between θ_b ± δ; a jump is far larger. The
/// bound is the sampled maximum with a factor 2 (the true maximum may lie
/// between samples) plus rounding of s (≈ ulps of the lift).
inline void expect_c2_at(const MotionLaw& law, double theta_b, const std::string& what) {
  constexpr double delta = 1e-7;  // [rad]
  const RateBounds b = sampled_bounds(law);
  const LawSample l = law.eval(theta_b - delta), r = law.eval(theta_b + delta);
  const double rounding = kRoundoff * std::max(law.max_s(), 1e-3);
  EXPECT_NEAR(l.s, r.s, 2 * delta * 2 * b.ds + rounding) << "s at " << what;
  EXPECT_NEAR(l.ds, r.ds, 2 * delta * 2 * b.d2s + rounding) << "s' at " << what;
  EXPECT_NEAR(l.d2s, r.d2s, 2 * delta * 2 * b.d3s + rounding) << "s'' at " << what;
}

/// s', s'', s''' against central differences at n points avoiding ±3h around `breaks` [rad].
inline void expect_derivatives_match_fd(const MotionLaw& law, const std::vector<double>& breaks, int n = 97) {
  constexpr double h = 1e-4;  // [rad], ≪ the shortest segment checked (≥ 30°)
  // Rounding is relative to the size of s, s', s'' over the law, not at the point.
  const RateBounds size = sampled_bounds(law);
  for (int i = 0; i < n; ++i) {
    const double th = 2 * std::numbers::pi * (i + 0.3) / n;
    if (std::any_of(breaks.begin(), breaks.end(), [&](double b) { return std::abs(th - b) < 3 * h; })) continue;
    const LawSample exact = law.eval(th);
    const auto d1 = central_difference([&](double t) { return law.eval(t).s; }, th, h, law.max_s());
    const auto d2 = central_difference([&](double t) { return law.eval(t).ds; }, th, h, size.ds);
    const auto d3 = central_difference([&](double t) { return law.eval(t).d2s; }, th, h, size.d2s);
    EXPECT_NEAR(exact.ds, d1.value, d1.tolerance) << "s' at θ = " << th;
    EXPECT_NEAR(exact.d2s, d2.value, d2.tolerance) << "s'' at θ = " << th;
    EXPECT_NEAR(exact.d3s, d3.value, d3.tolerance) << "s''' at θ = " << th;
  }
}

/// Builds the law and expects an InputError whose path is `path` and whose
/// reason contains `reason_part`.
inline void expect_input_error(const MotionLawConfig& c, const std::string& path, const std::string& reason_part = "") {
  try {
    build(c);
    ADD_FAILURE() << "no InputError, expected one at " << path;
  } catch (const InputError& e) {
    EXPECT_EQ(e.path(), path) << e.what();
    EXPECT_EQ(e.file(), kConfigFile) << e.what();
    EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
  }
}

}  // namespace camdyn::test
