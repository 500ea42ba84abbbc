// One optimize run, from the baseline scene and the study fields to the
// optimised design: evaluate the baseline (the normalisation comes from it),
// search with NLopt using the cheaper loop settings, then re-evaluate the best
// designs with the scene's own settings and keep the first that satisfies every
// constraint there. The answer is then the best of the baseline, the rigid
// stage's design and that result, each verified on the steady state at every
// operating speed (optim/optimize/candidate_choice.h), so it is never worse
// than the baseline. The optimised scene is built, written and read back
// exactly as optimized.json will be, so `camdyn run optimized.json`
// reproduces the reported metrics.
#pragma once

#include <cstddef>
#include <filesystem>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "io/config.h"
#include "optim/optimize/candidate_choice.h"
#include "optim/optimize/design.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize_config.h"
#include "optim/optimize/rigid_design.h"
#include "optim/search.h"

namespace camdyn::optim {

/// One row of history.csv: an evaluation of the search loop.
struct HistoryRecord {
  long evaluation = 0;  ///< 1-based
  int start = 0;
  PointKind kind = PointKind::nlopt;
  bool valid = true;
  std::string error;
  double objective = 0.0;
  std::vector<ConstraintValue> constraints;
  bool feasible = false;
  double best_objective = 0.0;  ///< best feasible objective so far (the first objective until one is feasible)
  bool best_feasible = false;
};

struct OptimizeOptions {
  int threads = 1;        ///< simulation threads (one per operating speed is enough)
  bool progress = false;  ///< progress lines on stderr
  /// Where history.csv, best_design.json and the journal are kept while
  /// the search runs, and a killed run's journal is replayed from (empty: none).
  std::filesystem::path checkpoint_dir;
  /// Spread the search's starts over the MPI ranks (optim/search.h
  /// starts_over_ranks; docs/optimize.md "MPI ranks"): collective, every
  /// rank calls run_optimize; a rank other than 0 stops after the search
  /// (its outcome is incomplete), rank 0 carries on with every start's result.
  bool over_ranks = false;
};

/// The objective on each speed's periodic steady state (study/steady_state.h)
/// where one is found, against the loop's window: the two agree when the
/// window already sat on the orbit.
struct SteadyStateCheck {
  bool checked = false;
  std::string reason;              ///< why not checked
  int speeds_on_orbit = 0;         ///< of the operating speeds, those with a stable orbit found
  int speeds = 0;                  ///< operating speeds
  double objective = 0.0;          ///< with the metrics over the orbits (the window's where none)
  double relative_change = 0.0;    ///< against the window's objective
  bool agrees = false;             ///< within WindowCheck::kTolerance
  std::vector<std::string> notes;  ///< per speed: the orbit, or why the window's metrics stay
};

/// The optimised design evaluated again over an evaluated window twice as
/// long: an objective that changes with the window is a transient's, not the
/// design's. Converged when it changes by at most `kTolerance` relative.
/// Beside it the steady-state check: the same objective on the periodic orbits.
struct WindowCheck {
  static constexpr double kTolerance = 1e-3;
  bool checked = false;
  std::string reason;              ///< why not checked
  double evaluated_cycles = 0.0;   ///< the scene's evaluated window [rev]
  double doubled_cycles = 0.0;     ///< the check's [rev]
  double objective = 0.0;          ///< over the scene's window
  double objective_doubled = 0.0;  ///< over the doubled window
  bool feasible_doubled = false;
  double relative_change = 0.0;
  bool converged = false;
  SteadyStateCheck steady_state;
};

/// One candidate answer (baseline, rigid design, dynamic result) with the
/// scene's settings on the steady state at every operating speed.
struct CandidateVerification {
  CandidateKind kind = CandidateKind::baseline;
  bool available = false;
  std::string reason;                  ///< why not available
  DesignEvaluation verified;           ///< simulation.steady_state set, the scene's settings
  std::vector<double> separating_rpm;  ///< operating speeds where it separates on the steady state
  /// On a train, per separating speed: where the train lets go first
  /// ("cam contact" or "link <body>", TrainMetrics::separates_first) and the cam angle there [deg].
  std::vector<std::pair<std::string, double>> lets_go;
  CandidateScore score;                                ///< as the choice saw it (the proven speeds included)
  CandidateKind sized_from = CandidateKind::baseline;  ///< spring: the candidate whose law it keeps
};

/// The study's answer: which candidate won, and the verification of each.
struct Selection {
  CandidateChoice choice;
  std::vector<CandidateVerification> candidates;  ///< baseline, rigid, dynamic (and spring), in CandidateKind order
  /// The verification of the chosen candidate.
  const CandidateVerification& chosen() const;
  /// Why the banner is not green although the answer meets everything: on a
  /// design.event it gave up lift nothing in the study keeps (lift_given_up
  /// in optim/optimize/certificate_text.h); empty otherwise.
  std::string lift_given_up;
  /// Green banner: jump-free at every operating speed, every constraint,
  /// better than the baseline, and the lift kept.
  bool good() const;
};

struct OptimizeOutcome {
  OptimizeStudyConfig config;
  std::vector<DesignVariable> variables;
  std::vector<double> x_initial, x_optimized;
  BaselineFit fit;
  std::vector<ConstraintSpec> constraints;
  Normalisation normalisation;
  bool loop_simulated = false;  ///< the loop ran simulations (else kinematics and geometry only)

