// The certificate of a lift-area design (docs/optimize.md "Lift area"): the
// largest ∫ s dθ that ANY lift over the same event [from, to] can have, with
// the same kept law around it (ramps, base circle), under the same linear
// constraints as the spline programme: contact force P ≥ P_min at the given
// speeds (rigid model, optim/optimize/jump_bound.h), s ≤ the lift cap, a flat
// face's |s'| ≤ face limit, r_b + s + s'' ≥ ρ_min and |s'''| ≤ J.
//
// The lift is free at every point of a fine grid (N intervals, spacing
// h = β / N): s'' by the three-point difference, s' (in P) by the central
// one, and s' (face) and s''' half a step after each point by the compact
// differences, the points just outside the event taken from the kept law
// (so the joins are held to s''' as the spline's are). Every
// smooth law that meets the constraints meets their differenced form up to
// O(h²), so the optimum is an upper bound on any law's area to that order:
// it converges from above as N grows, and the tests check that it does.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "geometry/motion_law.h"
#include "optim/optimize/jump_bound.h"

namespace camdyn::optim {

struct LobeLimits {
  std::vector<double> omegas;                                   ///< speeds where P ≥ P_min holds [rad/s]
  double max_lift = std::numeric_limits<double>::infinity();    ///< s cap [m]
  double face_limit = std::numeric_limits<double>::infinity();  ///< |s'| cap [m/rad]
  double pitch_height = 0.0;                                    ///< r_b of a flat face [m]
  double min_radius = 0.0;                                      ///< ρ_min of a flat face [m] (0: none)
  double max_jerk = 0.0;                                        ///< |s'''| cap [m/rad³] (0: none)
};

struct LobeBound {
  bool solved = false;
  std::string status;        ///< CLP's status ("optimal", "infeasible", ...)
  int grid = 0;              ///< N
  double area = 0.0;         ///< the largest ∫ s dθ over the event [m rad]
  std::vector<double> lift;  ///< the optimal lift at the N + 1 grid points [m]
};

/// The largest lift area over [from, to] [rad] of `law` (whose values
/// outside are kept) under `limits`, on `grid` intervals. Throws
/// NumericalError when CLP fails (not for an infeasible programme).
LobeBound lift_area_bound(const MotionLaw& law, double from, double to, const RigidFollower& follower,
                          const LobeLimits& limits, int grid);

/// ∫ s dθ over [from, to] of `law` [m rad], composite Simpson's rule on 4096 intervals.
double lift_area(const MotionLaw& law, double from, double to);

/// Highest s over [from, to] of `law` [m], sampled on the same 4096 intervals.
double highest_lift(const MotionLaw& law, double from, double to);

}  // namespace camdyn::optim
