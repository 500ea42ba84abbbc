#include "optim/optimize/optimize.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <nlopt.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/constants.h"
#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/contact_stress.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/held_train_force.h"
#include "dynamics/model.h"
#include "dynamics/spring_sizing.h"
#include "io/hex_doubles.h"
#include "io/json_archive.h"
#include "optim/optimize/certificate_text.h"
#include "optim/optimize/jump_bound.h"
#include "optim/optimize/optimize_checkpoint.h"
#include "study/mpi_runner.h"
#include "study/progress.h"
#include "study/study.h"

namespace camdyn::optim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double top_speed(const OptimizeStudyConfig& config) {
  return *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end());
}

/// The `simulate` config of a design at the top operating speed, read back
/// from its JSON so it is exactly what optimized.json holds.
SceneConfig simulate_scene(const SceneConfig& design, double rpm, const std::string& name, const std::string& file) {
  SceneConfig s = design;
  s.name = name;
  s.study = "simulate";
  s.mechanism.cam.rpm = rpm;
  return scene_from_json(to_json(s), ConfigSource{file, "."});
}

/// `mechanism.cam.rpm` set to the top operating speed where the document leaves it out.
Json with_default_rpm(const Json& doc) {
  Json d = doc;
  const auto speeds = d.find("operating_rpm");
  if (speeds == d.end() || !speeds->is_array() || speeds->empty()) return d;
  double top = 0.0;
  for (const Json& v : *speeds) {
    if (!v.is_number()) return d;  // reported by the study reader
    top = std::max(top, v.get<double>());
  }
  const auto mech = d.find("mechanism");
  if (mech == d.end() || !mech->is_object()) return d;
  const auto cam = mech->find("cam");
  if (cam == mech->end() || !cam->is_object() || cam->contains("rpm")) return d;
  (*cam)["rpm"] = std::min(top, kMaxCamRpm);  // a faster one is refused by the study reader, naming operating_rpm
  return d;
}

/// A progress line on stderr when options.progress is set.
void say(const OptimizeOptions& options, const char* what) {
  if (options.progress) std::fprintf(stderr, "  optimize: %s\n", what);
}

/// The best design of the search loop so far: valid, feasible before
/// infeasible, then the lowest objective.
struct BestSoFar {
  bool have = false;
  double objective = 0.0;
  bool feasible = false;

  /// Takes e when it is better; returns whether it did.
  bool update(const DesignEvaluation& e) {
    if (e.valid && (!have || (e.feasible && !feasible) || (e.feasible == feasible && e.objective < objective))) {
      have = true;
      objective = e.objective;
      feasible = e.feasible;
      return true;
    }
    return false;
  }
};

/// The history record of evaluation number `evaluation` (1-based) of design e,
/// with the best so far once e has been seen.
HistoryRecord history_record(const DesignEvaluation& e, long evaluation, int start, PointKind kind,
                             const BestSoFar& best) {
  HistoryRecord h;
  h.evaluation = evaluation;
  h.start = start;
  h.kind = kind;
  h.valid = e.valid;
  h.error = e.error;
  h.objective = e.objective;
  h.constraints = e.constraints;
  h.feasible = e.feasible;
  h.best_objective = best.have ? best.objective : e.objective;
  h.best_feasible = best.feasible;
  return h;
}

/// What the search sees of design e: objective, residuals, validity, feasibility.
PointValue point_value(const DesignEvaluation& e) {
  PointValue v;
  v.objective = e.objective;
  v.valid = e.valid;
  v.feasible = e.feasible;
  for (const ConstraintValue& c : e.constraints) v.residuals.push_back(c.residual);
  return v;
}

/// A search-progress printer for stderr (silent without options.progress):
/// evaluation i of max_evaluations, the best objective so far and the time
/// left if the search uses its whole budget (it may stop earlier); at most
/// one line per 0.2 s, and always the last evaluation.
std::function<void(const SearchProgress&)> progress_printer(const OptimizeOptions& options,
                                                            const OptimizerConfig& optimizer,
                                                            Clock::time_point loop_t0) {
  return [&options, &optimizer, loop_t0, last_print = -1.0](const SearchProgress& p) mutable {
    if (!options.progress) return;
    const double now = seconds_since(loop_t0);
    if (now - last_print < 0.2 && p.evaluations < optimizer.max_evaluations) return;
    last_print = now;
    const long max = optimizer.max_evaluations;
    const double left_s = remaining_iterations_s(p.evaluations, max, now);
    const std::string eta = p.evaluations >= max ? std::string("done")
                            : left_s < 0.0       ? format_time_left(left_s)
                                                 : format_time_left(left_s) + " at most";
    std::fprintf(stderr, "\r  optimize: evaluation %ld of %ld, best objective %.6g (%s), start %d/%d, %.1f/s, %s    ",
                 p.evaluations, max, p.best_objective, p.best_feasible ? "feasible" : "infeasible", p.start + 1,
                 p.starts, p.evaluations_per_second, eta.c_str());
    std::fflush(stderr);
  };
}

/// Counts `e` in out.budget_cut_evaluations when a budget cut one of its
/// simulations short (an invalid design for that reason, not a physical answer).
void note_budget_cut(const DesignEvaluation& e, OptimizeOutcome& out) {
  if (e.valid) return;
  const std::string budget = budget_that_cut(e.error);
  if (budget.empty()) return;
  ++out.budget_cut_evaluations;
  out.budget_cut_by.insert(budget);
}

