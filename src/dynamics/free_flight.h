// The follower's free flight in closed form (issue 15). While the contact is
// open, a follower driven by a constant-speed cam obeys a linear equation with
// constant coefficients,
//   M q̈ + c q̇ + k q = −(F₀ + M g)
// (spring, preload, damper, gravity; guide and pivot friction carry the
// contact's load and vanish with it; a roller's spin stays constant), whose
// exact solution is the exponential of a 2×2 system. FreeFlight gives that
// solution; FlightTrack follows the gap along it, without the integrator, and
// finds the landing: on intervals that the gap rigorously cannot close in
// (a bound on the closing speed from the cam's bounding circle), or else on
// short intervals checked with the cubic Hermite interpolant of the gap, the
// landing then refined by bracketing. The hybrid simulation
// (dynamics/simulation.cc) leaves the stiff integrator only the contact
// phases.
#pragma once
#include "dynamics/model.h"

namespace camdyn {

/// Whether the model's flight has the closed form: constant-speed drive, the
/// reduced pair form, follower forces with a linear part (follower_linear_parts;
/// none while an element without one is present) of non-negative stiffness,
/// and no state besides q, q̇, the pair parameter and the roller spin.
bool flight_has_closed_form(const Model& model);
/// The same with the follower forces' linear parts `linear` (follower_linear_parts(model)).
bool flight_has_closed_form(const Model& model, const std::optional<FollowerLinearParts>& linear);

/// q(t), q̇(t) of the free follower from a start (t₀, q₀, q̇₀), under the sum
/// of the follower forces' linear parts (F₀, k, c). Throws std::invalid_argument
/// for a model without the closed form's forces (flight_has_closed_form).
class FreeFlight {
 public:
  explicit FreeFlight(const Model& model);
  /// Under the linear part `linear` of the follower's forces.
  FreeFlight(const Model& model, const LinearPart& linear);
  void start(double t0, double q0, double v0);
  /// Position [m | rad] and rate at t ≥ t₀ [s].
  void at(double t, double& q, double& v) const;
  /// An upper bound of |q̇| over [t, t + h] from the state (q, v) at t [s].
  double speed_bound(double q, double v, double h) const;

 private:
  double c_half_ = 0.0;  // a = c / 2M [1/s], of the forces' linear part F₀ + k q + c q̇
  double omega2_ = 0.0;  // ω² = k / M [1/s²]
  double b2_ = 0.0;      // ω² − a² [1/s²]
  double load_ = 0.0;    // (F₀ + M g) / M [m/s² | rad/s²]
  double q_eq_ = 0.0;    // equilibrium −(F₀ + M g) / k, with a spring [m | rad]
  double t0_ = 0.0, q0_ = 0.0, v0_ = 0.0;
};

/// One point of a flight: the follower and the gap there.
struct FlightPoint {
  double t = 0.0;                    ///< [s]
  double q = 0.0, v = 0.0;           ///< follower coordinate and rate
  double u = 0.0;                    ///< pair parameter [rad]
  double gap = 0.0, gap_rate = 0.0;  ///< [m], [m/s]
  double damper_work = 0.0;          ///< ∫ c q̇² dt since the run's start [J]
  double separation = 0.0;           ///< ∫ g dt since the run's start [m s]
};

/// Follows one flight after another along the closed form. Allocates
/// nothing after construction.
class FlightTrack {
 public:
  explicit FlightTrack(const Model& model);

  /// Starts a flight at `p` (t, q, v, u, gap ≥ 0, the quadratures so far).
  void start(const FlightPoint& p);
  /// Advances by one interval, never past t_stop [s]. Returns whether the
  /// follower landed in it: the interval then ends at the landing (gap ≤ 0 by
  /// a rounding error at most). Returns false, with `ok` false, when the pair
  /// could not be found.
  bool advance(Workspace& ws, double t_stop, bool& ok);
  /// The last point reached, and the one before it.
  const FlightPoint& now() const { return b_; }
  const FlightPoint& before() const { return a_; }
  /// The flight at t in [before().t, now().t]: q, v, u, gap and the
  /// quadratures (the separation integral by the Hermite cubic between the
  /// interval's start and t). Returns false when the pair was not found.
  bool at(Workspace& ws, double t, FlightPoint& p);
  /// The largest gap over the last interval, from the Hermite cubic through
  /// its ends (accurate to the fourth power of the interval) [m].
  double largest_gap() const;
  long intervals() const { return intervals_; }  ///< since construction

 private:
  bool point(Workspace& ws, double t, double u_warm, FlightPoint& p);
  double damper_work(double ta, double tb) const;  ///< ∫ c q̇² dt over [ta, tb], c the linear part's [J]
  double safe_interval(const FlightPoint& p) const;
  bool refine_landing(Workspace& ws, FlightPoint lo, FlightPoint hi, FlightPoint& landing);

  const Model& model_;
  Model newton_;  // the model with Newton tracking: the pair from the follower's position
  FreeFlight flight_;
  double damping_ = 0.0;  // c of the forces' linear part [N s/m | N m s/rad]
  double r_max_ = 0.0;    // radius of the profile's bounding circle [m]
  double lever_ = 0.0;    // bound of |∂g/∂q| [m/m | m/rad]
  double h_near_ = 0.0;   // interval near the cam, checked by the Hermite cubic [s]
  double h_far_ = 0.0;    // longest interval [s]
  FlightPoint a_, b_;
  Evaluation ev_;
  long intervals_ = 0;
};

}  // namespace camdyn
