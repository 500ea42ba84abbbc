// The rigid-model stage's limits that are not linear, for any follower
// (optim/optimize/rigid_design.h): the pressure angle of an arm, the radius of
// curvature and the Hertz contact pressure of offset followers and arms.
// Where SplineFamily has no pointwise form in (s, s', s'') it asks this
// probe: the quantities at the designed segments' sample angles come from the
// cam synthesised for the design (geometry/cam_synthesis.h), their
// derivatives in the control points by forward differences through the
// synthesis, and the check of a design is the dense one `validate` makes
// (check_cam's sampling; the pressure every 0.1°, on a train at the held
// train's grid angles).
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "dynamics/contact_stress.h"
#include "geometry/cam_synthesis.h"
#include "geometry/follower_geometry.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/jump_bound.h"
#include "optim/optimize/optimize_config.h"

namespace camdyn::optim {

/// One linear row over the control points: lower ≤ Σ terms ≤ upper.
struct LimitCut {
  std::vector<std::pair<int, double>> terms;  ///< (column, coefficient)
  double lower = -kLpInfinity, upper = kLpInfinity;
};

/// Which limits the probe holds (the others are linear rows or pointwise cuts of SplineFamily).
struct ProbedLimits {
  std::optional<double> max_pressure_angle_deg;   ///< [deg]
  std::optional<double> min_radius_of_curvature;  ///< of the contour, |ρ| [m]
  std::optional<double> max_contact_stress;       ///< [Pa], with `contact`
  std::optional<LineContact> contact;
  std::vector<double> omegas;  ///< speeds the pressure holds at [rad/s]
  /// On a follower train: the baseline model whose held train gives the
  /// pressure's force (dynamics/held_train_force.h), never the follower
  /// alone; null for one mass (the RigidFollower's force). Outlives the probe.
  const Model* held = nullptr;
  bool any() const { return max_pressure_angle_deg || min_radius_of_curvature || max_contact_stress; }
};

class RigidLimitProbe {
 public:
  /// `angles`: the designed segments' sample angles [rad]; `follower`: the
  /// rigid follower whose force the pressure uses.
  RigidLimitProbe(const DesignSpace& space, const FollowerGeometry& geometry, int direction,
                  const RigidFollower& follower, ProbedLimits limits, std::vector<double> angles);

  const ProbedLimits& limits() const { return limits_; }
  /// Whether the design with control points c breaks a limit anywhere on the
  /// revolution (false for a cam that cannot be synthesised: nothing to cut).
  bool broken(const std::vector<double>& c) const;
  /// Rows "quantity linearised at c0 within 0.2 % of its limit" at the
  /// samples where the quantity at c0 comes within a margin of the limit.
  std::vector<LimitCut> cuts(const std::vector<double>& c0) const;

 private:
  /// The probed quantities at every sample angle (pressure: at every speed),
  /// each as a ratio to its limit that must stay ≤ 1; empty for a cam that
  /// cannot be synthesised.
  std::vector<double> ratios(const std::vector<double>& c) const;
  /// On a train: the held train's Q [N | N m] of `law` at the grid angles, per speed; empty for one mass.
  std::vector<std::vector<double>> held_forces(const MotionLaw& law) const;
  /// On a train: whether the held train's pressure of `cam` breaks the limit at a grid angle.
  bool held_pressure_broken(const SynthesisedCam& cam) const;

  const DesignSpace& space_;
  FollowerGeometry geometry_;
  int direction_;
  RigidFollower follower_;
  ProbedLimits limits_;
  std::vector<double> angles_;  ///< [rad]
};

}  // namespace camdyn::optim