/// The warm starts of the search loop (optimizer.warm_start; optim/simulation_pool.h):
/// per start, where its last valid evaluation ended at each operating speed.
/// An evaluation then depends on that start's earlier ones as well as on its
/// design, so each start's evaluations are remembered by design and a design
/// asked again by the same start gets its first evaluation back, as the
/// journal gives it back on resume (optim/optimize/optimize_journal.h): with
/// or without a journal, killed or not, the search sees the same values.
class WarmStarts {
 public:
  WarmStarts(const OptimizeStudyConfig& config, bool simulated)
      : on_(config.optimizer.warm_start && simulated), speeds_(config.operating_rpm.size()) {}

  /// Fills e with the evaluation start already made of x; false if none (or warm starts are off).
  bool recall(const std::vector<double>& x, int start, DesignEvaluation& e) const {
    if (!on_) return false;
    const auto hit = seen_.find({start, double_bits(x)});
    if (hit == seen_.end()) return false;
    e = hit->second;
    return true;
  }
  /// The settings of start's next evaluation: its warm points, and ask for the end points.
  void prepare(int start, EvaluationSettings& settings) {
    if (!on_) return;
    std::vector<std::optional<SectionPoint>>& points = points_[start];
    points.resize(speeds_);
    settings.warm = &points;
    settings.end_points = true;
  }
  /// After each evaluation of the search (simulated, replayed or recalled).
  void evaluated(const std::vector<double>& x, int start, const DesignEvaluation& e) {
    if (!on_) return;
    DesignEvaluation kept;  // what the search and the journal see, without the runs
    kept.valid = e.valid;
    kept.error = e.error;
    kept.objective = e.objective;
    kept.feasible = e.feasible;
    kept.constraints = e.constraints;
    kept.end_points = e.end_points;
    seen_.try_emplace({start, double_bits(x)}, std::move(kept));
    if (!e.valid || e.end_points.size() != speeds_) return;
    std::vector<std::optional<SectionPoint>>& points = points_[start];
    points.resize(speeds_);
    for (std::size_t i = 0; i < speeds_; ++i)
      if (e.end_points[i]) points[i] = e.end_points[i];
  }

 private:
  bool on_ = false;
  std::size_t speeds_ = 0;
  std::map<int, std::vector<std::optional<SectionPoint>>> points_;
  std::map<std::pair<int, std::vector<std::uint64_t>>, DesignEvaluation> seen_;
};

/// The evaluators of the search's starts. Starts that run one after the
/// other share the study's pool and evaluator; starts that run at once
/// (optimizer.starts > 1 and --jobs > 1) each get a SimulationPool and a
/// DesignEvaluator of their own (a pool runs one batch at a time), with the
/// study's constraints and normalisation, so an evaluation is the same
/// whichever thread makes it.
class StartEvaluators {
 public:
  StartEvaluators(const DesignEvaluator& main, SimulationPool& main_pool, const OptimizeStudyConfig& config,
                  std::string file, int parallel, int threads_each)
      : main_(main),
        main_pool_(main_pool),
        config_(config),
        file_(std::move(file)),
        parallel_(parallel),
        threads_each_(threads_each) {}

  int parallel() const { return parallel_; }

  /// The evaluator and pool of `start` (made on first use; thread-safe).
  std::pair<const DesignEvaluator*, SimulationPool*> of(int start) {
    if (parallel_ <= 1) return {&main_, &main_pool_};
    const std::lock_guard<std::mutex> lock(mutex_);
    Own& own = own_[start];
    if (!own.pool) {
      own.pool = std::make_unique<SimulationPool>(threads_each_, file_);
      own.evaluator = std::make_unique<DesignEvaluator>(config_, file_, *own.pool);
      if (own.evaluator->needs_simulation()) own.evaluator->require_no_separation_at(main_.proven_rpm());
      own.evaluator->set_normalisation(main_.normalisation());
    }
    return {own.evaluator.get(), own.pool.get()};
  }
  /// Over the starts' own pools (not the study's).
  long simulations() const { return sum(&SimulationPool::simulations); }
  long warm_kept() const { return sum(&SimulationPool::warm_kept); }
  long warm_rejected() const { return sum(&SimulationPool::warm_rejected); }

 private:
  struct Own {
    std::unique_ptr<SimulationPool> pool;
    std::unique_ptr<DesignEvaluator> evaluator;
  };
  long sum(long (SimulationPool::*count)() const) const {
    long n = 0;
    for (const auto& [start, own] : own_) n += ((*own.pool).*count)();
    return n;
  }

  const DesignEvaluator& main_;
  SimulationPool& main_pool_;
  const OptimizeStudyConfig& config_;
  std::string file_;
  int parallel_ = 1, threads_each_ = 1;
  std::mutex mutex_;
  std::map<int, Own> own_;
};

/// The search's starts spread over the MPI ranks (OptimizeOptions::over_ranks,
/// docs/optimize.md "MPI ranks"). On a rank other than 0 each evaluation of
/// its starts is kept as a journal record (optim/optimize/optimize_journal.h,
/// doubles as hex) with its point kind and whether it was simulated, and
/// each start's records go to rank 0 with the simulations and warm-start
/// counts of the rank's pool over that start (its starts run one at a time);
/// rank 0 books them as if its own loop had made them.
class RankStarts {
 public:
  RankStarts(const SimulationPool& pool, std::size_t dimension, std::size_t constraints)
      : pool_(pool),
        dimension_(dimension),
        constraints_(constraints),
        simulations_(pool.simulations()),
        warm_kept_(pool.warm_kept()),
        warm_rejected_(pool.warm_rejected()) {}

