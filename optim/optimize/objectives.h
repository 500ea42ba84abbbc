// Evaluation of one cam design for the optimize study: the kinematic figures
// of its law, its geometry (pressure angle, radius of curvature, undercut;
// geometry/cam_roller.h check_cam), one simulation per operating speed (run
// in parallel by a SimulationPool), and from these the weighted, normalised
// objective and the constraint values.
//
// Normalisation (so that weights mean something): forces by the baseline's
// peak rigid-model contact force at the top operating speed (docs/model.md §9;
// smooth and never zero, unlike the simulated peak of a baseline that
// hammers), the separation measure by the baseline's, kinematic peaks by the
// baseline's. The baseline's normalised objective is then about the sum of
// the weights.
//
// An invalid design (a cam that cannot be made, InputError from check_cam or
// build_model; a simulation that gives up, NumericalError) is not an error of
// the run: it gets a large finite objective and violated constraints, and is
// counted.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "dynamics/simulation.h"
#include "geometry/cam_roller.h"
#include "io/config.h"
#include "optim/optimize/kinematics.h"
#include "optim/optimize/optimize_config.h"
#include "optim/simulation_pool.h"

namespace camdyn::optim {

/// Simulation settings of an evaluation; unset fields keep the scene's.
struct EvaluationSettings {
  std::optional<double> cycles;           ///< replaces simulation.cycles / duration
  std::optional<double> rtol;             ///< replaces integrator.rtol
  std::optional<double> max_wall_time_s;  ///< caps integrator.max_wall_time_s
  bool record_series = false;             ///< keep the time series (for the report)
  /// Warm starts (optim/simulation_pool.h): one section point (or none) per
  /// operating speed to start that speed's run from; null or empty: cold.
  const std::vector<std::optional<SectionPoint>>* warm = nullptr;
  bool end_points = false;  ///< fill DesignEvaluation::end_points
};

/// The loop settings of optimizer.evaluation_*.
EvaluationSettings loop_settings(const OptimizerConfig& config);

struct SpeedResult {
  double rpm = 0.0;
  double mean_gap = 0.0;  ///< separation_integral / evaluated time [m]: the smooth separation measure
  SimulationResult result;
};

struct TermValue {
  std::string name;  ///< objective key
  double weight = 0.0;
  double value = 0.0;  ///< aggregated over the speeds, physical unit
  double normalised = 0.0;
  std::string unit;
};

struct ConstraintSpec {
  enum class Sense { at_most, at_least, zero };
  std::string name;  ///< constraints key, e.g. "max_pressure_angle_deg"
  Sense sense = Sense::at_most;
  double limit = 0.0;
  std::string unit;
  bool dynamic = false;  ///< needs the simulations
};

struct ConstraintValue {
  double value = 0.0;     ///< physical (the metric or geometry figure it limits)
  double margin = 0.0;    ///< how far inside the limit (negative: violated), same unit
  double residual = 0.0;  ///< normalised, ≤ 0 when it holds (what NLopt sees)
  bool holds = false;
};

struct DesignEvaluation {
  bool valid = false;
  std::string error;  ///< why the design is invalid
  SceneConfig scene;  ///< as evaluated (simulation settings of the evaluation, rpm of the top speed)
  LawKinematics kinematics;
  /// ∫ s dθ over the designed event (the whole turn for a segment design) [m rad]
  double lift_area = 0.0;
  double highest_lift = 0.0;  ///< highest s over the same span [m]
  CamGeometryReport geometry;
  /// Highest rigid-model Hertz pressure over the operating speeds [Pa]
  /// (only with constraints.max_contact_stress), at `contact_stress_rpm`.
  double peak_contact_stress = 0.0;
  double contact_stress_rpm = 0.0;
  bool simulated = false;
  std::vector<SpeedResult> speeds;  ///< one per operating speed, when simulated
  /// With EvaluationSettings::end_points and a valid simulated design: where
  /// each operating speed's run ended on the section (none where it did not),
  /// the warm starts of the next evaluation.
  std::vector<std::optional<SectionPoint>> end_points;
  int warm_speeds = 0;  ///< operating speeds whose warm window was kept

  std::vector<TermValue> terms;  ///< the weighted terms
  double objective = 0.0;
  std::vector<ConstraintValue> constraints;  ///< one per DesignEvaluator::constraints()
  bool feasible = false;
};

struct Normalisation {
  double force = 1.0;         ///< [N]
  double mean_gap = 1.0;      ///< [m]
  double acceleration = 1.0;  ///< [m/rad²]
  double jerk = 1.0;          ///< [m/rad³]
  double lift_area = 1.0;     ///< [m rad]
};

class DesignEvaluator {
 public:
  DesignEvaluator(const OptimizeStudyConfig& config, std::string file, SimulationPool& pool);

  const std::vector<ConstraintSpec>& constraints() const { return constraints_; }
  /// Whether any weighted term or constraint needs simulations (else the search
  /// loop evaluates kinematics and geometry only).
  bool needs_simulation() const { return needs_simulation_; }

  /// Measures a design and scores it with the current normalisation. Never
  /// throws for an invalid design (see the file comment).
  DesignEvaluation evaluate(const SceneConfig& scene, const EvaluationSettings& settings, bool simulate) const;

  /// Adds the constraint `no_separation_where_proven`: separation_fraction 0
  /// at each of `rpm`, the operating speeds the rigid stage proved jump-free
  /// (docs/config.md, "The answer of an optimize study"). Call before
  /// constraints() is read; no speeds add nothing.
  void require_no_separation_at(const std::vector<double>& rpm);
  const std::vector<double>& proven_rpm() const { return proven_rpm_; }

  /// Normalisation from the baseline (evaluated with simulations); its
  /// scenes' top speed gives the rigid-model force scale. Throws InputError if
  /// the baseline is invalid.
  Normalisation normalisation_from(const DesignEvaluation& baseline) const;
  void set_normalisation(const Normalisation& n) { norm_ = n; }
  const Normalisation& normalisation() const { return norm_; }

  /// Recomputes terms, objective and constraints of a measured design.
  void score(DesignEvaluation& e) const;

  /// The normalised objective given to an invalid design.
  double invalid_objective() const;

  /// The scene at operating speed `rpm` with `settings` applied.
  static SceneConfig at_speed(const SceneConfig& scene, double rpm, const EvaluationSettings& settings);

 private:
  double aggregate(const std::vector<double>& v, bool worst_is_max) const;
  /// e.peak_contact_stress over the operating speeds, from the model of
  /// e.scene: `assembled` (the design's model at another speed) with e.scene's
  /// speed set, or, where none is given, one built on `geometry`.
  void peak_contact_stress(const CamGeometry& geometry, const Model* assembled, DesignEvaluation& e) const;

  OptimizeStudyConfig config_;
  std::string file_;
  SimulationPool& pool_;
  std::vector<ConstraintSpec> constraints_;
  bool needs_simulation_ = false;
  std::vector<double> proven_rpm_;  ///< speeds of no_separation_where_proven
  Normalisation norm_;
};

}  // namespace camdyn::optim
