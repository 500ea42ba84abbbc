// Valvetrain conventions on a motion law (docs/valvetrain.md): the duration
// at each checking height, the maximum lift and the lobe centre, and the
// ramps' heights and velocities. Lift is
// measured from the base circle (s − min s). Crossings of a checking height
// are roots of the law itself (bracketed on a fine grid, then bisected to
// rounding), not interpolated between samples. Everything here is in cam
// angle [rad]; crank angles are the cam angle times the crank ratio.
#pragma once

#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "geometry/motion_law.h"

namespace camdyn {

/// Where the lift is at or above one checking height.
struct CheckingHeightTiming {
  double height = 0.0;  ///< h_c above the base circle [m]
  /// Every cam-angle interval [opening, closing] with lift ≥ h_c [rad]: opening
  /// in [0, 2π), closing > opening (it may pass 2π when the event wraps).
  struct Interval {
    double opening = 0.0, closing = 0.0;
  };
  std::vector<Interval> intervals;
  double duration = 0.0;  ///< total cam angle with lift ≥ h_c [rad] (0: never reached, 2π: always)
  /// The longest interval (the event), and its middle in [0, 2π) [rad]; unset when the height is never reached.
  std::optional<Interval> event;
  double midpoint = 0.0;
};

/// The end of a ramp: where the opening ramp ends (the main lobe starts) or the closing ramp starts.
struct RampEnd {
  double angle = 0.0;     ///< cam angle [rad]
  double height = 0.0;    ///< lift above the base circle there [m]
  double velocity = 0.0;  ///< ds/dθ there [m/rad of cam]; the closing ramp's is < 0
};

struct ValveTiming {
  double max_lift = 0.0;  ///< max s − min s [m]
  /// The lobe centre: the cam angle of maximum lift [rad] in [0, 2π); for a
  /// law that dwells at full lift, the middle of the dwell.
  double lobe_centre = 0.0;
  std::vector<CheckingHeightTiming> heights;  ///< in the order asked
  std::optional<RampEnd> opening_ramp, closing_ramp;
};

/// The figures of `law` at the checking heights `heights` [m]. `ramp_end`
/// [rad], when given, names where the opening ramp ends and the closing ramp
/// starts; otherwise a law made of pieces has an opening ramp when its event
/// opens with two rise pieces or more in a row, the first rising less than
/// half the event's lift (the closing ramp likewise: the last of two return
/// pieces or more), and a law of one piece (spline, table) has none.
ValveTiming valve_timing(const MotionLaw& law, std::span<const double> heights,
                         std::optional<std::pair<double, double>> ramp_end = std::nullopt);

/// The lift above the base circle at cam angle θ [m].
double lift_above_base(const MotionLaw& law, double theta);

}  // namespace camdyn