  /// A rank other than 0: evaluation e of x by `start`, `simulations` simulations (−1: not simulated here).
  void evaluated(const std::vector<double>& x, int start, PointKind kind, const DesignEvaluation& e, long simulations) {
    Json record = evaluation_record(x,
                                    JournaledEvaluation{e.valid, e.error, e.objective, e.feasible, e.constraints,
                                                        std::max(0L, simulations), start, e.end_points},
                                    true);
    record["gradient"] = kind == PointKind::gradient;
    record["simulated"] = simulations >= 0;
    records_[start].push_back(std::move(record));
  }
  /// A rank other than 0, after start `start`: its records and the pool's counts since the start before.
  std::string record(int start) {
    const Json text{{"evaluations", std::move(records_[start])},
                    {"simulations", pool_.simulations() - simulations_},
                    {"warm_kept", pool_.warm_kept() - warm_kept_},
                    {"warm_rejected", pool_.warm_rejected() - warm_rejected_}};
    records_.erase(start);
    simulations_ = pool_.simulations();
    warm_kept_ = pool_.warm_kept();
    warm_rejected_ = pool_.warm_rejected();
    return text.dump(-1, ' ', false, Json::error_handler_t::replace);
  }
  /// Rank 0: the records of start `start`, each to `book(x, kind, e, simulations or −1)` in order.
  void take(int start, const std::string& text,
            const std::function<void(const std::vector<double>&, PointKind, const DesignEvaluation&, long)>& book) {
    const Json taken = Json::parse(text);
    for (const Json& record : taken.at("evaluations")) {
      auto evaluation = evaluation_from_record(record, dimension_, constraints_);
      if (!evaluation || evaluation->second.start != start)
        throw std::runtime_error("optimize: a rank's evaluation record is malformed");
      const JournaledEvaluation& j = evaluation->second;
      DesignEvaluation e;
      fill_evaluation(j, e);
      book(evaluation->first, record.at("gradient").get<bool>() ? PointKind::gradient : PointKind::nlopt, e,
           record.at("simulated").get<bool>() ? j.simulations : -1);
    }
    taken_simulations += taken.at("simulations").get<long>();
    taken_warm_kept += taken.at("warm_kept").get<long>();
    taken_warm_rejected += taken.at("warm_rejected").get<long>();
  }

  long taken_simulations = 0, taken_warm_kept = 0, taken_warm_rejected = 0;  ///< rank 0: over the others' starts

 private:
  const SimulationPool& pool_;
  std::size_t dimension_ = 0, constraints_ = 0;
  long simulations_ = 0, warm_kept_ = 0, warm_rejected_ = 0;  ///< the pool's counts when the start began
  std::map<int, Json> records_;
};

/// After starts that ran at once: the history in the order of the starts
/// run one after the other (each start's evaluations in their order), numbered
/// and with the best so far as that run has them.
void order_history_by_start(std::vector<HistoryRecord>& history) {
  std::stable_sort(history.begin(), history.end(),
                   [](const HistoryRecord& a, const HistoryRecord& b) { return a.start < b.start; });
  BestSoFar best;
  for (std::size_t i = 0; i < history.size(); ++i) {
    HistoryRecord& h = history[i];
    DesignEvaluation e;
    e.valid = h.valid;
    e.objective = h.objective;
    e.feasible = h.feasible;
    best.update(e);
    h.evaluation = static_cast<long>(i) + 1;
    h.best_objective = best.have ? best.objective : h.objective;
    h.best_feasible = best.feasible;
  }
}

