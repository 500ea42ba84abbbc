// The plots of the cam itself that every report shows (every study's scene
// has a cam: simulate, optimize, periodic, jump_map, speed_limit, compare,
// convergence, identify): the cam and its follower drawn to scale (equal units per pixel on
// both axes), the pressure angle and the contour's radius of curvature
// against cam angle with the scene's limits, and the law's lift, velocity,
// acceleration and jerk (SVAJ) against cam angle, with units.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "output/report.h"
#include "scene/scene.h"

namespace camdyn {

/// One cam to draw, with its legend label.
struct CamDesign {
  std::string label;
  const Model* model = nullptr;         ///< not owned
  PlotRole role = PlotRole::automatic;  ///< e.g. baseline / optimised: the same look in every figure
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

/// Lift, velocity, acceleration and jerk of each design's law against cam
/// angle (one curve per design, labelled when there are several): at `rpm`
/// the lift in µm, mm or m as its size needs (output/plot_style.h), m/s, m/s², m/s³ (oscillating: deg, rad/s, rad/s²,
/// rad/s³), or per radian of cam angle when rpm = 0 (a report over several speeds).
std::vector<Plot> svaj_plots(const std::vector<CamDesign>& designs, double rpm);

/// The cam plots of one scene: the layout at the angle of the largest
/// pressure angle (a cam held still: at its initial angle), the pressure
/// angle and radius of curvature with `mechanism.cam.limits`, and the SVAJ
/// at `rpm` (0: per radian of cam angle). A non-empty `caption` (e.g. "base design: case 'a'") is added to
/// every title, for a report whose runs have more than one cam.
std::vector<Plot> cam_plots(const Model& model, const CamLimitsConfig& limits, double rpm,
                            const std::string& caption = "");

/// cam_plots of `scene`, its model built here (`file` names it in messages),
/// for the reports that keep the scene rather than its model.
std::vector<Plot> scene_cam_plots(const SceneConfig& scene, const std::string& file, double rpm,
                                  const std::string& caption = "");

}  // namespace camdyn
