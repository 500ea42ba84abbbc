// The event of a motion law as one curve: a clamped B-spline that replaces
// the law on a span [from, to] of cam angle (a whole valve lobe, nose
// included, between its lash ramps) while the rest of the law is kept bit
// for bit (docs/config.md `motion_law`, its field `event`; docs/optimize.md
// "The whole event as one curve"). At both joins the spline's first control points are
// set so that s, s', s'' and, from degree 4 on, s''' equal the kept law's
// there; the free control points in between are lift values [m] (or [rad]
// for an arm), not normalised, because an event that rises and returns has
// no lift of its own to normalise by.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/motion_law.h"

namespace camdyn {

/// The highest derivative an event spline of `degree` matches at each join:
/// s''' from degree 4 on, else s''.
int event_join_order(int degree);

/// The spline basis of an event on a given law: the knots, and the boundary
/// control points that join it to the kept law. The event's lift is
/// s(θ) = Σ c_i N_i(x), x = (θ − from) / (to − from), with c_0 … c_r and
/// c_{n−1−r} … c_{n−1} (r = join order) fixed by the joins and the `free`
/// control points c_{r+1} … c_{r+free} free.
struct EventSplineBasis {
  int degree = 5;
  int order = 3;                   ///< derivatives matched at each join
  int free = 0;                    ///< free control points
  double from = 0.0, to = 0.0;     ///< [rad], 0 ≤ from < to ≤ 2π
  std::vector<double> knots;       ///< clamped, uniform interior knots on [0, 1]
  std::vector<double> head, tail;  ///< c_0 … c_r and c_{n−1} … c_{n−1−r}

  int count() const { return free + 2 * (order + 1); }  ///< all control points n
  int first_free() const { return order + 1; }          ///< index of the first free one
  double span() const { return to - from; }             ///< β [rad]
  /// All n control points with the free ones set to `free_points`.
  std::vector<double> coefficients(const std::vector<double>& free_points) const;
};

/// The kept law's s, s', s'', s''' at a join: at `from` from the left (the
/// piece that ends there), at `to` from the right.
std::array<double, 4> join_values(const MotionLaw& law, double theta, bool from_left);

/// The basis of an event [from, to] [rad] of `law` with `free` free control
/// points of `degree`. Requires 0 ≤ from < to ≤ 2π, 3 ≤ degree ≤ 9, and
/// free + 2 (order + 1) ≥ degree + 1 (checked by the caller).
EventSplineBasis event_spline_basis(const MotionLaw& law, double from, double to, int degree, int free);

/// `law` with [from, to) replaced by the event spline of `basis` and free
/// control points `free_points`; every other angle evaluates exactly as in
/// `law` (its pieces clipped, MotionLaw::Piece::origin).
MotionLaw splice_event(const MotionLaw& law, const EventSplineBasis& basis, const std::vector<double>& free_points);

/// The index of the event's piece in a law made by splice_event.
std::size_t event_piece_index(const MotionLaw& spliced, const EventSplineBasis& basis);

}  // namespace camdyn