/// The search loop with the loop settings, from the initial design: fills
/// out.initial, out.history, out.search, out.loop_time_s and
/// out.loop_simulations; returns the simulations of the starts' own pools
/// (starts run at once, on --jobs threads) and, on rank 0, of the other
/// ranks' starts (over MPI ranks). Throws NumericalError when no
/// design was valid.
long search_designs(const DesignSpace& space, const DesignEvaluator& evaluator, SimulationPool& pool,
                    const OptimizeStudyConfig& config, const OptimizeOptions& options, const std::string& file,
                    LoopRecorder& recorder, OptimizeOutcome& out) {
  const EvaluationSettings loop = loop_settings(config.optimizer);
  out.initial = evaluator.evaluate(space.scene(out.x_initial), loop, out.loop_simulated);
  const long sims_before = pool.simulations();
  const bool local = config.optimizer.algorithm.rfind("GN_", 0) != 0;
  const bool ranks = options.over_ranks && starts_over_ranks(search_settings(config.optimizer));
  // Over MPI ranks each rank runs its starts one at a time, their simulations on its threads.
  const int parallel = local && !ranks ? std::clamp(options.threads, 1, config.optimizer.starts) : 1;
  StartEvaluators starts(evaluator, pool, config, file, parallel, std::max(1, options.threads / parallel));
  RankStarts rank_starts(pool, static_cast<std::size_t>(space.dimension()), out.constraints.size());
  const bool helper = ranks && mpi::rank() != 0;  // a rank that sends its starts to rank 0
  std::mutex book;                                // the bookkeeping below, shared by the starts
  BestSoFar best;
  // After each evaluation of the search, of this process's starts or (rank 0) another rank's.
  const auto keep = [&](const std::vector<double>& x, int start, PointKind kind, const DesignEvaluation& e) {
    note_budget_cut(e, out);
    const bool improved = best.update(e);
    out.history.push_back(history_record(e, static_cast<long>(out.history.size()) + 1, start, kind, best));
    recorder.evaluated(out, space, x, improved);
  };
  SearchProblem problem;
  problem.lower = space.lower();
  problem.upper = space.upper();
  problem.x0 = out.x_initial;
  problem.constraint_count = static_cast<int>(out.constraints.size());
  WarmStarts warm(config, out.loop_simulated);
  problem.parallel_starts = parallel;
  problem.evaluate = [&](const std::vector<double>& x, int start, PointKind kind) {
    std::unique_lock<std::mutex> lock(book);
    // The outputs cannot be kept, or the study's time is up: stop every start.
    if (recorder.failed() || study_budget_exhausted()) throw nlopt::forced_stop();
    DesignEvaluation e;
    long simulated = -1;  // the simulations of an evaluation made here
    if (!warm.recall(x, start, e) && !recorder.replay(x, start, e)) {
      EvaluationSettings settings = loop;
      warm.prepare(start, settings);
      lock.unlock();
      const auto [own, own_pool] = starts.of(start);
      const long sims = own_pool->simulations();
      try {
        e = own->evaluate(space.scene(x), settings, out.loop_simulated);
      } catch (const InputError& err) {  // a spline the geometry code refuses
        e.valid = false;
        e.error = err.what();
        own->score(e);
      }
      lock.lock();
      simulated = own_pool->simulations() - sims;
      recorder.journal(x, start, e, simulated);
    }
    warm.evaluated(x, start, e);
    if (helper) rank_starts.evaluated(x, start, kind, e, simulated);
    keep(x, start, kind, e);
    if (recorder.failed()) throw nlopt::forced_stop();
    return point_value(e);
  };
  problem.over_ranks = ranks;
  problem.start_record = [&](int start) { return rank_starts.record(start); };
  problem.take_start_record = [&](int start, const std::string& text) {
    rank_starts.take(start, text,
                     [&](const std::vector<double>& x, PointKind kind, const DesignEvaluation& e, long sims) {
                       if (sims >= 0) recorder.journal(x, start, e, sims);
                       keep(x, start, kind, e);
                     });
  };
  const auto loop_t0 = Clock::now();
  out.search =
      run_search(problem, search_settings(config.optimizer), progress_printer(options, config.optimizer, loop_t0));
  if (helper) return 0;  // rank 0 has the search's result
  recorder.rethrow();
  if (study_budget_exhausted())
    throw NumericalError(
        study_budget_text() + " after " + std::to_string(out.history.size()) + " evaluations of the search" +
        (recorder.journal_path().empty()
             ? std::string()
             : "; they are kept in " + recorder.journal_path().string() + ": " + study_rerun_advice()));
  out.loop_time_s = seconds_since(loop_t0);
  out.resumed_simulations = recorder.replayed_simulations();
  if (parallel > 1 || ranks) order_history_by_start(out.history);
  out.loop_simulations =
      pool.simulations() - sims_before + starts.simulations() + out.resumed_simulations + rank_starts.taken_simulations;
  out.warm_kept = pool.warm_kept() + starts.warm_kept() + rank_starts.taken_warm_kept;
  out.warm_rejected = pool.warm_rejected() + starts.warm_rejected() + rank_starts.taken_warm_rejected;
  if (options.progress) std::fprintf(stderr, "\n");
  if (out.search.candidates.empty())
    throw NumericalError("the optimiser found no valid design in " + std::to_string(out.search.evaluations) +
                         " evaluations (stop reason " + out.search.stop_reason + ")" +
                         (out.budget_cut_by.empty() ? std::string()
                                                    : "; " + std::to_string(out.budget_cut_evaluations) +
                                                          " of them were cut short by a budget (" +
                                                          out.budget_cut_names() + "), which proves nothing"));
  return starts.simulations() + rank_starts.taken_simulations;
}

/// `scene` with the study's geometric constraints that design `e` meets as
/// `mechanism.cam.limits`, so `camdyn validate optimized.json` re-checks them
/// (one it breaks is left out, or optimized.json could not be run at all;
/// result.json reports it).
SceneConfig with_limits(const SceneConfig& scene, const std::vector<ConstraintSpec>& specs, const DesignEvaluation& e) {
  SceneConfig s = scene;
  CamLimitsConfig& l = s.mechanism.cam.limits;
  for (std::size_t i = 0; i < specs.size() && i < e.constraints.size(); ++i) {
    if (!e.constraints[i].holds) continue;
    if (specs[i].name == "max_pressure_angle_deg") l.max_pressure_angle_deg = specs[i].limit;
    if (specs[i].name == "min_radius_of_curvature") l.min_radius_of_curvature = specs[i].limit;
    if (specs[i].name == "max_peak_jerk") l.max_peak_jerk = specs[i].limit;
    if (specs[i].name == "max_contact_stress") l.max_contact_stress = specs[i].limit;
  }
  return s;
}

/// A design of the search re-evaluated with the scene's settings.
struct Candidate {
  DesignEvaluation evaluation;
  SceneConfig scene;  ///< its `simulate` config
  std::vector<double> x;
};

