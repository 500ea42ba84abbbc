// Layout for packaging cams (docs/optimize.md, "Layout"): the base radius,
// a translating follower's offset, an oscillating one's pivot position and
// arm length as variables within the ranges `design.layout` gives, the cam's
// size (the largest radius of its contour) minimised against the pressure
// angle, curvature and undercut limits. Geometric only: no simulation, each
// evaluation one build of the cam's geometry (milliseconds).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/cam_roller.h"
#include "scene/scene.h"

namespace camdyn::optim {

/// `design.layout`: each given range [lower, upper] makes that field a variable.
struct LayoutConfig {
  std::optional<std::vector<double>> base_radius;  ///< [m]
  std::optional<std::vector<double>> offset;       ///< translating [m]
  std::optional<std::vector<double>> pivot_x;      ///< oscillating [m]
  std::optional<std::vector<double>> pivot_y;      ///< oscillating [m]
  std::optional<std::vector<double>> arm_length;   ///< oscillating [m]
  bool operator==(const LayoutConfig&) const = default;
};

/// The limits a layout must meet (absent: none).
struct LayoutLimits {
  std::optional<double> max_pressure_angle_deg;   ///< [deg]
  std::optional<double> min_radius_of_curvature;  ///< of the cam contour [m]
};

/// One layout evaluated.
struct LayoutPoint {
  std::vector<double> values;  ///< the variables, in LayoutResult::names order
  bool buildable = false;      ///< the cam could be made (no cusp, undercut or invalid geometry)
  std::string error;           ///< why not
  double cam_size = 0.0;       ///< largest radius of the cam contour [m]
  CamGeometryReport report;
  double violation = 0.0;  ///< sum of the limits' relative excesses (0: feasible)
  bool feasible() const { return buildable && violation == 0.0; }
};

struct LayoutResult {
  std::vector<std::string> names;  ///< dotted paths of the variables
  LayoutPoint baseline, best;
  SceneConfig scene;  ///< the baseline with the best layout
  long evaluations = 0;
  double run_time_s = 0.0;
};

/// Checks the ranges against the scene's follower; throws InputError naming
/// `design.layout.<field>`.
void check_layout(const SceneConfig& scene, const LayoutConfig& layout, const std::string& file);

/// Searches the layout: a Halton design over the ranges, then NLopt COBYLA
/// from the smallest feasible cam found (every return value checked).
LayoutResult design_layout(const SceneConfig& baseline, const LayoutConfig& layout, const LayoutLimits& limits,
                           const std::string& file);

}  // namespace camdyn::optim