  DesignEvaluation baseline;  ///< the baseline law, scene settings, time series kept
  RigidStageResult rigid;     ///< the rigid-model stage and its certificate (rigid.enabled)
  /// Operating speeds the rigid design is jump-free at (rigid-model margin ≥ 0):
  /// the search holds no separation there as a constraint (no_separation_where_proven).
  std::vector<double> proven_rpm;
  DesignEvaluation initial;    ///< the first start of the search (the rigid design, else the spline fit), loop settings
  DesignEvaluation optimized;  ///< the chosen design (selection), scene settings, time series kept
  Selection selection;         ///< which of baseline, rigid design and dynamic result is the answer
  /// The smallest spring preload [required_preload_unit] that keeps the
  /// chosen design's rigid-model contact force at least P_min up to the top
  /// operating speed (dynamics/spring_sizing.h; on a follower train the held
  /// train's contact and link forces, of the spring required_preload_spring),
  /// and the smallest rate for the preload it has. NaN where not available
  /// (required_preload_unavailable says why).
  double required_preload = 0.0;
  double required_stiffness = 0.0;          ///< +inf when no rate suffices; NaN on a train (not sized)
  std::string required_preload_unit = "N";  ///< "N", or "N m" for an arm's own spring
  std::string required_preload_spring;  ///< the spring sized ("mechanism.follower.spring", "mechanism.train[0].spring")
  std::string required_preload_unavailable;    ///< why there is no figure ("" when there is)
  std::string required_stiffness_unavailable;  ///< why the rate is not sized ("" when it is)
  SceneConfig optimized_scene;                 ///< the `simulate` config written to optimized.json
  /// The answer's jump-free speed on the rigid stage's model at P_min
  /// (stage_jump_free_rpm: the figure the certificate gives the baseline and
  /// the rigid design) [rpm]; NaN without a certificate.
  double answer_jump_free_rpm = std::numeric_limits<double>::quiet_NaN();
  WindowCheck window_check;             ///< the optimised objective over a doubled window (dynamic objectives only)
  int candidates_tried = 0;             ///< designs re-evaluated at the scene settings to find a feasible one
  std::size_t resumed_evaluations = 0;  ///< search evaluations replayed from the journal of an earlier, killed run
  /// Evaluations (search, re-evaluation at the scene's settings and
  /// verification) whose simulations a budget cut short
  /// (integrator.max_steps, max_wall_time_s, evaluation_max_wall_time_s):
  /// counted invalid, never a result (docs/optimize.md "Budgets").
  std::size_t budget_cut_evaluations = 0;
  std::set<std::string> budget_cut_by;   ///< the budgets that cut them
  std::string budget_cut_names() const;  ///< budget_cut_by, comma-separated
  /// Why the answer is withheld (the verification of a candidate the choice
  /// rests on was cut short by a budget); empty when it stands.
  std::string withheld;
  long resumed_simulations = 0;  ///< their simulations (counted in `simulations`, not run again)

  SearchResult search;
  std::vector<HistoryRecord> history;
  long simulations = 0;       ///< all simulations of the run
  long loop_simulations = 0;  ///< simulations of the search loop
  /// optimizer.warm_start: loop simulations whose warm window was kept, and
  /// those tried warm that ran cold after all (optim/simulation_pool.h).
  long warm_kept = 0, warm_rejected = 0;
  double loop_time_s = 0.0;  ///< wall time of the search loop [s]
  double run_time_s = 0.0;   ///< whole run [s]
};

/// Sets out.withheld when the verification of a candidate in out.selection
/// was cut short by a budget (its error names one: common/study_budget.h
/// budget_that_cut), counting it in out.budget_cut_evaluations: the choice
/// of the answer would rest on a run that says nothing about the physics.
void withhold_on_budget(OptimizeOutcome& out);

/// The two halves of an optimize study config.
struct OptimizeStudy {
  SceneConfig baseline;
  OptimizeStudyConfig config;
};

/// Reads an optimize study document (after load_config_json): the baseline
/// scene and the study fields, each with its unknown keys rejected. The
/// baseline's `mechanism.cam.rpm` is not used (the operating speeds are), so
/// it may be left out and defaults to the top operating speed, which is also
/// the speed of optimized.json. Throws InputError.
OptimizeStudy read_optimize_study(const Json& doc, const ConfigSource& source);

/// Runs the study. Throws InputError for a design that cannot be set up or a
/// baseline that cannot be built, NumericalError when the baseline cannot be
/// simulated or the search found no valid design at all.
OptimizeOutcome run_optimize(const SceneConfig& baseline, const OptimizeStudyConfig& config, const std::string& file,
                             const OptimizeOptions& options = {});

/// Checks what run_optimize would check before simulating (design space,
/// baseline model, loop settings against the scene); throws InputError.
void check_optimize(const SceneConfig& baseline, const OptimizeStudyConfig& config, const std::string& file);

/// A scene's spring sizing (OptimizeOutcome::required_preload): the rigid
/// model's, or on a follower train the held train's.
struct SceneSpringSizing {
  bool available = true;
  std::string reason;                                ///< why not, when not available
  std::string spring = "mechanism.follower.spring";  ///< the spring sized
  int body = 0;                                      ///< its body (0: the follower, i: mechanism.train[i − 1])
  std::string unit = "N";                            ///< of the preload
  double required_preload = 0.0;                     ///< [unit]
  double required_stiffness = 0.0;                   ///< NaN on a train (not sized)
  std::string stiffness_reason;                      ///< why the rate is not sized
};

/// The spring sizing of `scene` up to the top operating speed, with the
/// rigid stage's P_min: the rigid model's (dynamics/spring_sizing.h), or on a
/// follower train the held train's (size_held_spring; docs/model.md §12).
SceneSpringSizing size_scene_spring(const SceneConfig& scene, const OptimizeStudyConfig& config,
                                    const std::string& file);

}  // namespace camdyn::optim