/// The best loop designs with the scene's settings (`full`): the first that
/// holds every constraint there wins (the loop settings are cheaper and can
/// differ near a constraint boundary); if none does, the best of the loop.
/// Fills out.optimized, out.optimized_scene, out.x_optimized and
/// out.candidates_tried; throws NumericalError when none can be simulated.
void choose_optimized(const DesignSpace& space, const DesignEvaluator& evaluator, const EvaluationSettings& full,
                      const std::string& name, double top, const std::string& file, OptimizeOutcome& out) {
  std::optional<Candidate> fallback;
  // Designs infeasible in the loop are not worth a second look: only the best one is tried then.
  const std::size_t tries = std::max<std::size_t>(1, static_cast<std::size_t>(out.search.feasible_candidates));
  for (std::size_t k = 0; k < tries && k < out.search.candidates.size(); ++k) {
    const std::vector<double>& x = out.search.candidates[k];
    ++out.candidates_tried;
    const SceneConfig scene = simulate_scene(space.scene(x), top, name, file);
    DesignEvaluation e = evaluator.evaluate(scene, full, true);
    note_budget_cut(e, out);
    if (e.valid && e.feasible) {
      out.optimized_scene = with_limits(scene, out.constraints, e);
      out.optimized = std::move(e);
      out.x_optimized = x;
      return;
    }
    if (e.valid && !fallback) fallback = Candidate{e, with_limits(scene, out.constraints, e), x};
  }
  if (!fallback)
    throw NumericalError(
        "none of the " + std::to_string(out.candidates_tried) +
        " best designs of the search could be simulated with the scene's settings" +
        (out.budget_cut_by.empty() ? std::string() : " (a budget cut them short: " + out.budget_cut_names() + ")"));
  out.optimized = std::move(fallback->evaluation);
  out.optimized_scene = std::move(fallback->scene);
  out.x_optimized = std::move(fallback->x);
}

/// The steady-state check of the chosen design from its verification (the
/// metrics over the periodic orbits) against its window's objective.
SteadyStateCheck steady_state_check(const DesignEvaluation& verified, double window_objective) {
  SteadyStateCheck c;
  if (!verified.valid) {
    c.reason = "the design could not be simulated for its steady state: " + verified.error;
    return c;
  }
  c.checked = true;
  c.speeds = static_cast<int>(verified.speeds.size());
  for (const SpeedResult& speed : verified.speeds) {
    if (speed.result.metrics_over == "periodic_orbit") ++c.speeds_on_orbit;
    c.notes.push_back(format_shortest(speed.rpm) + " rpm: " + speed.result.metrics_note);
  }
  c.objective = verified.objective;
  c.relative_change = std::abs(verified.objective - window_objective) / std::max(std::abs(window_objective), 1e-12);
  c.agrees = c.relative_change <= WindowCheck::kTolerance;
  return c;
}

WindowCheck check_window(const DesignEvaluator& evaluator, const OptimizeOutcome& out) {
  WindowCheck w;
  const SimulationConfig& sim = out.optimized_scene.simulation;
  if (!evaluator.needs_simulation()) {
    w.reason = "the objective and constraints are kinematic";
    return w;
  }
  if (!sim.cycles || sim.duration) {
    w.reason = "the scene sets simulation.duration, not cycles";
    return w;
  }
  w.evaluated_cycles = *sim.cycles - sim.discard_cycles;
  w.doubled_cycles = sim.discard_cycles + 2.0 * w.evaluated_cycles;
  EvaluationSettings doubled;
  doubled.cycles = w.doubled_cycles;
  const DesignEvaluation e = evaluator.evaluate(out.optimized_scene, doubled, true);
  if (!e.valid) {
    w.reason = "the design could not be simulated over the longer window: " + e.error;
    return w;
  }
  w.checked = true;
  w.objective = out.optimized.objective;
  w.objective_doubled = e.objective;
  w.feasible_doubled = e.feasible;
  w.relative_change = std::abs(e.objective - w.objective) / std::max(std::abs(w.objective), 1e-12);
  w.converged = w.relative_change <= WindowCheck::kTolerance && e.feasible == out.optimized.feasible;
  if (out.optimized_scene.simulation.steady_state)
    w.steady_state.reason = "the loop's evaluations were on the steady state (simulation.steady_state)";
  else
    w.steady_state = steady_state_check(out.selection.chosen().verified, out.optimized.objective);
  return w;
}

/// The seat's constraints need a seat (docs/config.md): without one there is
/// neither seat bounce nor lash take-up.
void check_seat_constraints(const Model& model, const ConstraintsConfig& c, const std::string& file) {
  if (model.take_up.applies) return;
  const char* const needs =
      "needs a seat (`seat` on the follower or a train body): without one there is no seat bounce and no lash "
      "take-up (docs/valvetrain.md)";
  if (c.max_seat_bounce_height) throw InputError(file, "constraints.max_seat_bounce_height", needs);
  if (c.max_take_up_bounces) throw InputError(file, "constraints.max_take_up_bounces", needs);
}

/// The operating speeds the rigid stage proved jump-free: its design's
/// rigid-model margin P − P_min (the built law sampled densely) is ≥ 0 there.
std::vector<double> proven_speeds(const RigidStageResult& rigid, const OptimizeStudyConfig& config) {
  std::vector<double> out;
  if (!rigid.design.have) return out;
  for (std::size_t i = 0; i < config.operating_rpm.size() && i < rigid.design.verified_margin.size(); ++i)
    if (rigid.design.verified_margin[i] >= 0.0) out.push_back(config.operating_rpm[i]);
  return out;
}

