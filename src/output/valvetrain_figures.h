// The valvetrain figures of `outputs.valvetrain` (docs/valvetrain.md):
// geometry/valve_timing.h on the scene's law, in cam
// and crank degrees, as summary.json's `valvetrain` object and as a table and
// a lift plot against crank angle in the report.
#pragma once

#include <optional>

#include "dynamics/model.h"
#include "geometry/valve_timing.h"
#include "io/config.h"
#include "output/report.h"

namespace camdyn {

/// The timing of the scene's law at its checking heights; unset without `outputs.valvetrain`.
std::optional<ValveTiming> scene_valve_timing(const SceneConfig& scene, const Model& model);

/// summary.json's `valvetrain` object (angles in degrees, lengths in metres,
/// velocities per radian of cam and in m/s at the run's cam speed); null
/// without `outputs.valvetrain`.
Json valvetrain_json(const SceneConfig& scene, const Model& model);

/// The report's "Valvetrain" table and lift-against-crank-angle plot; nothing
/// without `outputs.valvetrain`.
void add_valvetrain_report(const SceneConfig& scene, const Model& model, Report& report);

}  // namespace camdyn
