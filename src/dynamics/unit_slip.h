// The unit slip of a scene (docs/warnings.md): a length above 1 m, almost
// surely given in millimetres. Apart from the other plausibility checks
// (dynamics/plausibility.h, which run on a built model and its results):
// building the cam geometry (dynamics/cam_geometry.cc) names the slip when
// it fails, before any model exists.
#pragma once

#include <optional>
#include <string>

#include "common/errors.h"
#include "scene/scene.h"

namespace camdyn {

/// Lengths above this are almost surely given in millimetres [m].
inline constexpr double kMaxPlausibleLength = 1.0;

/// One warning of summary.json `warnings` and of the `warning:` lines.
struct PlausibilityWarning {
  std::string cause;    ///< a short word: "unit_slip", "pressure_angle", "contact_stiffness", "chatter", ...
  std::string field;    ///< the dotted config path to change ("" when it is the run as a whole)
  std::string message;  ///< what is wrong and what to change
};

/// The first length of the scene above 1 m (base radius, a segment's or a
/// spline's lift, a circle's radius, a face width): almost surely given in
/// millimetres. None when there is none.
std::optional<PlausibilityWarning> unit_slip(const SceneConfig& scene);

/// Rethrows `error` (raised while building the model) as an InputError that
/// names the unit slip when the scene has one, with the original reason
/// appended; otherwise rethrows it unchanged.
[[noreturn]] void rethrow_naming_unit_slip(const SceneConfig& scene, const std::string& file, const InputError& error);

}  // namespace camdyn
