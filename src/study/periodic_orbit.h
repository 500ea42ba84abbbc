// The steady state of a cam-follower at one speed: periodic orbits of the
// once-per-revolution Poincaré map (dynamics/poincare_map.h) by shooting, their
// Floquet multipliers, and, when no orbit up to the longest period asked for
// converges, the largest Lyapunov exponent of the motion.
//
// Shooting: Newton on R(x) = P^k(x) − x for k = 1, 2, …, started from the end
// of a short transient run. The Jacobian of P^k is taken by forward
// sensitivities through the events (dynamics/map_sensitivity.h: one run with
// the saltation matrices), checked against the map's own run; where they do
// not apply or cannot be trusted, by central differences through the event
// handling, each column two map evaluations, run in parallel. At a converged
// orbit that Jacobian (recomputed there) is the monodromy matrix; its eigenvalues are the Floquet multipliers, and the
// orbit is stable when they all lie inside the unit circle.
//
// Lyapunov exponent (study/lyapunov.cc): a tangent carried one revolution
// at a time and renormalised each revolution; λ is the mean of the log of its
// stretch per revolution (and per impact). The stretch is taken by forward
// sensitivities (the tangent-linear method, Müller 1995) or by a neighbour
// trajectory a small distance d₀ away (Benettin et al. 1980).
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dynamics/poincare_map.h"