/// Candidate `scene` verified: the scene's settings, the metrics over the
/// steady state at every operating speed (its `window` evaluation when the
/// scene already asks for the steady state).
CandidateVerification verify(CandidateKind kind, const SceneConfig& scene, const DesignEvaluator& evaluator,
                             const DesignEvaluation& window) {
  CandidateVerification v;
  v.kind = kind;
  v.available = true;
  if (scene.simulation.steady_state) {
    v.verified = window;
  } else {
    SceneConfig s = scene;
    s.simulation.steady_state = true;
    v.verified = evaluator.evaluate(s, {}, true);
  }
  for (const SpeedResult& speed : v.verified.speeds) {
    const Metrics& m = speed.result.metrics;
    // A train separates at the cam or at a link, in float (docs/optimize.md "Trains", docs/valvetrain.md).
    if (!separates(m)) continue;
    v.separating_rpm.push_back(speed.rpm);
    if (m.train) v.lets_go.emplace_back(m.train->separates_first, m.train->separates_first_deg);
  }
  return v;
}

/// What the choice needs of a verified candidate.
CandidateScore score_of(const CandidateVerification& c, const std::vector<ConstraintSpec>& specs,
                        const std::vector<double>& proven_rpm) {
  CandidateScore s;
  s.kind = c.kind;
  s.available = c.available;
  s.valid = c.available && c.verified.valid;
  s.feasible = s.valid && c.verified.feasible;
  s.objective = c.verified.objective;
  for (std::size_t i = 0; i < specs.size() && i < c.verified.constraints.size(); ++i) {
    const ConstraintValue& v = c.verified.constraints[i];
    s.violation += std::max(v.residual, 0.0);
    if (!v.holds) s.violated.push_back(specs[i].name);
  }
  // The proven speeds, also where the search did not hold them (a kinematic search).
  const char* kProven = "no_separation_where_proven";
  for (double rpm : c.separating_rpm) {
    if (std::find(proven_rpm.begin(), proven_rpm.end(), rpm) == proven_rpm.end()) continue;
    if (std::find(s.violated.begin(), s.violated.end(), kProven) == s.violated.end()) {
      s.violated.emplace_back(kProven);
      s.feasible = false;
      s.violation += 1.0;
    }
  }
  return s;
}

/// The preload [N | N m] of the spring of body `body` in `scene` (0: the follower's).
double& spring_preload(SceneConfig& scene, int body) {
  return body == 0 ? scene.mechanism.follower.spring.preload
                   : scene.mechanism.train[static_cast<std::size_t>(body - 1)].spring.preload;
}

/// Scores every candidate of out.selection and chooses among them.
void choose_among(OptimizeOutcome& out) {
  std::vector<CandidateScore> scores;
  for (CandidateVerification& c : out.selection.candidates) {
    c.score = score_of(c, out.constraints, out.proven_rpm);
    scores.push_back(c.score);
  }
  out.selection.choice = choose_candidate(scores);
}

/// design.spring: `best` with the smallest preload that keeps the rigid-model
/// force ≥ P_min up to the top speed, verified and added to out.selection.
/// The simulated force dips below the rigid model's by the contact's and the
/// follower's own dynamics: where the verification finds the study's
/// min_contact_force short by Δ, the preload is raised by Δ (force is linear
/// in the preload on the rigid model) and verified again, at most kRaises times.
Candidate sized_spring_candidate(const Candidate& best, const DesignEvaluator& evaluator,
                                 const EvaluationSettings& full, const std::string& file, OptimizeOutcome& out) {
  constexpr int kRaises = 3;
  const auto& specs = out.constraints;
  const auto floor_at =
      std::find_if(specs.begin(), specs.end(), [](const ConstraintSpec& c) { return c.name == "min_contact_force"; });
  SceneConfig scene = best.scene;
  const SceneSpringSizing sized = size_scene_spring(scene, out.config, file);
  double& preload = spring_preload(scene, sized.body);
  if (sized.available) preload = sized.required_preload;  // else verified as it is
  for (int k = 0;; ++k) {
    DesignEvaluation e = evaluator.evaluate(scene, full, true);
    CandidateVerification v = verify(CandidateKind::spring, scene, evaluator, e);
    double shortfall = 0.0;
    if (floor_at != specs.end() && v.verified.valid) {
      const ConstraintValue& c = v.verified.constraints[static_cast<std::size_t>(floor_at - specs.begin())];
      if (!c.holds && c.value > 0.0) shortfall = -c.margin;  // in contact, below the floor
    }
    if (shortfall <= 0.0 || k == kRaises) {
      out.selection.candidates.push_back(std::move(v));
      return Candidate{std::move(e), scene, best.x};
    }
    preload += shortfall;
  }
}

