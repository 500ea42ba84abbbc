// Valvetrain conventions on a motion law (docs/valvetrain.md): the duration
// at each checking height, the maximum lift and the lobe centre, and the
// ramps' heights and velocities, at the cam or at a body of the follower
// train (the valve). At the cam the lift is measured from the base circle
// (s − min s); at a body it is the law carried there (geometry/lift_chain.h:
// the links' ratios and lash, held at the seat) less the body's datum (its
// seat). Crossings of a checking height are roots of that lift itself
// (bracketed on a fine grid, then bisected to rounding), not interpolated
// between samples. Everything here is in cam angle [rad]; crank angles are
// the cam angle times the crank ratio.
#pragma once

#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "geometry/lift_chain.h"
#include "geometry/motion_law.h"

namespace camdyn {

/// Where the lift is at or above one checking height.
struct CheckingHeightTiming {
  double height = 0.0;  ///< h_c above the datum [m]
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
  double height = 0.0;    ///< lift above the datum there [m]
  double velocity = 0.0;  ///< d(lift)/dθ there [m/rad of cam]; the closing ramp's is < 0 (0 on the seat)
};

struct ValveTiming {
  /// Where the lift is measured from, in the body's coordinate [m]: the
  /// law's min s at the cam, LiftChain::datum at a body.
  double datum = 0.0;
  double max_lift = 0.0;  ///< the largest lift above the datum [m] (at the cam: max s − min s)
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
/// `chain`: the figures at the body it leads to (lifts, heights and ramp
/// velocities there, the ramps found on the law); empty: at the cam.
ValveTiming valve_timing(const MotionLaw& law, std::span<const double> heights,
                         std::optional<std::pair<double, double>> ramp_end = std::nullopt, const LiftChain& chain = {});

/// The lift above the base circle at cam angle θ [m].
double lift_above_base(const MotionLaw& law, double theta);

}  // namespace camdyn
