// The study-specific part of an `optimize` config (docs/config.md, section
// `optimize`): what is designed, at which speeds, what is minimised, which
// constraints must hold and how NLopt searches. Defaults live in the member
// initialisers; optimize_config.cc maps each struct to and from JSON in one
// `visit` function, so unknown keys are rejected and `camdyn validate` prints
// every field.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/config.h"
#include "optim/optimize/layout_design.h"
#include "optim/search.h"

namespace camdyn::optim {

/// Bounds [lower, upper] of a designed segment's end angle [deg]; unset keeps it fixed.
struct EndAngleRanges {
  std::optional<std::vector<double>> rise;  ///< [lower_deg, upper_deg]
  std::optional<std::vector<double>> ret;   ///< JSON key "return"

  bool operator==(const EndAngleRanges&) const = default;
};

/// `design`: the segments replaced by spline segments and their parametrisation.
/// The most free control points `design.control_points` takes per segment.
inline constexpr int kMaxDesignControlPoints = 100;

/// `design.event`: one spline over the cam angles [from_deg, to_deg] of any
/// baseline law, nose free; the rest of the law kept bit for bit
/// (geometry/event_spline.h).
struct DesignEventConfig {
  double from_deg = 0.0;  ///< [deg], in [0, 360)
  double to_deg = 0.0;    ///< [deg], in (from_deg, 360]

  bool operator==(const DesignEventConfig&) const = default;
};

struct DesignConfig {
  std::vector<SegmentType> segments = {SegmentType::rise, SegmentType::return_};  ///< segment types designed
  int control_points = 6;  ///< free interior control points per designed segment (6 boundary ones are added)
  int degree = 5;          ///< spline degree, 3..9
  /// Keep the free control points ordered between the fixed boundary ones, so
  /// the lift of each designed segment is monotone (a B-spline with a
  /// monotone control polygon is monotone).
  bool monotone = true;
  EndAngleRanges end_deg_range;  ///< optional end angles as extra variables
  /// Instead of segments: the event as one curve (control_points free ones
  /// over the whole span; monotone does not apply).
  std::optional<DesignEventConfig> event;
  /// Also size the answer's spring: the best design with the smallest preload
  /// that keeps the rigid-model force ≥ P_min up to the top speed competes.
  bool spring = false;
  /// Instead of the law: the cam's layout (optim/optimize/layout_design.h), geometric only.
  std::optional<LayoutConfig> layout;

  bool operator==(const DesignConfig&) const = default;
};

/// The range of a nonzero objective weight (the terms are normalised, only
/// ratios matter; beyond it the weighted sum overflows or a term vanishes).
inline constexpr double kMinObjectiveWeight = 1e-6;
inline constexpr double kMaxObjectiveWeight = 1e6;
/// Upper ends of the constraints' limits, far past any cam: a force [N], a
/// Hertz pressure [Pa], a length [m], a jerk [m/rad³], a seating speed [m/s].
inline constexpr double kMaxForceLimit = 1e9;
inline constexpr double kMaxStressLimit = 1e13;
inline constexpr double kMaxLengthLimit = 10.0;
inline constexpr double kMaxJerkLimit = 1e9;
inline constexpr double kMaxSeatingVelocityLimit = 1e3;
inline constexpr double kMaxTakeUpBouncesLimit = 1e6;  // per revolution
/// The largest rigid.speed_factor (a multiple of the top operating speed).
inline constexpr double kMaxSpeedFactor = 100.0;

/// `objective`: weights of the normalised terms (0 leaves a term out).
struct ObjectiveConfig {
  double separation = 1.0;            ///< mean gap while separated, ∫max(g,0)dt / window
  double peak_contact_force = 0.0;    ///< largest contact force
  double contact_force_margin = 0.0;  ///< smallest contact force (maximised; negative while separating)
  double peak_acceleration = 0.0;     ///< kinematic max |d²s/dθ²|
  double peak_jerk = 0.0;             ///< kinematic max |d³s/dθ³|
  /// ∫ s dθ over the designed event (the whole turn for a segment design),
  /// maximised: the term is baseline area / area. The rigid stage maximises
  /// it by LP (docs/optimize.md "Lift area").
  double lift_area = 0.0;
  std::string aggregate = "worst";  ///< over the operating speeds: "worst" or "mean"

