// Small text helpers for the messages of the cam checks (cam_roller.cc,
// cam_synthesis.cc): a short number, a cam angle in [0, 360) degrees, and a
// sibling config path.
#pragma once

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

namespace camdyn::check_text {

/// `v` with six significant digits.
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

/// Cam angle u [rad] as degrees in [0, 360).
inline double to_deg_0_360(double u) {
  double deg = std::fmod(u, 2.0 * std::numbers::pi) * (180.0 / std::numbers::pi);
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

/// `path` with its last component replaced: sibling("mechanism.cam", "follower.offset")
/// is "mechanism.follower.offset".
inline std::string sibling(const std::string& path, const std::string& name) {
  const auto dot = path.rfind('.');
  return dot == std::string::npos ? name : path.substr(0, dot + 1) + name;
}

}  // namespace camdyn::check_text
