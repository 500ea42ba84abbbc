// The `jump_map` study: the bifurcation diagram of a cam-follower over a
// speed range. At each speed it follows the motion past its transient,
// records the Poincaré samples (the state once per revolution) with every
// impact (cam angle, approach speed), and runs the periodic analysis
// (study/periodic_orbit.h) on it. Each speed starts from the neighbouring
// speed's orbit (natural-parameter continuation) within a contiguous range of
// speeds; the ranges run in parallel, journalled like a compare study's runs
// (resume, --jobs, MPI). From the sequence it marks where the follower first
// leaves the cam, period doublings, other period changes and chaotic bands;
// at each change of class it looks for the other side's attractor, and a
// speed where two coexist is marked so, without a single class.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dynamics/cam_geometry.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "output/report.h"
#include "scene/enum_names.h"
#include "study/periodic_study.h"
#include "study/study.h"

namespace camdyn {

/// The study's own fields (`jump_map` in the config).
struct JumpMapConfig {
  double low_rpm = 0.0;            ///< [rpm], > 0
  double high_rpm = 0.0;           ///< [rpm], > low_rpm
  int speeds = 21;                 ///< grid points, low to high, ≥ 2
  int ranges = 4;                  ///< contiguous ranges run in parallel (continuation within each), ≥ 1
  int transient_revolutions = 20;  ///< followed at each speed before its samples and analysis
  int samples = 30;                ///< Poincaré samples recorded at each speed
  /// Start a speed from the orbit predicted by its neighbours' stable orbits
  /// (secant in rpm) and shoot it directly, without the transient; the
  /// transient path only when that gives no stable orbit of the same period.
  bool warm_start = true;
  /// Where the class changes between neighbouring speeds, shoot from each
  /// side's stable orbit one step across, and follow the transient path at a
  /// speed the warm start reached: two attractors mark the speed
  /// `coexisting` (docs/periodic.md "Coexisting attractors").
  bool check_coexistence = true;
  /// Bisection levels between neighbouring grid speeds whose class (motion
  /// kind, period) differs: each adds one speed and halves the bracket, ≥ 0.
  int refine = 1;
};

/// The most `refine` levels (each halves a bracket: 2^-20 of a grid step is finer than any speed needs).
inline constexpr int kMaxRefineLevels = 20;

struct JumpMapStudy {
  SceneConfig scene;
  /// The scene's geometry, built once when the config is read and shared by
  /// every speed (null: each speed builds its own).
  std::shared_ptr<const CamGeometry> geometry;
  /// The scene's model, assembled once when the config is read: each range
  /// runs its speeds on a copy of it, the speed set in place (set_cam_speed)
  /// (null: each speed assembles its own, as the study did before;
  /// bench/model_reuse_bench.cc compares).
  std::shared_ptr<const Model> model;
  JumpMapConfig config;
  PeriodicConfig periodic;  ///< `periodic` fields: the analysis at each speed
  Json resolved;
  double rigid_jump_speed_rpm = 0.0;         ///< jump_speed_rpm of the scene [rpm]
  double damped_rigid_jump_speed_rpm = 0.0;  ///< damped_jump_speed_rpm (the damper's c ω s' included) [rpm]
  /// With a follower train both figures are the held train's (docs/model.md §12), so named.
  std::string jump_speed_name = "rigid-model jump speed";
  std::vector<double> rpm;    ///< the grid
  int section_dimension = 0;  ///< coordinates of the Poincaré map (dynamics/poincare_map.h)
  /// Threads each speed's Jacobian columns and Lyapunov pair run on (the
  /// study's --jobs): while several ranges run they share the cores; a range
  /// left running alone uses them all. The answers do not depend on it.
  int threads_per_speed = 1;
};

/// How a speed's motion was reached: shot from the orbit its neighbours
/// predicted, or followed past a transient and analysed.
enum class JumpMapStart { predicted, transient };
inline constexpr EnumName<JumpMapStart> kJumpMapStartNames[] = {{JumpMapStart::predicted, "predicted"},
                                                                {JumpMapStart::transient, "transient"}};
constexpr std::span<const EnumName<JumpMapStart>> enum_names(JumpMapStart) { return kJumpMapStartNames; }

/// How an attractor of a speed was reached: along the range's continuation
/// (the point's own motion), by shooting from the stable orbit of the speed
/// below or above it across a change of class (the hysteresis check), or, at
/// a speed the warm start reached, by the transient path from the motion of
/// the speed below (what `"warm_start": false` would have followed), or by
/// the shooting from the speed's own motion, which itself did not go there
/// (PeriodicAnalysis::unreached_orbits).
enum class JumpMapReach { continuation, from_below, from_above, transient, shooting };
inline constexpr EnumName<JumpMapReach> kJumpMapReachNames[] = {{JumpMapReach::continuation, "continuation"},
                                                                {JumpMapReach::from_below, "from_below"},
                                                                {JumpMapReach::from_above, "from_above"},
                                                                {JumpMapReach::transient, "transient"},
                                                                {JumpMapReach::shooting, "shooting"}};
constexpr std::span<const EnumName<JumpMapReach>> enum_names(JumpMapReach) { return kJumpMapReachNames; }

/// One attractor found at a speed (JumpMapPoint::attractors).
struct JumpMapAttractor {
  JumpMapReach reached = JumpMapReach::continuation;
  MotionKind motion = MotionKind::periodic;            ///< periodic, or the continuation's own motion (e.g. chaotic)
  int period = 0;                                      ///< of the stable orbit (0 when not periodic)
  double spectral_radius = 0.0;                        ///< largest |Floquet multiplier| (< 1: stable)
  std::vector<double> fixed_point;                     ///< the orbit's section point, the map's coordinates [SI]
  double approach_speed = 0.0;                         ///< v₀ of the contact episode in progress there [m/s]
  std::vector<double> multipliers_re, multipliers_im;  ///< Floquet multipliers, largest modulus first
};

/// What one speed gave.
struct JumpMapPoint {
  double rpm = 0.0;
  bool ok = false;
  JumpMapStart start = JumpMapStart::transient;
  bool refined = false;  ///< inserted between grid speeds of different classes (JumpMapConfig::refine)
  std::string error;
  /// The budget that cut this speed short (common/study_budget.h:
  /// budget_that_cut), empty when none did: such a speed says nothing about
  /// the motion, and a map with one withholds its conclusions.
  std::string budget;
  MotionKind motion = MotionKind::unresolved;
  int period = 0;                ///< of the stable orbit (0 when none)
  double spectral_radius = 0.0;  ///< of its monodromy matrix
  double lyapunov = 0.0;         ///< per revolution, when estimated
  /// Its standard error by batch means (LyapunovEstimate::standard_error) [1/revolution].
  std::optional<double> lyapunov_standard_error;
  /// Of the Lyapunov estimate's revolutions, those its sensitivity tangent
  /// could not take and a neighbour trajectory took (LyapunovEstimate).
  long lyapunov_fallback_revolutions = 0;
  std::vector<double> impact_angle_deg, impact_speed;  ///< every impact of the samples [deg], [m/s]
  std::vector<double> section_position;                ///< follower coordinate at each sample [m | rad]
  double separation_fraction = 0.0;                    ///< over the samples
  double link_separation_fraction = 0.0;               ///< a follower train's links open, over the samples
  /// The follower floats or a link opens off its seats in float (an impact
  /// that ends a float included): the map's "leaves the cam". Take-up and
  /// seat bounces of a scene with a seat are not (docs/valvetrain.md).
  bool floats = false;
  /// Where it floats, as speed_limit's limit_cause: "float" (the cam
  /// contact) or "link" (a link open off every seat); "" where it does not.
  std::string float_cause;
  long seat_bounces = 0;            ///< bodies leaving their seats after seating, over the samples
  double max_gap = 0.0;             ///< [m]
  double peak_contact_force = 0.0;  ///< [N]
  /// Two different attractors were found at this speed (a stable orbit of
  /// another period, or of the same period with fixed points apart, or a
  /// stable orbit beside a motion that found none): the speed has no single
  /// class. `motion`, `period` and the samples stay those reached along the
  /// continuation; `attractors` lists every one found, that one first.
  bool coexisting = false;
  std::vector<JumpMapAttractor> attractors;  ///< empty unless coexisting
};

/// A change of character between two neighbouring grid speeds.
struct JumpMapTransition {
  /// separation, reattachment, period_doubling, period_adding, period_change, chaos_onset, chaos_end, or
  /// coexistence (a speed with two attractors: no change of class is stated to or from it)
  std::string kind;
  double from_rpm = 0.0, to_rpm = 0.0;
  int from_period = 0, to_period = 0;  ///< 0: not periodic
};

/// Reads a `jump_map` study config; throws InputError.
JumpMapStudy read_jump_map_study(const Json& doc, const StudyContext& ctx);

/// The speeds of range `r` (indices into study.rpm), run in order with continuation.
std::vector<std::size_t> jump_map_range(const JumpMapStudy& study, std::size_t r);

/// The expected cost of grid speed `i` [revolutions integrated]: the progress
/// line's unit of work, so that its time left weighs the speeds left by what
/// they cost, not one a speed. A speed the warm start can shoot (below the
/// damped rigid jump speed, not the first of its range): one Jacobian of the
/// map (1 + 2n revolutions, n section coordinates) and 3 more; one on the
/// transient path: transient_revolutions + samples + two Newton iterations
/// (2 (1 + 2n)); past the jump speed, where the motion may be chaotic, also
/// the Lyapunov run's two trajectories (2 lyapunov_revolutions).
double jump_map_speed_work(const JumpMapStudy& study, std::size_t i);

/// Runs range `r`; one point per speed, in order. Never throws: a speed that
/// fails is a point with ok false and the error, and the next starts afresh;
/// once the study's budget is used up the remaining speeds are not run (ok
/// false, budget "--max-study-time").
std::vector<JumpMapPoint> run_jump_map_range(const JumpMapStudy& study, std::size_t r, const std::string& file);

/// The transitions along the grid (points in rpm order).
std::vector<JumpMapTransition> jump_map_transitions(const std::vector<JumpMapPoint>& points);

/// The map's limit, as speed_limit's (docs/valvetrain.md): the lowest grid
/// speed that floats and where (`limit_cause` "float" or "link"), and the
/// lowest with a seat bounce; none where no speed does.
struct JumpMapLimit {
  std::optional<double> rpm;              ///< [rpm]
  std::string cause;                      ///< "float" or "link"
  std::optional<double> seat_bounce_rpm;  ///< [rpm]
};
JumpMapLimit jump_map_limit(const std::vector<JumpMapPoint>& points);

/// A point as a journal record and back.
Json jump_map_point_json(const JumpMapPoint& p);
JumpMapPoint jump_map_point_from_json(const Json& j);

/// report.html: the verdict, the diagrams against cam speed (impact speed,
/// the Poincaré section of the follower coordinate in its own unit, impact
/// angles), the cam and the table of speeds; `file` names the config in messages.
Report jump_map_report(const JumpMapStudy& study, const std::vector<JumpMapPoint>& points,
                       const std::vector<JumpMapTransition>& transitions, double run_time, const std::string& file);

/// Runs (or, with ctx.validate_only, checks) the study; writes jump_map.json,
/// jump_map.csv and report.html; returns the exit code.
int run_jump_map_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
