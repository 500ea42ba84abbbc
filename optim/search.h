// The NLopt driver of the optimize study, independent of cams: minimises an
// objective f(x) subject to inequality constraints c_i(x) ≤ 0 inside a box,
// with the algorithms of optimizer.algorithm.
//
//   LN_COBYLA, LD_SLSQP, LD_MMA, GN_ISRES   constraints handled natively
//   LN_BOBYQA, LN_SBPLX, GN_CRS2_LM,         no constraint support: wrapped in
//   GN_DIRECT_L                              NLOPT_AUGLAG (augmented Lagrangian)
//                                            with the algorithm as subsidiary
//   LD_*                                     gradients by forward differences
//                                            (the simulations have none)
//
// Local algorithms run from several starts (the given x0, then seeded random
// points in the box); the evaluation budget is shared evenly between them.
// The starts may run at once on several threads (SearchProblem::
// parallel_starts): each start's points, budget and stop are its own, the
// random starts are drawn before any runs, and evaluated points are ranked
// by (start, evaluation within the start), so the result is the sequential
// one's whatever the threads' timing.
// Under MPI (SearchProblem::over_ranks, docs/optimize.md "MPI ranks") the
// starts spread over the ranks instead: start s runs on rank s mod N, and
// each start's result and evaluated points travel to rank 0 as text (every
// double as the hex of its bits, io/hex_doubles.h), which ranks them as the
// one process would: the same result, to the bit, on rank 0.
// Every NLopt status and exception becomes a `stop_reason` name; a start that
// fails keeps what it found and never stops the others. The objective and
// constraint functions of one point are evaluated once (cached: NLopt asks
// for them separately), and the best point is tracked here rather than taken
// from NLopt, so no status can lose it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace camdyn::optim {

/// How run_search searches: the algorithm, its budget and its starts. The
/// optimize study gives its `optimizer` settings (docs/config.md) through
/// search_settings() of optim/optimize/optimize_config.h; the defaults here
/// are that config's.
struct SearchSettings {
  /// LN_COBYLA, LN_BOBYQA, LN_SBPLX, LD_SLSQP, LD_MMA, GN_ISRES, GN_CRS2_LM, GN_DIRECT_L.
  std::string algorithm = "LN_COBYLA";
  int max_evaluations = 400;         ///< total over all starts (split evenly)
  double xtol_rel = 1e-4;            ///< NLopt relative tolerance on the design vector
  double ftol_rel = 0.0;             ///< NLopt relative tolerance on the objective (0: off)
  std::optional<double> max_time_s;  ///< wall-time budget of the search [s]
  int starts = 1;                    ///< local algorithms: x0, then random starts
  int seed = 1;                      ///< random starts and NLopt's stochastic algorithms
  double initial_step = 0.1;         ///< derivative-free local algorithms: first step, share of each bound range
  double gradient_step = 1e-3;       ///< LD_ algorithms: forward-difference step, share of each bound range

  bool operator==(const SearchSettings&) const = default;
};

/// The value of one point: objective, constraint residuals (≤ 0 feasible) and
/// whether the point could be evaluated at all and satisfies every constraint.
struct PointValue {
  double objective = 0.0;
  std::vector<double> residuals;
  bool valid = true;
  bool feasible = false;
};

/// Why a point is evaluated: a point NLopt asked for, or a finite-difference probe.
enum class PointKind { nlopt, gradient };

struct SearchProblem {
  std::vector<double> lower, upper;  ///< finite bounds
  std::vector<double> x0;            ///< first start
  int constraint_count = 0;
  /// Must not throw; `start` is the index of the start that asks. With
  /// parallel_starts > 1 it is called from several threads at once, never
  /// twice at once for the same start.
  std::function<PointValue(const std::vector<double>& x, int start, PointKind kind)> evaluate;
  /// Threads the starts run on (local algorithms with several starts; 1: one after the other).
  int parallel_starts = 1;
  /// Spread the starts over the MPI ranks when starts_over_ranks(config)
  /// (study/mpi_runner.h; collective: every rank calls run_search). The
  /// result is then complete on rank 0 only; the other ranks get their own
  /// starts' results and no candidates.
  bool over_ranks = false;
  /// Over ranks, on the rank (not 0) that ran start `start`, right after it:
  /// what the caller keeps of that start (its evaluations), as text.
  std::function<std::string(int start)> start_record;
  /// Over ranks, on rank 0: the text start_record gave for a start run on
  /// another rank, before the search ranks its points (in arrival order).
  std::function<void(int start, const std::string& record)> take_start_record;
};

struct SearchProgress {
  long evaluations = 0;  ///< over all starts so far
  int start = 0, starts = 1;
  double best_objective = 0.0;
  bool best_feasible = false;
  double evaluations_per_second = 0.0;
};

struct StartResult {
  int index = 0;
  std::vector<double> x0;
  std::string stop_reason;  ///< NLopt status name, e.g. "xtol_reached", "roundoff_limited"
  std::string message;      ///< detail for failures (empty otherwise)
  long evaluations = 0;
  bool found = false;  ///< evaluated at least one valid point
  std::vector<double> best_x;
  double best_objective = 0.0;
  bool best_feasible = false;
};

struct SearchResult {
  std::string algorithm;    ///< as configured
  std::string method;       ///< what ran, e.g. "AUGLAG(LN_BOBYQA)"
  std::string stop_reason;  ///< of the start that found the chosen point
  long evaluations = 0;
  long invalid_evaluations = 0;
  double run_time_s = 0.0;
  std::vector<StartResult> starts;
  /// Distinct evaluated points, best first: feasible ones by objective, then
  /// infeasible ones by total constraint violation, invalid ones never.
  std::vector<std::vector<double>> candidates;
  int feasible_candidates = 0;  ///< how many of the leading candidates are feasible
};

/// Runs the search. Throws InputError only for a problem that cannot be set
/// up (dimension 0, bounds not ordered); NLopt failures are stop reasons.
/// `progress` is called under a lock (one call at a time) after each evaluation.
SearchResult run_search(const SearchProblem& problem, const SearchSettings& config,
                        const std::function<void(const SearchProgress&)>& progress = {});

/// Whether run_search spreads the starts over the MPI ranks when the
/// problem asks it to: a local algorithm with several starts, and several ranks.
bool starts_over_ranks(const SearchSettings& config);

/// NLopt's result code as a stop reason: "success", "stopval_reached",
/// "ftol_reached", "xtol_reached", "maxeval_reached", "maxtime_reached",
/// "failure", "invalid_args", "out_of_memory", "roundoff_limited", "forced_stop".
std::string nlopt_result_name(int code);

}  // namespace camdyn::optim