/// The study's answer (optim/optimize/candidate_choice.h): the baseline, the
/// rigid design and the dynamic result (out.optimized from choose_optimized)
/// verified alike; with design.spring also the best of them with its
/// preload sized (docs/model.md §11). The best is kept as out.optimized and
/// out.optimized_scene.
void select_answer(const DesignSpace& space, const DesignEvaluator& evaluator, const EvaluationSettings& full,
                   const SceneConfig& baseline, const std::string& name, double top, const std::string& file,
                   OptimizeOutcome& out) {
  std::vector<CandidateVerification>& list = out.selection.candidates;
  list.clear();
  std::vector<std::optional<Candidate>> answers;  // beside `list`
  const SceneConfig base_scene = with_limits(simulate_scene(baseline, top, name, file), out.constraints, out.baseline);
  list.push_back(verify(CandidateKind::baseline, base_scene, evaluator, out.baseline));
  answers.push_back(Candidate{out.baseline, base_scene, {}});
  if (out.rigid.design.have) {
    SceneConfig scene = simulate_scene(space.scene(out.rigid.design.x), top, name, file);
    DesignEvaluation e = evaluator.evaluate(scene, full, true);
    scene = with_limits(scene, out.constraints, e);
    list.push_back(verify(CandidateKind::rigid, scene, evaluator, e));
    answers.push_back(Candidate{std::move(e), scene, out.rigid.design.x});
  } else {
    CandidateVerification none;
    none.kind = CandidateKind::rigid;
    none.reason = out.config.rigid.enabled ? "the rigid stage made no design" : "rigid.enabled is false";
    list.push_back(std::move(none));
    answers.emplace_back();
  }
  list.push_back(verify(CandidateKind::dynamic, out.optimized_scene, evaluator, out.optimized));
  answers.push_back(Candidate{out.optimized, out.optimized_scene, out.x_optimized});
  choose_among(out);
  if (out.config.design.spring) {
    const CandidateKind from = out.selection.choice.chosen;
    answers.push_back(sized_spring_candidate(*answers[static_cast<std::size_t>(from)], evaluator, full, file, out));
    list.back().sized_from = from;
    choose_among(out);
  }
  Candidate& chosen = *answers[static_cast<std::size_t>(out.selection.choice.chosen)];
  out.selection.lift_given_up = lift_given_up(out.config, out.baseline, chosen.evaluation, out.selection.choice.chosen);
  out.optimized = std::move(chosen.evaluation);
  out.optimized_scene = std::move(chosen.scene);
  out.x_optimized = std::move(chosen.x);
}

/// out.required_preload and out.required_stiffness of the chosen design up
/// to the top operating speed, with the rigid stage's P_min.
void size_chosen_spring(const std::string& file, OptimizeOutcome& out) {
  const SceneSpringSizing s = size_scene_spring(out.optimized_scene, out.config, file);
  out.required_preload = s.required_preload;
  out.required_stiffness = s.required_stiffness;
  out.required_preload_unit = s.unit;
  out.required_preload_spring = s.spring;
  out.required_preload_unavailable = s.available ? "" : s.reason;
  out.required_stiffness_unavailable = s.stiffness_reason;
}

}  // namespace

/// The spring sizing of `scene` up to the top operating speed, with the
/// rigid stage's P_min: the rigid model's (dynamics/spring_sizing.h), or on a
/// follower train the held train's (size_held_spring; docs/model.md §12).
SceneSpringSizing size_scene_spring(const SceneConfig& scene, const OptimizeStudyConfig& config,
                                    const std::string& file) {
  const Model model = build_model(scene, file);
  SceneSpringSizing out;
  out.unit = coordinate_units(model).force;
  if (rigid_figures_held(model)) {
    const HeldSpringSizing h =
        size_held_spring(model, rigid_min_contact_force(config), top_speed(config) * kRadPerSecondPerRpm);
    out.available = h.available;
    out.reason = h.reason;
    out.spring = h.spring;
    out.body = h.body;
    out.unit = h.unit;
    out.required_preload = h.available ? h.required_preload : std::numeric_limits<double>::quiet_NaN();
    out.required_stiffness = std::numeric_limits<double>::quiet_NaN();
    out.stiffness_reason =
        "not sized on a train: a rate changes the held train's modes, so the force is not linear in it";
    return out;
  }
  const std::optional<RigidFollower> follower = rigid_follower(model, rigid_min_contact_force(config));
  const std::optional<RigidSpringLoad> load =
      follower ? rigid_spring_load(model, follower->min_force) : std::optional<RigidSpringLoad>();
  if (!load) {  // some follower element has no linear part
    out.available = false;
    out.reason = kNoLinearPart;
    out.required_preload = out.required_stiffness = std::numeric_limits<double>::quiet_NaN();
    out.stiffness_reason = kNoLinearPart;
    return out;
  }
  const SpringSizing s = size_spring(*model.law, *load, top_speed(config) * kRadPerSecondPerRpm);
  out.required_preload = s.required_preload;
  out.required_stiffness = s.required_stiffness;
  return out;
}

/// out.withheld when the verification of a candidate was cut short by a
/// budget: the choice among the candidates (and "better than the baseline")
/// would rest on a run that says nothing about the physics.
void withhold_on_budget(OptimizeOutcome& out) {
  std::size_t cut = 0, verified = 0;
  for (const CandidateVerification& c : out.selection.candidates) {
    if (!c.available) continue;
    ++verified;
    const std::size_t before = out.budget_cut_evaluations;
    note_budget_cut(c.verified, out);
    cut += out.budget_cut_evaluations - before;
  }
  if (cut > 0)
    out.withheld = withheld_text(cut, verified, "verifications of the candidates", out.budget_cut_names(),
                                 "the choice of the answer (and whether it beats the baseline)");
}

