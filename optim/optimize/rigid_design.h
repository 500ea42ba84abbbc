// The rigid-model stage of an optimize study: exact and global, because on
// the rigid model the contact condition is linear in the spline's control
// points (optim/optimize/jump_bound.h has the physics).
//
//  * The design: a linear programme over the free control points c of the
//    designed segments that maximises the worst margin P − P_min over the
//    operating speeds at sample angles, subject to a monotone control polygon
//    (design.monotone) and, for a translating roller or mushroom, the
//    pressure-angle bound |s'| + |e| ≤ tan φ_max (y₀ + s), which is linear
//    and, without offset, exact. The dynamic stage starts from it. With
//    objective.lift_area it maximises ∫ s dθ instead, keeping P ≥ P_min at
//    every speed up to the top one, the lift cap, a flat face's |s'| and
//    r_b + s + s'' ≥ ρ_min as rows, and reports the area's certificate
//    (optim/optimize/lobe_bound.h; docs/optimize.md "Lift area").
//  * The certificate: (a) the highest jump-free speed ANY law with these
//    lifts, durations, follower and spring reaches; (b) the highest the
//    spline family reaches under the same linear constraints, and which
//    constraints hold it down; (c) for each operating speed whether the
//    family can be jump-free there. All by bisection on ω over CLP solves.
// Constraints that are not linear (radius of curvature, Hertz contact
// pressure, an arm's pressure angle): the stage tightens the design under
// them, with cuts where the dense check fails, a shrinking trust region and
// at most 8 rounds. For a translating follower without offset the first two
// have a pointwise form in (s, s', s''); the rest come from a probe through
// the cam synthesis (optim/optimize/rigid_limits.h). The dynamic stage holds them as
// constraints as well, and the final design is re-checked.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/optimize_config.h"

namespace camdyn::optim {

/// (c): one operating speed.
struct SpeedCertificate {
  double rpm = 0.0;
  bool feasible = false;     ///< some design of the family keeps P ≥ P_min at this speed
  double best_margin = 0.0;  ///< the largest worst margin P − P_min the family reaches at this speed [N]
};

/// The certificate of a lift-area design (objective.lift_area with
/// design.event; docs/optimize.md "Lift area"): its area against the largest
/// any lift over the same event can have under the same constraints
/// (optim/optimize/lobe_bound.h).
struct LiftAreaCertificate {
  bool available = false;
  std::string reason;              ///< why not, when not available
  double design = 0.0;             ///< ∫ s dθ of the stage's design over the event [m rad]
  double bound = 0.0;              ///< the any-law bound [m rad]
  double baseline = 0.0;           ///< the baseline's [m rad]
  int grid = 0;                    ///< intervals of the bound's programme
  std::vector<double> speeds_rpm;  ///< the speeds at which P ≥ P_min is held [rpm]
};

struct Certificate {
  bool available = false;
  std::string reason;              ///< why not, when not available
  double min_contact_force = 0.0;  ///< P_min [N]
  std::string margin_unit = "N";   ///< of the margins: "N", or "N m" for an arm (torque about its pivot)
  double any_law_rpm = 0.0;        ///< (a) [rpm] (+inf: no limit below 1000× the top speed)
  std::string any_law_binding;     ///< the segment (or the fixed part of the law) that sets (a)
  /// Why (a) is not computed ("" when it is): then any_law_rpm and
  /// any_law_coarse_rpm are NaN, never a figure (docs/optimize.md "The certificate").
  std::string any_law_unavailable;
  double family_rpm = 0.0;  ///< (b) [rpm]
  /// What holds (b) down: "max_pressure_angle_deg" and "monotone" when dropping
  /// them raises (b) by more than 0.5 %; "spline family" otherwise;
  /// "spring and mass" when (b) is within 1 % of (a). Found (two more
  /// bisections) when an operating speed is infeasible or rigid.explain_bound
  /// is set; empty otherwise.
  std::vector<std::string> family_binding;
  double baseline_rpm = 0.0;  ///< the baseline law's own rigid jump-free speed at P_min [rpm]
  /// The model the margins are of: "rigid one-mass" (docs/model.md §9) or
  /// "held train" (every contact and link held, optim/optimize/train_rows.h).
  std::string model = "rigid one-mass";
  /// On a train: (a) with 8 instead of 16 control points per segment [rpm]
  /// (any_law_rpm rises to the true bound as the spline is refined).
  double any_law_coarse_rpm = 0.0;
  int train_harmonics = 0;               ///< most harmonics of the held train's response used
  double train_truncation = 0.0;         ///< their estimated truncation, relative to the largest force [-]
  std::vector<SpeedCertificate> speeds;  ///< (c), in operating_rpm order
  LiftAreaCertificate lift_area;
  bool all_feasible() const;
  /// family_binding joined by ", " ("" when none was worked out).
  std::string binding_text() const;
};

struct RigidDesign {
  bool have = false;
  std::vector<double> control_points;   ///< the raw free control points c
  std::vector<double> x;                ///< as a design vector of the DesignSpace
  double lp_margin = 0.0;               ///< the programme's worst margin over the operating speeds [N]
  std::vector<double> verified_margin;  ///< per operating speed, the built law sampled densely [N]
  double jump_free_rpm = 0.0;           ///< the design's own rigid jump-free speed at P_min [rpm]
};

/// Whether the stage's design keeps P ≥ P_min at operating speed `i` on the
/// dense check (its verified margin ≥ 0): what "feasible" at that speed
/// promises of the design, not only of the family.
bool design_holds(const RigidDesign& d, std::size_t i);

struct RigidStageResult {
  Certificate certificate;
  RigidDesign design;
  int lp_solves = 0;
  double run_time_s = 0.0;
};

/// Runs the stage on `baseline` (translating or oscillating follower). Throws
/// NumericalError when CLP fails on a programme (not for an infeasible one).
/// The certificate is not available (with the reason) when some follower
/// force element has no linear part: the programmes are linear in the forces.
RigidStageResult run_rigid_stage(const SceneConfig& baseline, const OptimizeStudyConfig& config,
                                 const DesignSpace& space, const std::string& file);

/// The rigid-model margin P − P_min [N, or N m for an arm] of `scene`'s law
/// at `rpm` at each cam angle of `angles_deg`.
std::vector<double> rigid_margin_curve(const SceneConfig& scene, double rpm, double min_force,
                                       const std::vector<double>& angles_deg);

/// The jump-free speed [rpm] of `scene`'s law on the stage's model at P_min
/// with the stage's limits — the held train's on a train, the rigid one-mass
/// model's otherwise: the one figure camdyn calls "jump-free to", for the
/// baseline (Certificate::baseline_rpm), the stage's design
/// (RigidDesign::jump_free_rpm) and any other design (the answer). +inf when
/// there is no limit below the bracket's top.
double stage_jump_free_rpm(const SceneConfig& scene, const OptimizeStudyConfig& config, const std::string& file);

/// P_min of the stage: rigid.min_contact_force, else constraints.min_contact_force, else 0 [N].
double rigid_min_contact_force(const OptimizeStudyConfig& config);

}  // namespace camdyn::optim
