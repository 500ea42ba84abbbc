// The rigid-model contact condition of a follower as linear
// constraints (docs/model.md §9), and the highest jump-free speed that ANY law
// with a segment's lift and duration can reach: the first half of an
// optimize study's certificate.
//
// On the rigid model the cam pushes the follower along its axis with
//   P(θ; ω) = M ω² s''(θ) + c ω s'(θ) + k s(θ) + F₀ + M g,
// and the normal contact force is P / cos φ ≥ P. So P ≥ P_min at every θ
// keeps the normal force at least P_min (exactly so for a flat face). P is
// linear in the lift s, so "some law with this lift and duration stays in
// contact at ω" is a linear programme over the lift sampled on a fine grid
// (s'' and s' by central differences, the lift held between the segment's
// end levels), and the highest such ω is found by bisection.
//
// Closed form for the undamped case, used by the tests: the best law jumps to
// its top speed at once and then decelerates as hard as the spring allows,
// u'' = −(k / M ω²) u with u = s + (F₀ + M g − P_min) / k, arriving at rest
// at the top; so β √(k / M) / ω = arccos(u_start / u_top).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/follower_forces.h"
#include "geometry/motion_law.h"
#include "optim/linear_program.h"

namespace camdyn {
struct Model;
}

namespace camdyn::optim {

/// The follower as the rigid model sees it (translating: N, kg, m): the sum
/// of its force elements' linear parts (dynamics/follower_forces.h).
struct RigidFollower {
  double mass = 0.0;       ///< M [kg]
  double stiffness = 0.0;  ///< k of every element [N/m]
  double preload = 0.0;    ///< F₀: spring force at s = 0 [N]
  double damping = 0.0;    ///< c of every element [N s/m]
  double weight = 0.0;     ///< F₀ of the other elements: M g, towards the cam [N]
  double min_force = 0.0;  ///< P_min: the contact force to keep [N], ≥ 0
  /// A follower train (optim/optimize/train_rows.h): a design jump-free up to
  /// ω is checked at ω k / n, k = 1 … n (its response is not monotone in ω); 0: one mass.
  int sampled_speeds = 0;

  /// P − P_min at one sample [N]: the margin against losing contact.
  double margin(double omega, const LawSample& s) const {
    return mass * omega * omega * s.d2s + damping * omega * s.ds + stiffness * s.s + preload + weight - min_force;
  }
  /// Coefficients of (s, s', s'') in P(ω), and the constant part of P − P_min.
  double coefficient_s() const { return stiffness; }
  double coefficient_ds(double omega) const { return damping * omega; }
  double coefficient_d2s(double omega) const { return mass * omega * omega; }
  double constant() const { return preload + weight - min_force; }
};

/// The rigid follower of a model, with P_min = `min_force` [N]. For an
/// oscillating arm the same form holds in the arm angle (M the arm inertia,
/// k and F₀ torsional, P the torque about the pivot [N m]); its min_force is
/// then the torque P_min · 1.2 · (largest lever ∂g/∂q of the baseline cam),
/// conservative (exact for P_min = 0). None, no rigid stage, when some
/// follower element has no linear part (dynamics/follower_forces.h kNoLinearPart).
std::optional<RigidFollower> rigid_follower(const Model& model, double min_force);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
std::optional<RigidFollower> rigid_follower(const Model& model, double min_force,
                                            const std::optional<FollowerLinearParts>& linear);

/// The speeds at which a design that is to be jump-free up to ω [rad/s] is
/// checked: ω itself; with a damper (whose term c ω s' is not monotone in ω)
/// also 1/8 … 7/8 of it; a train at its sampled speeds.
std::vector<double> check_speeds(double omega, const RigidFollower& follower);

/// The largest ω in (0, ω_cap] with feasible(ω), for a `feasible` that holds
/// on an interval (0, ω*]: bracketing from `omega_hint` [rad/s] by factors of
/// `growth` (> 1; a good hint with a growth near 1 saves solves) then
/// bisection to a relative width `rtol`. Returns 0 when feasible fails even
/// at ω → 0 (checked at omega_hint · 1e-6), and ω_cap when it still holds there.
double highest_feasible_speed(const std::function<bool(double)>& feasible, double omega_hint, double omega_cap,
                              double rtol = 1e-5, double growth = 2.0);

/// A law sampled once, `samples` intervals per piece with both ends, each
/// end taken from inside its own piece so that a jump at a piece boundary
/// counts on both sides; the margin at any ω is then a loop over numbers.
class SampledLaw {
 public:
  /// Every piece of `law`.
  explicit SampledLaw(const MotionLaw& law, int samples = 2000);
  /// Only the pieces `pieces` (indices into law.pieces()).
  SampledLaw(const MotionLaw& law, const std::vector<std::size_t>& pieces, int samples = 2000);

  /// Minimum of the margin P − P_min over the samples at every ω of `omegas`
  /// [N] (+inf without samples).
  double worst_margin(const RigidFollower& follower, const std::vector<double>& omegas) const;
  double worst_margin(const RigidFollower& follower, double omega) const {
    return worst_margin(follower, std::vector<double>{omega});
  }
  const std::vector<LawSample>& samples() const { return samples_; }

 private:
  std::vector<LawSample> samples_;
};

/// The any-law bound of one rise or return piece.
struct SegmentJumpBound {
  std::size_t piece = 0;  ///< index into law.pieces()
  double start_deg = 0.0, end_deg = 0.0;
  double lift = 0.0;   ///< signed [m]
  double omega = 0.0;  ///< highest jump-free speed of any law [rad/s] (inf: no limit found)
};

/// For each piece in `pieces` (rises and returns of `law`), the highest speed
/// at which some lift s(θ) between the piece's end levels, meeting the
/// neighbours with their slope, keeps P ≥ P_min: the LP of this file on
/// `grid` intervals, bisected to `rtol` from the closed form's value (exact
/// only without a damper, so only the starting bracket). Throws
/// NumericalError when CLP fails (not for an infeasible programme, which is
/// an answer).
std::vector<SegmentJumpBound> any_law_jump_bounds(const MotionLaw& law, const RigidFollower& follower,
                                                  const std::vector<std::size_t>& pieces, double omega_hint,
                                                  int grid = 600, double rtol = 1e-4);

/// The closed form of the file comment for an undamped rest-to-rest piece
/// from level s_start to s_end over β [rad]: the highest jump-free speed of
/// any law [rad/s] (0 when the spring cannot hold the follower even at the
/// top). Where the spring cannot hold it at the bottom (u_start < 0) the same
/// extremal holds (it accelerates there, at least at −λ² u); the dwell
/// before the piece is then what fails, which the caller checks.
double any_law_jump_speed_closed_form(const RigidFollower& follower, double s_start, double s_end, double beta);

}  // namespace camdyn::optim