namespace camdyn {

/// How the shooting takes the Jacobian of P^k (`periodic.jacobian`, docs/periodic.md):
/// `automatic` ("auto") by forward sensitivities on a map of at least
/// PeriodicOptions::sensitivity_min_coordinates coordinates where they can be trusted, else by
/// central differences; `sensitivity` the same, but a sensitivity run that cannot be
/// trusted stops the study (NumericalError) instead of falling back;
/// `finite_difference` always by central differences.
enum class JacobianMethod { automatic, sensitivity, finite_difference };

inline constexpr EnumName<JacobianMethod> kJacobianMethodNames[] = {
    {JacobianMethod::automatic, "auto"},
    {JacobianMethod::sensitivity, "sensitivity"},
    {JacobianMethod::finite_difference, "finite_difference"}};
constexpr std::span<const EnumName<JacobianMethod>> enum_names(JacobianMethod) { return kJacobianMethodNames; }

/// A state (a section point's coordinates) as an Eigen vector.
inline Eigen::VectorXd to_vector(const std::vector<double>& x) {
  return Eigen::Map<const Eigen::VectorXd>(x.data(), std::ssize(x));
}

struct PeriodicOptions {
  int max_period = 8;              ///< longest period k tried [revolutions]
  int min_period = 1;              ///< shortest period k tried [revolutions]
  int transient_revolutions = 4;   ///< run before the first Newton start
  int max_newton_iterations = 15;  ///< per period
  double tolerance = 1e-7;         ///< max |R_j| / scale_j at a converged orbit [-]
  int lyapunov_revolutions = 200;  ///< of the Lyapunov run when no stable orbit converged (0: none)
  double chaos_threshold = 0.01;   ///< λ per revolution above which the motion is called chaotic [-]
  /// When no stable orbit converged: the most revolutions followed (the
  /// Lyapunov run's included) waiting for the sampled states to repeat.
  int settle_revolutions = 1000;
  /// A stable orbit Newton converged to is the motion's steady state only
  /// when the motion from the search's start comes within the near radius
  /// (1e3 shooting tolerances, scaled) of one of its phases within this many
  /// revolutions; otherwise it is an unreached orbit, one that coexists with
  /// the motion (docs/periodic.md "Reached orbits"). 0: no check (where the
  /// claim is only that a stable orbit exists, as the jump map's
  /// continuation and its hysteresis check).
  int reach_revolutions = 200;
  /// The motion is expected to be aperiodic (the jump map's speed below
  /// reached no stable orbit): the Lyapunov run comes first. When it finds
  /// the motion chaotic, the motion is followed on to `reach_revolutions` to
  /// see whether it settles, and no orbit is sought otherwise: one Newton
  /// converged to from the start could not be the motion's. When it does
  /// not, the orbit search follows and the estimate is kept
  /// (docs/periodic.md "Lyapunov first").
  bool lyapunov_first = false;
  int threads = 1;
  JacobianMethod jacobian = JacobianMethod::automatic;
  /// The shortest map on which "auto" takes sensitivities: one sensitivity
  /// run costs about as much as the 2n runs of central differences at n ≈ 18
  /// (bench/periodic_bench.cc, BM_MapJacobian*); on shorter maps differences
  /// are cheaper.
  int sensitivity_min_coordinates = 16;
  /// Only stable orbits are sought (the jump map): Newton on P^k stops once
  /// its residual is below 1e3 times the tolerance and the Jacobian at its
  /// iterate is clearly unstable (largest |multiplier| above 1.2), instead
  /// of refining that orbit into the map's noise (docs/periodic.md
  /// "Unstable orbits").
  bool stable_orbits_only = false;
  /// Told what the search is doing (period tried, Newton residual).
  std::function<void(const std::string&)> log;
};

/// One Newton iterate of the shooting.
struct NewtonStep {
  int period = 0;
  int iteration = 0;
  double residual = 0.0;  ///< max |R_j| / scale_j [-]
};

/// A periodic orbit: x = P^k(x).
struct Orbit {
  int period = 0;             ///< k [revolutions]
  SectionPoint fixed_point;   ///< at the section t = 0 (mod kT)
  Eigen::MatrixXd monodromy;  ///< ∂P^k/∂x at the fixed point
  /// How `monodromy` was taken: sensitivity or finite_difference (never automatic).
  JacobianMethod jacobian_method = JacobianMethod::finite_difference;
  std::vector<std::complex<double>> multipliers;  ///< its eigenvalues, largest modulus first
  bool stable = false;                            ///< every |μ| < 1
  int newton_iterations = 0;
  double residual = 0.0;  ///< at the fixed point [-]
  double spectral_radius() const { return multipliers.empty() ? 0.0 : std::abs(multipliers.front()); }
};

struct LyapunovEstimate {
  double per_revolution = 0.0;  ///< λ [1/revolution]
  double per_impact = 0.0;      ///< λ per impact (0 without impacts)
  /// per_revolution's standard error by batch means
  /// (lyapunov_standard_error); nullopt with fewer than 20 revolutions.
  std::optional<double> standard_error;  ///< [1/revolution]
  long revolutions = 0;
  long impacts = 0;
  /// How the tangent was stretched: `sensitivity` (by forward sensitivities,
  /// revolution by revolution where they can be trusted) or
  /// `finite_difference` (by a neighbour trajectory every revolution).
  JacobianMethod method = JacobianMethod::finite_difference;
  long sensitivity_revolutions = 0;  ///< stretched by sensitivities
  /// Stretched by the neighbour because the sensitivity run could not be
  /// trusted there (0 when `method` is finite_difference).
  long fallback_revolutions = 0;
  std::string fallback_reason;  ///< the last such revolution's reason
  /// The first revolutions, whose stretches are left out of λ, of its standard
  /// error and of per_impact: the tangent turning from its start towards the
  /// most expanding direction (min(10, a tenth of the run)).
  int aligning_revolutions = 0;
  /// ln of each revolution's stretch [-], in order (the mean of all but the
  /// aligning ones is λ).
  std::vector<double> stretches;
  std::vector<std::vector<double>> section_points;  ///< the reference trajectory's x, once per revolution
  /// Whether those samples come back near where they have been
  /// (section_points_recur): a torus does, a slow drift does not.
  bool samples_recur = false;
  SectionPoint last;  ///< the reference trajectory's last section point
};

/// The standard error of the mean of `stretches` (ln of each revolution's
/// stretch) by batch means: 10 batches of consecutive revolutions (the last
/// `size % 10` left out), the batch means' sample standard deviation over
/// √10. Consecutive stretches are correlated; batches of them much less.
/// nullopt with fewer than 20 stretches (2 a batch).
std::optional<double> lyapunov_standard_error(std::span<const double> stretches);

/// Whether a motion's samples, once a revolution, return near where they
/// have been: every sample of the second half lies within twice the widest
/// nearest-neighbour spacing of the first half (scaled max-norm, `scales`)
/// of some first-half sample. A motion on a torus fills the same closed
/// curve in both halves, its later samples falling between the earlier
/// ones; a slow transient near a bifurcation drifts away by many spacings.
/// False with fewer than 8 samples.
bool section_points_recur(const std::vector<std::vector<double>>& points, std::span<const double> scales);

/// `chattering`: impacts accumulating onto a contact phase
/// (dynamics/chatter.h), periodic or not: never called chaotic.
enum class MotionKind { periodic, chaotic, quasi_periodic, unresolved, chattering };
inline constexpr EnumName<MotionKind> kMotionKindNames[] = {{MotionKind::periodic, "periodic"},
                                                            {MotionKind::chaotic, "chaotic"},
                                                            {MotionKind::quasi_periodic, "quasi_periodic"},
                                                            {MotionKind::unresolved, "unresolved"},
                                                            {MotionKind::chattering, "chattering"}};

/// The class a Lyapunov estimate supports, λ ± 2 standard errors against
/// ±`chaos_threshold` (per revolution): `chaotic` when all of it is above
/// the threshold, `quasi_periodic` when all of it is within, it reaches up
/// to 0 at least and the samples recur (LyapunovEstimate::samples_recur),
/// `unresolved` otherwise (contracting, even slowly as a stable orbit with a
/// multiplier near the unit circle does; drifting; or straddling a bound:
/// the estimate does not tell). Without a standard error (under 20
/// revolutions) λ alone decides against ±`chaos_threshold`.
MotionKind lyapunov_class(const LyapunovEstimate& e, double chaos_threshold);

/// Which evidence an `unresolved` class lacks, the first that fails:
/// `contracts` (λ + 2 standard errors below 0, or λ < 0 without one: a
/// stable orbit not yet reached), `drifts` (the samples do not recur: a slow
/// transient), `straddles` (the band reaches across ±`chaos_threshold`).
enum class UnresolvedReason { contracts, drifts, straddles };
UnresolvedReason unresolved_reason(const LyapunovEstimate& e);
constexpr std::span<const EnumName<MotionKind>> enum_names(MotionKind) { return kMotionKindNames; }

struct PeriodicAnalysis {
  MotionKind motion = MotionKind::unresolved;
  std::optional<Orbit> orbit;          ///< the stable orbit, when one converged
  std::vector<Orbit> unstable_orbits;  ///< orbits that converged but repel
  /// Stable orbits that converged but that the motion from the start did not
  /// reach within PeriodicOptions::reach_revolutions: they coexist with it.
  std::vector<Orbit> unreached_orbits;
  /// Revolutions of the motion from the start before it came near the
  /// stable orbit (0: it started there); -1 when not checked.
  long reached_after = -1;
  std::optional<LyapunovEstimate> lyapunov;
  std::vector<NewtonStep> newton;  ///< every iterate, in order
  SectionPoint transient_end;
  long revolutions = 0;  ///< integrated in all, transient included
  long map_evaluations = 0;
  long sensitivity_jacobians = 0;        ///< Jacobians of P^k taken by forward sensitivities
  long finite_difference_jacobians = 0;  ///< … and by central differences
  std::string jacobian_fallback;         ///< why the last sensitivity run was not used, if one was not
  std::string failure;                   ///< the last map evaluation that failed, if any
  /// Revolutions after the orbit search's start until the sampled states
  /// repeated (the orbit then shot from there); -1 when it was not needed.
  long settled_after = -1;
};

/// The orbit search from `start` (normally the end of a transient run).
PeriodicAnalysis find_periodic_orbit(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options);

/// The orbit search from `start`, and the Lyapunov run from there when no
/// stable orbit converged, with the motion classified.
PeriodicAnalysis analyse_from(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options);

/// The whole analysis: the transient run from the scene's own start, the
/// orbit search, and the Lyapunov run when no stable orbit converged.
PeriodicAnalysis analyse_steady_state(const PoincareMap& map, const PeriodicOptions& options);

/// Whether estimate_lyapunov stretches its tangent by forward sensitivities:
/// only for `sensitivity`. "auto" takes the neighbour trajectory: its two map
/// runs cost 2.7 to 4 times less than one sensitivity run with the single
/// tangent column, on 2 and on 18 coordinates alike (bench/lyapunov_bench.cc).
bool lyapunov_by_sensitivities(const PoincareMap& map, const PeriodicOptions& options);

/// λ of the motion from `start` over options.lyapunov_revolutions revolutions
/// (study/lyapunov.cc); `revolutions` (when given) grows by those integrated.
LyapunovEstimate estimate_lyapunov(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options,
                                   long* revolutions = nullptr);

/// Floquet multipliers of a monodromy matrix, largest modulus first.
std::vector<std::complex<double>> floquet_multipliers(const Eigen::MatrixXd& monodromy);

}  // namespace camdyn
