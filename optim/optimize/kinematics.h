// Kinematic figures of a motion law that an optimize study minimises or
// reports: peak velocity, acceleration and jerk per unit cam angle over the
// cycle, and per rise / return segment the dimensionless coefficients
// C_v = v_max β / h, C_a = a_max β² / h, C_j = j_max β³ / h (β the segment
// angle [rad], h its lift), which are what cam handbooks tabulate
// (cycloidal: C_a = 2π; 3-4-5 polynomial: 5.77; lower bound for any
// rest-to-rest rise: 4, the constant-acceleration law).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geometry/motion_law.h"
#include "io/config.h"

namespace camdyn::optim {

struct SegmentKinematics {
  std::size_t index = 0;  ///< into motion_law.segments
  std::string type;       ///< "rise" or "return"
  double start_deg = 0.0, end_deg = 0.0;
  double lift = 0.0;                      ///< |h| [m]
  double velocity_coefficient = 0.0;      ///< C_v [-]
  double acceleration_coefficient = 0.0;  ///< C_a [-]
  double jerk_coefficient = 0.0;          ///< C_j [-]
};

struct LawKinematics {
  double peak_velocity = 0.0;               ///< max |ds/dθ| [m/rad]
  double peak_acceleration = 0.0;           ///< max |d²s/dθ²| [m/rad²]
  double peak_jerk = 0.0;                   ///< max |d³s/dθ³| [m/rad³]
  std::vector<SegmentKinematics> segments;  ///< rise and return segments
};

/// Samples every piece of `law` (built from `segments`, one piece per
/// segment) at `samples` + 1 points including both ends, each end evaluated
/// from inside its own piece so that a jump at a segment boundary counts on
/// both sides.
LawKinematics law_kinematics(const MotionLaw& law, const std::vector<SegmentConfig>& segments, int samples = 4000);

}  // namespace camdyn::optim