std::string OptimizeOutcome::budget_cut_names() const {
  std::string names;
  for (const std::string& name : budget_cut_by) names += (names.empty() ? "" : ", ") + name;
  return names;
}

const CandidateVerification& Selection::chosen() const {
  for (const CandidateVerification& c : candidates)
    if (c.kind == choice.chosen) return c;
  static const CandidateVerification kNone;
  return kNone;
}

bool Selection::good() const {
  const CandidateVerification& c = chosen();
  return choice.feasible && choice.beats_baseline && c.verified.valid && c.separating_rpm.empty() &&
         lift_given_up.empty();
}

OptimizeStudy read_optimize_study(const Json& doc, const ConfigSource& source) {
  Json part;
  OptimizeStudy s;
  s.baseline = scene_from_study_json(with_default_rpm(doc), source, optimize_study_keys(), part);
  resolve_segment_groups(part, s.baseline.mechanism.cam.motion_law, source);  // [["rise", "return"]]: design.event
  s.config = optimize_config_from_json(part, source);
  return s;
}

void check_optimize(const SceneConfig& baseline, const OptimizeStudyConfig& config, const std::string& file) {
  const double cycles = config.optimizer.evaluation_cycles.value_or(baseline.simulation.cycles.value_or(0.0));
  if (config.optimizer.evaluation_cycles && cycles <= baseline.simulation.discard_cycles)
    throw InputError(file, "optimizer.evaluation_cycles",
                     "must be more than simulation.discard_cycles (" +
                         std::to_string(baseline.simulation.discard_cycles) + "), got " + format_shortest(cycles));
  if (config.constraints.max_contact_stress)
    require_line_contact(baseline.mechanism.contact, file, "constraints.max_contact_stress");
  for (double rpm : config.operating_rpm) {
    SceneConfig s = baseline;
    s.mechanism.cam.rpm = rpm;
    check_seat_constraints(build_model(s, file), config.constraints, file);  // geometry and contact law too
  }
  const DesignSpace space(baseline, config.design, file);  // the design against the baseline law
}

OptimizeOutcome run_optimize(const SceneConfig& baseline, const OptimizeStudyConfig& config, const std::string& file,
                             const OptimizeOptions& options) {
  const auto t0 = Clock::now();
  check_optimize(baseline, config, file);
  OptimizeOutcome out;
  out.config = config;
  const DesignSpace space(baseline, config.design, file);
  out.variables = space.variables();
  out.x_initial = space.initial();
  out.fit = space.fit_quality();
  if (config.rigid.enabled) {
    say(options, "rigid-model stage (linear programmes)");
    out.rigid = run_rigid_stage(baseline, config, space, file);
    if (out.rigid.design.have) out.x_initial = out.rigid.design.x;  // the dynamic stage starts from it
  }
  const int threads = std::clamp(options.threads, 1, static_cast<int>(config.operating_rpm.size()));
  SimulationPool pool(threads, file);
  DesignEvaluator evaluator(config, file, pool);
  // A speed the rigid stage proved jump-free stays so: a hard constraint of a
  // search that simulates (a kinematic search is not made to simulate for it;
  // the verification of the answer checks it either way).
  out.proven_rpm = proven_speeds(out.rigid, config);
  if (evaluator.needs_simulation()) evaluator.require_no_separation_at(out.proven_rpm);
  out.constraints = evaluator.constraints();
  out.loop_simulated = evaluator.needs_simulation();
  LoopRecorder recorder(options.checkpoint_dir, baseline, config, space, out.constraints.size(), file);
  out.resumed_evaluations = recorder.resumed_evaluations();
  if (out.resumed_evaluations > 0 && options.progress)
    std::fprintf(stderr, "  optimize: resuming: %zu evaluations of an earlier run replayed from %s\n",
                 out.resumed_evaluations, recorder.journal_path().c_str());

  // Baseline with the scene's settings: what the user has now, and the scales.
  say(options, "evaluating the baseline");
  EvaluationSettings full;
  full.record_series = true;
  out.baseline = evaluator.evaluate(baseline, full, true);
  if (!out.baseline.valid) throw NumericalError("the baseline could not be simulated: " + out.baseline.error);
  out.normalisation = evaluator.normalisation_from(out.baseline);
  evaluator.set_normalisation(out.normalisation);
  evaluator.score(out.baseline);

  say(options, "searching");
  const long start_pool_simulations = search_designs(space, evaluator, pool, config, options, file, recorder, out);
  if (options.over_ranks && mpi::rank() != 0) return out;  // rank 0 has every start's result

  say(options, "re-evaluating the best designs with the scene's settings");
  choose_optimized(space, evaluator, full, baseline.name + "-optimized", top_speed(config), file, out);
  say(options, "verifying the baseline, the rigid design and the dynamic result on the steady state");
  select_answer(space, evaluator, full, baseline, baseline.name + "-optimized", top_speed(config), file, out);
  withhold_on_budget(out);
  size_chosen_spring(file, out);
  if (out.rigid.certificate.available)  // the certificate's one "jump-free to" figure, of the answer too
    out.answer_jump_free_rpm = stage_jump_free_rpm(out.optimized_scene, config, file);
  say(options, "checking that the objective does not depend on the window");
  out.window_check = check_window(evaluator, out);
  out.simulations = pool.simulations() + start_pool_simulations + out.resumed_simulations;
  out.run_time_s = seconds_since(t0);
  return out;
}

}  // namespace camdyn::optim
