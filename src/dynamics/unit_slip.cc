#include "dynamics/unit_slip.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "scene/follower_shape.h"

namespace camdyn {

namespace {

/// A length [m] as the plausibility warnings print it (three digits).
std::string length_text(double x) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", x);
  return buffer;
}

/// Whether `text` holds "inf" or "nan" (any case) as a word of its own, as
/// printed for a number that overflowed ("-inf N", "nan m").
bool names_non_finite(const std::string& text) {
  auto letter = [](char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0 || c == '_'; };
  for (std::size_t i = 0; i + 3 <= text.size(); ++i) {
    std::string word = text.substr(i, 3);
    for (char& c : word) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    const bool alone = (i == 0 || !letter(text[i - 1])) && (i + 3 == text.size() || !letter(text[i + 3]));
    if (alone && (word == "inf" || word == "nan")) return true;
  }
  return false;
}

}  // namespace

std::optional<PlausibilityWarning> unit_slip(const SceneConfig& scene) {
  const MechanismConfig& mech = scene.mechanism;
  auto slip = [](const std::string& field, const std::string& what, double value) {
    return PlausibilityWarning{"unit_slip", field,
                               what + " " + length_text(value) + " m is above " + length_text(kMaxPlausibleLength) +
                                   " m: did you give millimetres? Lengths are in metres"};
  };
  if (mech.cam.base_radius > kMaxPlausibleLength)
    return slip("mechanism.cam.base_radius", "base radius", mech.cam.base_radius);
  const MotionLawConfig& law = mech.cam.motion_law;
  for (std::size_t i = 0; i < law.segments.size(); ++i)
    if (law.segments[i].lift && *law.segments[i].lift > kMaxPlausibleLength)
      return slip("mechanism.cam.motion_law.segments[" + std::to_string(i) + "].lift", "lift", *law.segments[i].lift);
  if (law.spline)
    for (std::size_t i = 0; i < law.spline->lift.size(); ++i)
      if (std::abs(law.spline->lift[i]) > kMaxPlausibleLength)
        return slip("mechanism.cam.motion_law.spline.lift[" + std::to_string(i) + "]", "lift", law.spline->lift[i]);
  const ShapeConfig& shape = mech.follower.shape;
  const FollowerShapeTraits traits = follower_shape_traits(shape.type);
  if (traits.takes_radius() && shape.radius > kMaxPlausibleLength)
    return slip("mechanism.follower.shape.radius", std::string(traits.label) + " radius", shape.radius);
  if (traits.takes_face_width() && shape.face_width > kMaxPlausibleLength)
    return slip("mechanism.follower.shape.face_width", "face width", shape.face_width);
  return std::nullopt;
}

void rethrow_naming_unit_slip(const SceneConfig& scene, const std::string& file, const InputError& error) {
  const std::optional<PlausibilityWarning> slip = unit_slip(scene);
  if (!slip || slip->field == error.path()) throw error;
  // A slip so large that the failure downstream is in numbers that overflowed
  // (inf, nan) says nothing more: the slip alone is the cause.
  const std::string reason =
      names_non_finite(error.reason())
          ? slip->message
          : slip->message + " (building the cam then failed: " + error.path() + ": " + error.reason() + ")";
  throw InputError(error.file().empty() ? file : error.file(), slip->field, reason);
}

}  // namespace camdyn
