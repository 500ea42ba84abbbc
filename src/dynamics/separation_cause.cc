#include "dynamics/separation_cause.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "dynamics/kinematic_lift.h"
#include "geometry/valve_timing.h"

namespace camdyn {

namespace {

/// Body `body`'s kinematic position for the law value s, held by every seat
/// before it but not by its own.
double free_position(const FollowerTrain& train, std::size_t body, double s) {
  double k = s;
  for (std::size_t i = 0; i < body; ++i) k = lift_step(train, i).carry(k);
  const LiftStep own = lift_step(train, body);
  return own.ratio * k - own.lash;
}

/// The law value in [lo, hi] where body `body` leaves its seat at p
/// (bisection on the monotone chain): hi when it never does.
double seat_lift_off(const FollowerTrain& train, std::size_t body, double p, double lo, double hi) {
  for (int iteration = 0; iteration < 200 && hi - lo > 1e-15 * (std::abs(lo) + std::abs(hi)); ++iteration) {
    const double mid = 0.5 * (lo + hi);
    (free_position(train, body, mid) > p ? hi : lo) = mid;
  }
  return hi;
}

/// `x` [m] in millimetres, to four significant digits.
std::string millimetres(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g mm", x * 1e3);
  return text;
}

}  // namespace

TakeUpWindow take_up_window(const FollowerTrain& train, const MotionLaw& law,
                            std::optional<std::pair<double, double>> ramp_end) {
  TakeUpWindow w;
  w.lift_off.fill(std::numeric_limits<double>::quiet_NaN());
  if (!train.has_seat()) return w;
  w.applies = true;
  const double lo = law.min_s(), hi = law.max_s();  // [m | rad]
  w.base = lo;
  w.max_lift = hi - lo;
  // A seat counts as reached within a millionth of the lift (a seat put at
  // the chain's rest position exactly is seated, not held open).
  const double tolerance = 1e-6 * std::max(w.max_lift, 1e-12);
  for (std::size_t i = 0; i < train.bodies.size(); ++i) {
    const std::optional<double> seat = lift_step(train, i).seat;
    if (!seat) continue;
    const double p = *seat;
    if (free_position(train, i, lo) > p + tolerance) {
      w.lift_off[i] = 0.0;
      if (w.held_open_body < 0) {
        w.held_open_body = static_cast<int>(i);
        w.held_open_by = free_position(train, i, lo) - p;
      }
      continue;
    }
    if (!(free_position(train, i, hi) > p + tolerance)) {
      w.lift_off[i] = std::numeric_limits<double>::infinity();
      if (w.never_lifted_body < 0) w.never_lifted_body = static_cast<int>(i);
      continue;
    }
    w.lift_off[i] = seat_lift_off(train, i, p, lo, hi) - lo;
    w.take_up = std::max(w.take_up, w.lift_off[i]);
  }
  const ValveTiming timing = valve_timing(law, {}, ramp_end);
  w.ramps_from_law = timing.opening_ramp && timing.closing_ramp;
  w.opening_end = w.ramps_from_law ? timing.opening_ramp->height : 2.0 * w.take_up;
  w.closing_end = w.ramps_from_law ? timing.closing_ramp->height : 2.0 * w.take_up;
  return w;
}

SeparationCause opening_cause(const TakeUpWindow& w, const LawSample& at, bool seated_since_take_up) {
  if (!w.applies) return SeparationCause::float_gap;
  const double lift = at.s - w.base;
  if (lift < w.take_up) return seated_since_take_up ? SeparationCause::seat_bounce : SeparationCause::take_up;
  return in_take_up_windows(w, at) ? SeparationCause::take_up : SeparationCause::float_gap;
}

std::string take_up_window_problem(const FollowerTrain& train, const TakeUpWindow& w) {
  if (w.never_lifted_body >= 0)
    return "the law never lifts the " + train.bodies[static_cast<std::size_t>(w.never_lifted_body)].name +
           " off its seat: the lash and seat heights, carried through the links' ratios, exceed the lift of " +
           millimetres(w.max_lift) + " at the cam";
  if (w.held_open_body >= 0)
    return "valve held open: on the base circle the " + train.bodies[static_cast<std::size_t>(w.held_open_body)].name +
           " is held " + millimetres(w.held_open_by) + " above its seat (its seat is below where the links put it)";
  return {};
}

}  // namespace camdyn
