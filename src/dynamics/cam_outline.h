// The cam's outline for plotting and export: its contour and, for a circle
// follower (roller, mushroom), the pitch curve the circle's centre runs on,
// both in the cam frame (the world frame at cam angle 0), sampled over one
// turn. Taken from the profile the contact is tracked against
// (Model::profile(), at distance Model::profile_offset from the circle's
// centre), moved along its normal (contact/profile_pair_tracking.h
// InwardOffsetProfile), so it is the cam the simulation sees.
#pragma once

#include <vector>

#include "dynamics/model.h"

namespace camdyn {

struct CamOutline {
  /// Profile parameter of each point [rad]: the cam angle at which that point
  /// is the contact for a cam synthesised from its law, the fitted contour's
  /// parameter for a cam given as a contour.
  std::vector<double> u;
  std::vector<double> contour_x, contour_y;  ///< the cam contour [m]
  std::vector<double> pitch_x, pitch_y;      ///< the circle's centre path [m]; empty for a flat face
};

/// `points` (≥ 3) points at u = 2πk/points, k = 0 … points − 1.
CamOutline cam_outline(const Model& model, int points);

}  // namespace camdyn
