// Valve-train verdicts (docs/valvetrain.md "What each verdict means"): a gap
// that opens is not always a jump. With the lift law s(θ) at the cam and the
// train's lash, every separation (the cam contact's or a link's, with no body
// from it on resting on its seat) is one of
//   take-up bounce: it opens while the law is between the lash and the end of
//     the opening ramp (the law's ramp, or twice the lash where it has none),
//     or in the mirror window on the closing ramp before the body seats;
//   float: it opens while the law is above the ramps (flanks and nose): the
//     jump that speed limits are about;
//   seat bounce: a body leaves its seat after seating, with the law below the
//     height that lifts it (the cam on its base circle as that body sees it).
// A law whose ramps are too short for its lash (or have none) throws the
// follower off at the take-up into a train of rebounds that outlasts any
// window. A cam gap that opens above the window after an impact of such a
// train, where the law accelerates the train onto the cam (s'' > 0: no
// spring can lose it there) or separating at a quarter of that impact's
// approach speed or more (a rebound), is decided where it lands: a take-up
// bounce when it lands no harder than that impact or than twice its own
// separation speed (a flight the spring holds is a near-symmetric parabola
// in the cam's frame: it lands about as fast as it left), float when it
// lands harder (the cam outran the spring: it flew).
// TakeUpWindow holds the heights, made once per model from the law and the
// train's ratios, lashes and seats; SeparationCauses follows which cause each
// open gap has during a run.
#pragma once

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <utility>

#include "dynamics/follower_train.h"
#include "geometry/motion_law.h"
#include "scene/enum_names.h"

namespace camdyn {

/// Why a gap opened (events.csv `cause`).
/// `rebound`: a rebound of the take-up's train of impacts, decided where it lands.
enum class SeparationCause { none, take_up, float_gap, seat_bounce, rebound };

inline constexpr EnumName<SeparationCause> kSeparationCauseNames[] = {{SeparationCause::none, ""},
                                                                      {SeparationCause::take_up, "take_up"},
                                                                      {SeparationCause::float_gap, "float"},
                                                                      {SeparationCause::seat_bounce, "seat_bounce"},
                                                                      {SeparationCause::rebound, "rebound"}};
constexpr std::span<const EnumName<SeparationCause>> enum_names(SeparationCause) { return kSeparationCauseNames; }

/// Whether an open gap of cause `c` counts as float: every separation but a
/// take-up or seat bounce and a rebound not decided yet (one not classified
/// at all included: never hide flight).
constexpr bool floats(SeparationCause c) {
  return c != SeparationCause::take_up && c != SeparationCause::seat_bounce && c != SeparationCause::rebound;
}

/// A rebound separates at this share of its impact's approach speed or more.
inline constexpr double kReboundSpeedShare = 0.25;
/// A rebound that lands faster than this many times its separation speed
/// (and than its impact) flew: float.
inline constexpr double kReboundLandingFactor = 2.0;

/// The lift heights that classify a separation, all as cam lift above the
/// base circle (s − min s) [m | rad].
struct TakeUpWindow {
  bool applies = false;         ///< the train has a seat: take-up and seat bounce exist
  double base = 0.0;            ///< min s of the law [m | rad]
  double max_lift = 0.0;        ///< max s − min s [m | rad]
  double take_up = 0.0;         ///< the lift at which the last seated body leaves its seat (the lash at the cam)
  double opening_end = 0.0;     ///< the opening take-up window ends here (the ramp's end, or twice the lash)
  double closing_end = 0.0;     ///< the closing window starts here
  bool ramps_from_law = false;  ///< the windows' ends are the law's ramps (else twice the lash)
  /// Per body: the lift at which the law lifts it off its seat (+inf: never; NaN: no seat).
  std::array<double, TrainLimits::kMaxBodies> lift_off{};
  /// The first body the law cannot seat on the base circle (its kinematic
  /// position there above its seat: a valve held open), −1 when none.
  int held_open_body = -1;
  double held_open_by = 0.0;  ///< how far above its seat it is held [m | rad]
  /// The first body the law never lifts off its seat (lash or seat beyond the lift), −1 when none.
  int never_lifted_body = -1;
};

/// The windows of a train on `law`. `ramp_end` [rad], when given, names
/// where the opening ramp ends and the closing ramp starts
/// (`outputs.valvetrain.ramp_end_deg`); otherwise the law's own ramps
/// (geometry/valve_timing.h) or twice the lash.
TakeUpWindow take_up_window(const FollowerTrain& train, const MotionLaw& law,
                            std::optional<std::pair<double, double>> ramp_end = std::nullopt);

/// Whether the law sample `at` (s, ds) lies in a take-up window or below it:
/// its lift at most the opening window's end on the rising side, the
/// closing window's on the falling side. Always false without a seat.
inline bool in_take_up_windows(const TakeUpWindow& w, const LawSample& at) {
  return w.applies && at.s - w.base <= (at.ds >= 0.0 ? w.opening_end : w.closing_end);
}

/// The cause of a gap that opens at a law sample `at` (s, ds at the cam angle
/// there); `seated_since_take_up`: the train rested on a seat since the law
/// last fell below the take-up height (a gap opening below it is then a seat bounce).
SeparationCause opening_cause(const TakeUpWindow& w, const LawSample& at, bool seated_since_take_up);

/// Whether a body leaving its seat at law value `s` is a seat bounce (the law does not lift it there).
inline bool leaves_seat_as_bounce(const TakeUpWindow& w, int body, double s) {
  const double lift_off = w.lift_off[static_cast<std::size_t>(body)];
  return w.applies && s - w.base < lift_off;
}

/// The cause of each gap open during a run: the cam contact's and each
/// body's link; set where a gap opens, kept until it closes.
struct SeparationCauses {
  SeparationCause cam = SeparationCause::none;
  std::array<SeparationCause, TrainLimits::kMaxBodies> link{};
  std::array<bool, TrainLimits::kMaxBodies> seat_bouncing{};  ///< a body off its seat in a seat bounce
  /// The train rested on a seat since the law last fell below the take-up height.
  bool seated_since_take_up = true;
  /// The approach speed of the impact that began the cam's contact episode
  /// where it takes the lash up or ends a take-up bounce [m/s]; 0 otherwise.
  double chain_speed = 0.0;
  /// A rebound's separation in the run's events, and the decisions so far:
  /// how many, and the last one's cause (take_up or float_gap).
  std::size_t rebound_event = 0;
  double rebound_speed = 0.0;  ///< its separation speed [m/s]
  long decisions = 0;
  SeparationCause decided = SeparationCause::none;
};

/// "valve held open" / "never lifted" text of the windows' checks, empty when neither applies.
std::string take_up_window_problem(const FollowerTrain& train, const TakeUpWindow& w);

}  // namespace camdyn