  bool operator==(const ObjectiveConfig&) const = default;
};

/// `constraints`: null leaves a constraint out.
struct ConstraintsConfig {
  std::optional<double> max_pressure_angle_deg = 30.0;  ///< [deg]
  std::optional<double> min_radius_of_curvature;        ///< of the cam contour [m]
  std::optional<double> max_peak_contact_force;         ///< at every operating speed [N]
  std::optional<double> min_contact_force;              ///< floor of the smallest contact force [N], > 0
  bool no_separation = false;                           ///< separation_fraction 0 at every operating speed
  std::optional<double> max_peak_jerk;                  ///< max |d³s/dθ³| over the cycle [m/rad³]
  /// Hertz line-contact pressure of the rigid-model contact force at every
  /// operating speed [Pa] (dynamics/contact_stress.h; needs the contact's materials and width)
  std::optional<double> max_contact_stress;
  /// Highest lift of the designed event [m] (lift_area: the valve lift the
  /// lobe may reach; default the baseline's highest lift).
  std::optional<double> max_lift;
  /// A flat face's contact stays this far inside the face's edge [m]:
  /// |s'| ≤ face_width / 2 − margin (flat follower only).
  std::optional<double> face_edge_margin;
  /// A train's spring with mass: the force at each spring's frame end
  /// (surge: coil bind, fatigue) at every operating speed [N] (metric peak_spring_force).
  std::optional<double> max_spring_force;
  /// A train with a seat: the speed of a seated body where it reaches its
  /// seat at every operating speed [m/s] (metric max_seating_velocity).
  std::optional<double> max_seating_velocity;
  /// A train with a seat: the highest a body rises off its seat in a seat
  /// bounce, at every operating speed [m] (metric max_seat_bounce_height).
  std::optional<double> max_seat_bounce_height;
  /// A train with a seat: take-up bounces per cam revolution (per valve
  /// event), at every operating speed [-] (metric take_up_bounces over the
  /// revolutions it counts).
  std::optional<double> max_take_up_bounces;

  bool operator==(const ConstraintsConfig&) const = default;
};

/// `optimizer`: NLopt algorithm, budget and starts (the search's own
/// settings, optim/search.h), and the cheaper settings of the search loop.
struct OptimizerConfig : SearchSettings {
  /// The search loop simulates with these instead of the scene's settings
  /// (null: the scene's); the chosen design is re-evaluated with the scene's.
  /// Looser than 1e-7, the peak force is noisy enough (~1e-4 relative) to
  /// stall the linear models of COBYLA near the optimum.
  std::optional<double> evaluation_cycles = 2.0;
  std::optional<double> evaluation_rtol = 1e-7;
  double evaluation_max_wall_time_s = 30.0;  ///< per simulation in the loop [s]; slower designs are invalid
  /// Each start's evaluation at an operating speed begins where that start's
  /// last valid evaluation at that speed ended (on the section, the cam phase
  /// lined up), integrates the evaluated window only, and keeps it when the
  /// window returns to its start within optim/simulation_pool.h
  /// kWarmStartTolerance (the motion had settled); otherwise the evaluation
  /// is run cold as without it (docs/optimize.md "Warm starts").
  bool warm_start = false;

  bool operator==(const OptimizerConfig&) const = default;
};

/// The settings of the search (optim/search.h) that `optimizer` gives.
SearchSettings search_settings(const OptimizerConfig& config);

/// `rigid`: the rigid-model stage (optim/optimize/rigid_design.h) that runs before the
/// search: a linear programme over the spline's control points that
/// maximises the worst rigid-model contact-force margin at the operating
/// speeds, and the jump-speed certificate. Translating followers only.
struct RigidStageConfig {
  bool enabled = true;         ///< false: the search starts from the spline fit of the baseline
  int samples = 121;           ///< constraint samples per designed segment (ends included)
  int certificate_grid = 300;  ///< intervals per segment of the any-law programme (bound error ~0.5/grid)
  /// The contact force the rigid stage keeps at every angle [N]; null: the
  /// constraint `min_contact_force` if given, else 0 (then the stage
  /// maximises the margin above 0).
  std::optional<double> min_contact_force;
  /// The design is kept jump-free up to this multiple of the top operating
  /// speed (where the family reaches it) while it minimises the peak force or
  /// acceleration the objective weighs; with neither weighed it is the
  /// family's fastest design.
  double speed_factor = 1.1;
  /// Name the constraints that hold the family's bound down even when every
  /// operating speed is feasible (always done when one is not).
  bool explain_bound = false;

  bool operator==(const RigidStageConfig&) const = default;
};

/// The fields an optimize study adds to a scene.
struct OptimizeStudyConfig {
  DesignConfig design;
  std::vector<double> operating_rpm;  ///< [rpm], > 0, at least one
  ObjectiveConfig objective;
  ConstraintsConfig constraints;
  OptimizerConfig optimizer;
  RigidStageConfig rigid;

  bool operator==(const OptimizeStudyConfig&) const = default;
};

/// Top-level keys of the study part (split off the scene by scene_from_study_json).
const std::vector<std::string>& optimize_study_keys();

/// The algorithms `optimizer.algorithm` accepts.
const std::vector<std::string>& optimize_algorithms();

/// Reads the study part (an object holding optimize_study_keys()); unknown
/// keys, wrong types and ranges are InputError naming `source.file` and the
/// dotted path.
OptimizeStudyConfig optimize_config_from_json(const Json& study_part, const ConfigSource& source);

/// Every field, defaults included.
Json to_json(const OptimizeStudyConfig& config);

/// `design.segments` given as groups (`[["rise", "return"]]`: a run of
/// consecutive segments of the baseline designed as one curve) rewritten as
/// the equivalent `design.event` from the start of the run's first segment
/// to the end of its last, in `study_part`; InputError naming
/// `design.segments` when the baseline has no such run or is not segmented.
/// A plain list of types is left as it is.
void resolve_segment_groups(Json& study_part, const MotionLawConfig& baseline_law, const ConfigSource& source);

}  // namespace camdyn::optim
