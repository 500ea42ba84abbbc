// The units of the follower coordinate q (docs/model.md §5): metres for a
// translating follower, radians for an oscillating arm, with its rate, its
// acceleration and the generalised force along it. Every message, axis
// label, table header and plausibility ratio that prints q, or a quantity
// measured in q, takes its unit and its scale from here instead of writing
// "m" by hand, which an arm's radians then contradict. Quantities at the
// contact (gap, penetration, contact force, normal speed) are m, m/s and N
// for every follower and do not come from here.
#pragma once

#include <cstdio>
#include <string>
#include <string_view>

#include "dynamics/model.h"
#include "scene/scene.h"

namespace camdyn {

struct CoordinateUnits {
  bool oscillating = false;
  const char* position = "m";                       ///< q: "m" or "rad"
  const char* velocity = "m/s";                     ///< q̇: "m/s" or "rad/s"
  const char* acceleration = "m/s²";                ///< q̈: "m/s²" or "rad/s²"
  const char* force = "N";                          ///< generalised force along q: "N" or "N m"
  const char* position_name = "follower position";  ///< what q is called: or "arm angle"
  const char* velocity_name = "follower velocity";  ///< what q̇ is called: or "arm angular velocity"

  /// `label [unit]`: an axis label or a table header (docs/architecture.md, Reports).
  static std::string axis(std::string_view label, std::string_view unit) {
    return std::string(label) + " [" + std::string(unit) + "]";
  }
  /// `value` to `digits` significant digits, then its unit: "0.00638 rad".
  static std::string with_unit(double value, std::string_view unit, int digits = 3) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    return std::string(buffer) + " " + std::string(unit);
  }
  /// The unit of the motion law's n-th derivative per radian of cam angle,
  /// "m/rad^n" or "rad/rad^n" (n = 1 ... 3; `ascii`: "^2" instead of "²").
  std::string per_cam_radian(int n, bool ascii = false) const {
    static constexpr const char* kPowers[] = {"", "", "²", "³"};
    const std::string power = n <= 1 ? "" : ascii ? "^" + std::to_string(n) : kPowers[n < 4 ? n : 3];
    return std::string(position) + "/rad" + power;
  }
};

/// The units of a follower that translates or oscillates.
constexpr CoordinateUnits coordinate_units(FollowerMotion motion) {
  if (motion == FollowerMotion::oscillating)
    return CoordinateUnits{true, "rad", "rad/s", "rad/s²", "N m", "arm angle", "arm angular velocity"};
  return CoordinateUnits{};
}

/// The units of a built model's follower coordinate.
inline CoordinateUnits coordinate_units(const Model& model) { return coordinate_units(model.follower.motion); }

/// The units of a scene's follower coordinate (for outputs without a model).
inline CoordinateUnits coordinate_units(const SceneConfig& scene) {
  return coordinate_units(scene.mechanism.follower.motion);
}

/// The unit of a config field measured along q (docs/config.md, follower):
/// the spring, its preload, the damper, the initial position and velocity;
/// "" for any other dotted path (their units do not depend on the follower).
inline std::string coordinate_field_unit(std::string_view path, const CoordinateUnits& u) {
  if (path == "mechanism.follower.spring.stiffness") return u.oscillating ? "N m/rad" : "N/m";
  if (path == "mechanism.follower.spring.preload") return u.force;
  if (path == "mechanism.follower.damping") return u.oscillating ? "N m s/rad" : "N s/m";
  if (path == "mechanism.follower.initial.position") return u.position;
  if (path == "mechanism.follower.initial.velocity") return u.velocity;
  return "";
}

/// The motion law's total lift, max s − min s, in the unit of q [m or rad]:
/// the scale a position error or an excursion of q is judged against (an
/// arm's error in rad against its lift in rad, never against a lift in m).
inline double coordinate_lift(const Model& model) { return model.law->lift(); }

}  // namespace camdyn
