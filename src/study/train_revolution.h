// The report's last revolution of a follower train (docs/valvetrain.md, "The
// train's last revolution"; docs/model.md §12): against crank angle (cam angle
// without `outputs.valvetrain`), the valve's lift, velocity and acceleration,
// dynamic against kinematic (the law carried to the valve through the links'
// ratios less lash, held by the seats: dynamics/kinematic_lift.h), every
// body's seat, link and spring force, each with the angles the verdict names
// (study/simulation_output.h VerdictAngles) marked at the same angles.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "output/report.h"
#include "output/valvetrain_figures.h"
#include "scene/scene.h"

namespace camdyn {

/// The x axis of the last revolution's train plots: crank degrees from the
/// crank's TDC where the scene has `outputs.valvetrain` (CrankScale), else cam
/// degrees.
struct RevolutionAxis {
  std::optional<CrankScale> crank;

  /// Where cam angle `cam_deg` (a running one too) falls on the axis, in [0, span()) [deg].
  double of(double cam_deg) const;
  /// One cam revolution on the axis: 360 r crank degrees, or 360 cam degrees [deg].
  double span() const;
  /// The axis label, naming which angle it is.
  std::string label() const;
};

/// The axis of `scene`'s last-revolution train plots.
RevolutionAxis revolution_axis(const SceneConfig& scene);

/// The series' column `name`: the follower's fixed columns
/// (`follower_position`, `follower_velocity`, `follower_acceleration`) or a
/// train column (`<body>_position`, `_velocity`, `_seat_force`, ...); null if
/// the series has none of that name.
const std::vector<double>* train_column(const TimeSeries& ts, const std::string& name);

/// Adds the last revolution's train plots to `report`: nothing for a model
/// without a train, an oscillating follower (lifts in rad), a cam held still,
/// or a series shorter than one cam revolution.
void add_train_revolution_plots(const SceneConfig& scene, const Model& model, const SimulationResult& result,
                                Report& report);

}  // namespace camdyn
