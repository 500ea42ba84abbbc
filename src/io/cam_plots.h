// The plots of the cam itself that every report with a cam shows (simulate,
// optimize): the cam and its follower drawn to scale (equal units per pixel on
// both axes), the pressure angle and the contour's radius of curvature
// against cam angle with the scene's limits, and the law's lift, velocity,
// acceleration and jerk (SVAJ) against cam angle, with units.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "io/report.h"
#include "scene/scene.h"

namespace camdyn {

/// One cam to draw, with its legend label.
struct CamDesign {
  std::string label;
  const Model* model = nullptr;  ///< not owned
};

/// Samples per revolution of the curves against cam angle (every 0.5°).
inline constexpr int kCamPlotSamples = 720;

/// The first design to scale in the world frame at cam angle `mark` [rad]
/// (mm, equal_axes): its contour, pitch curve (circle followers), base
/// circle, the follower in its place on the law (roller or mushroom circle,
/// or the flat face, with stem or arm) and the contact point; the contours of
/// the other designs overlaid, turned to the same angle.
Plot cam_layout_plot(const std::vector<CamDesign>& designs, double mark);

/// Pressure angle φ(θ) [deg] of each design, with ±limit lines when `limit_deg` is set.
Plot pressure_angle_plot(const std::vector<CamDesign>& designs, std::optional<double> limit_deg);

/// Signed radius of curvature ρ(θ) of each contour [mm] (> 0 convex), with
/// ±limit lines when `limit` [m] is set; the axis is clipped to a few cam
/// radii, since ρ runs off to infinity where the contour turns from convex to concave.
Plot curvature_plot(const std::vector<CamDesign>& designs, std::optional<double> limit);

/// Lift, velocity, acceleration and jerk of the law against cam angle: at
/// `rpm` in mm, m/s, m/s², m/s³ (oscillating: deg, rad/s, rad/s², rad/s³),
/// or per radian of cam angle when rpm = 0.
std::vector<Plot> svaj_plots(const Model& model, double rpm);

/// The cam plots of one scene (simulate's report): the layout at the angle of
/// the largest pressure angle, the pressure angle and radius of curvature
/// with `mechanism.cam.limits`, and the SVAJ at the scene's speed.
std::vector<Plot> cam_plots(const Model& model, const CamLimitsConfig& limits, double rpm);

}  // namespace camdyn
