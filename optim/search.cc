#include "optim/search.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <new>
#include <nlopt.hpp>
#include <numeric>
#include <random>
#include <stdexcept>
#include <utility>

#include "common/errors.h"
#include "common/parallel.h"
#include "io/config.h"
#include "io/hex_doubles.h"
#include "study/mpi_runner.h"

namespace camdyn::optim {

namespace {

using Clock = std::chrono::steady_clock;

/// Constraint tolerance handed to NLopt: residuals are normalised (O(1)), so
/// this is a relative violation that counts as satisfied by NLopt's own tests.
constexpr double kConstraintTolerance = 1e-8;
/// How many of the best points the caller gets to re-evaluate.
constexpr std::size_t kCandidates = 8;

nlopt::algorithm algorithm_of(const std::string& name) {
  if (name == "LN_COBYLA") return nlopt::LN_COBYLA;
  if (name == "LN_BOBYQA") return nlopt::LN_BOBYQA;
  if (name == "LN_SBPLX") return nlopt::LN_SBPLX;
  if (name == "LD_SLSQP") return nlopt::LD_SLSQP;
  if (name == "LD_MMA") return nlopt::LD_MMA;
  if (name == "GN_ISRES") return nlopt::GN_ISRES;
  if (name == "GN_CRS2_LM") return nlopt::GN_CRS2_LM;
  if (name == "GN_DIRECT_L") return nlopt::GN_DIRECT_L;
  throw InputError("", "optimizer.algorithm", "unknown algorithm '" + name + "'");
}

bool is_global(const std::string& name) { return name.rfind("GN_", 0) == 0; }
bool uses_gradient(const std::string& name) { return name.rfind("LD_", 0) == 0; }
bool has_native_constraints(const std::string& name) {
  return name == "LN_COBYLA" || name == "LD_SLSQP" || name == "LD_MMA" || name == "GN_ISRES";
}

/// Thrown by our callbacks when the evaluation budget of a start is used up
/// (NLopt's own maxeval does not count finite-difference probes); nlopt.hpp
/// turns it into a forced stop.
struct BudgetExhausted : nlopt::forced_stop {};

struct Entry {
  PointValue value;
  double violation = 0.0;
  /// (start, evaluation within the start): the evaluation order of the
  /// starts run one after the other, whatever threads ran them.
  std::pair<int, long> order;
};

/// What every start shares: the counters, the evaluated points of all starts
/// and the progress callback, behind one lock.
struct SharedPoints {
  std::mutex mutex;
  long total = 0, invalid = 0;
  std::map<std::vector<double>, Entry> all;
};

/// Callback state of one start: the evaluation cache, finite differences,
/// the budget and the best point.
class StartRun {
 public:
  StartRun(const SearchProblem& problem, const SearchSettings& config, int index, long budget, Clock::time_point t0,
           SharedPoints& shared, const std::function<void(const SearchProgress&)>& progress, int starts)
      : problem_(problem),
        config_(config),
        index_(index),
        budget_(budget),
        t0_(t0),
        shared_(shared),
        progress_(progress),
        starts_(starts) {}

  static double objective(unsigned n, const double* x, double* grad, void* data) {
    auto* self = static_cast<StartRun*>(data);
    const std::vector<double> point(x, x + n);
    const PointValue& v = self->value(point, PointKind::nlopt);
    if (grad != nullptr) {
      const Gradient& g = self->gradient(point);
      std::copy(g.objective.begin(), g.objective.end(), grad);
    }
    return v.objective;
  }

  static void constraints(unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
    auto* self = static_cast<StartRun*>(data);
    const std::vector<double> point(x, x + n);
    const PointValue& v = self->value(point, PointKind::nlopt);
    std::copy(v.residuals.begin(), v.residuals.begin() + m, result);
    if (grad != nullptr) {
      const Gradient& g = self->gradient(point);
      std::copy(g.jacobian.begin(), g.jacobian.end(), grad);  // row-major m × n
    }
  }

  bool budget_exhausted() const { return exhausted_; }
  long evaluations() const { return evaluations_; }
  bool found() const { return has_best_; }
  const std::vector<double>& best_x() const { return best_x_; }
  const Entry& best() const { return best_; }

 private:
  struct Gradient {
    std::vector<double> objective;  ///< n
    std::vector<double> jacobian;   ///< m × n, row-major
  };

  const PointValue& value(const std::vector<double>& x, PointKind kind) {
    if (auto it = cache_.find(x); it != cache_.end()) return it->second;
    if (evaluations_ >= budget_) {
      exhausted_ = true;
      throw BudgetExhausted();
    }
    PointValue v = problem_.evaluate(x, index_, kind);
    if (v.residuals.size() != static_cast<std::size_t>(problem_.constraint_count))
      throw std::logic_error("search: evaluate returned the wrong number of constraint residuals");
    ++evaluations_;
    Entry e{v, 0.0, {index_, evaluations_}};
    for (double r : v.residuals) e.violation += std::max(0.0, r);
    if (v.valid && (!has_best_ || better(e, best_))) {
      has_best_ = true;
      best_ = e;
      best_x_ = x;
    }
    {
      const std::lock_guard<std::mutex> lock(shared_.mutex);
      ++shared_.total;
      if (!v.valid) ++shared_.invalid;
      // A point two starts evaluated keeps the earlier start's entry, as when they run in turn.
      if (v.valid) {
        const auto [it, added] = shared_.all.emplace(x, e);
        if (!added && e.order < it->second.order) it->second = e;
      }
      report();
    }
    return cache_.emplace(x, std::move(v)).first->second;
  }

  const Gradient& gradient(const std::vector<double>& x) {
    if (auto it = gradients_.find(x); it != gradients_.end()) return it->second;
    const PointValue base = value(x, PointKind::nlopt);
    const std::size_t n = x.size(), m = base.residuals.size();
    Gradient g{std::vector<double>(n), std::vector<double>(m * n)};
    for (std::size_t j = 0; j < n; ++j) {
      std::vector<double> probe = x;
      double h = config_.gradient_step * (problem_.upper[j] - problem_.lower[j]);
      if (probe[j] + h > problem_.upper[j]) h = -h;  // stay inside the box
      probe[j] += h;
      h = probe[j] - x[j];  // the step actually taken
      const PointValue& v = value(probe, PointKind::gradient);
      g.objective[j] = (v.objective - base.objective) / h;
      for (std::size_t i = 0; i < m; ++i) g.jacobian[i * n + j] = (v.residuals[i] - base.residuals[i]) / h;
    }
    return gradients_.emplace(x, std::move(g)).first->second;
  }

  void report() {
    if (!progress_) return;
    const double elapsed = std::chrono::duration<double>(Clock::now() - t0_).count();
    progress_({shared_.total, index_, starts_, best_.value.objective, has_best_ && best_.value.feasible,
               elapsed > 0.0 ? static_cast<double>(shared_.total) / elapsed : 0.0});
  }

 public:
  /// Feasible before infeasible; then by objective, or by violation.
  static bool better(const Entry& a, const Entry& b) {
    if (a.value.feasible != b.value.feasible) return a.value.feasible;
    if (a.value.feasible) return a.value.objective < b.value.objective;
    if (a.violation != b.violation) return a.violation < b.violation;
    return a.value.objective < b.value.objective;
  }

 private:
  const SearchProblem& problem_;
  const SearchSettings& config_;
  int index_;
  long budget_;
  Clock::time_point t0_;
  SharedPoints& shared_;
  const std::function<void(const SearchProgress&)>& progress_;
  int starts_;

  std::map<std::vector<double>, PointValue> cache_;
  std::map<std::vector<double>, Gradient> gradients_;
  long evaluations_ = 0;
  bool exhausted_ = false;
  bool has_best_ = false;
  Entry best_;
  std::vector<double> best_x_;
};

/// Sets the stopping criteria shared by an optimiser and its subsidiary.
void set_tolerances(nlopt::opt& opt, const SearchSettings& config) {
  opt.set_xtol_rel(config.xtol_rel);
  opt.set_ftol_rel(config.ftol_rel);
}

/// Throws for a problem that cannot be set up: no variables, bounds of the
/// wrong size or not ordered.
void check_problem(const SearchProblem& problem) {
  const std::size_t n = problem.x0.size();
  if (n == 0) throw InputError("", "design", "the design has no variables");
  if (problem.lower.size() != n || problem.upper.size() != n)
    throw std::logic_error("search: bounds and x0 differ in size");
  for (std::size_t j = 0; j < n; ++j) {
    if (!(problem.lower[j] < problem.upper[j]))
      throw InputError("", "design", "variable " + std::to_string(j) + " has empty bounds");
  }
}

/// What every start shares: the algorithm, the clock, the counters and the
/// evaluated points of all starts.
struct SearchSetup {
  nlopt::algorithm algorithm = nlopt::NUM_ALGORITHMS;  ///< of config.algorithm (set by run_search)
  bool auglag = false;                                 ///< the algorithm runs as AUGLAG's subsidiary
  int starts = 1;
  Clock::time_point t0;
  std::vector<double> step;  ///< initial step of each variable (its share of the box)
  SharedPoints shared;
  /// nlopt::srand sets a process-wide seed: one start at a time seeds and builds its optimiser.
  std::mutex seed_mutex;
};

/// Sets up the NLopt optimiser of one start (AUGLAG when setup.auglag) with
/// `budget` evaluations and its callbacks on `run`. It is set up in place, not
/// returned: nlopt.hpp's callback data points back at the optimiser object.
void configure_optimizer(nlopt::opt& opt, const SearchProblem& problem, const SearchSettings& config,
                         const SearchSetup& setup, long budget, StartRun& run) {
  const std::size_t n = problem.x0.size();
  opt.set_lower_bounds(problem.lower);
  opt.set_upper_bounds(problem.upper);
  opt.set_min_objective(&StartRun::objective, &run);
  if (problem.constraint_count > 0) {
    opt.add_inequality_mconstraint(&StartRun::constraints, &run,
                                   std::vector<double>(problem.constraint_count, kConstraintTolerance));
  }
  set_tolerances(opt, config);
  // NLopt counts its own calls only; with finite differences each gradient
  // costs n more, so its budget is cut to match ours (ours is enforced too).
  const long nlopt_budget =
      uses_gradient(config.algorithm) ? std::max<long>(1, budget / static_cast<long>(n + 1)) : budget;
  opt.set_maxeval(static_cast<int>(nlopt_budget));
  if (config.max_time_s) {
    const double left = *config.max_time_s - std::chrono::duration<double>(Clock::now() - setup.t0).count();
    opt.set_maxtime(std::max(left, 1e-3));
  }
  if (!is_global(config.algorithm) && !uses_gradient(config.algorithm)) opt.set_initial_step(setup.step);
  if (setup.auglag) {
    nlopt::opt sub(setup.algorithm, static_cast<unsigned>(n));
    sub.set_lower_bounds(problem.lower);
    sub.set_upper_bounds(problem.upper);
    set_tolerances(sub, config);
    // A global subsidiary would spend the whole budget on the first
    // penalty parameter: give each subproblem a share.
    if (is_global(config.algorithm))
      sub.set_maxeval(static_cast<int>(std::max<long>(1, budget / 4)));
    else
      sub.set_initial_step(setup.step);
    opt.set_local_optimizer(sub);
  }
}

/// The first point of each start: x0 for the first, seeded random points of
/// the box for the others, drawn in start order before any start runs.
std::vector<std::vector<double>> start_points(const SearchProblem& problem, const SearchSettings& config, int starts) {
  const std::size_t n = problem.x0.size();
  std::mt19937_64 rng(static_cast<unsigned long>(config.seed));
  std::vector<std::vector<double>> points;
  for (int s = 0; s < starts; ++s) {
    std::vector<double> x0 = problem.x0;
    if (s > 0) {
      for (std::size_t j = 0; j < n; ++j)
        x0[j] = std::uniform_real_distribution<double>(problem.lower[j], problem.upper[j])(rng);
    }
    for (std::size_t j = 0; j < n; ++j) x0[j] = std::clamp(x0[j], problem.lower[j], problem.upper[j]);
    points.push_back(std::move(x0));
  }
  return points;
}

/// Start s from x0; every NLopt status and exception becomes its stop reason.
StartResult run_start(const SearchProblem& problem, const SearchSettings& config, int s, std::vector<double> x0,
                      SearchSetup& setup, SharedPoints& shared,
                      const std::function<void(const SearchProgress&)>& progress) {
  const std::size_t n = problem.x0.size();
  StartResult sr;
  sr.index = s;
  sr.x0 = std::move(x0);
  const int starts = setup.starts;
  const long budget = config.max_evaluations / starts + (s < config.max_evaluations % starts ? 1 : 0);
  StartRun run(problem, config, s, budget, setup.t0, shared, progress, starts);

  try {
    std::unique_lock<std::mutex> seeding(setup.seed_mutex);
    // Reproducible stochastic algorithms (ISRES, CRS2) for a given seed.
    nlopt::srand(static_cast<unsigned long>(config.seed) + static_cast<unsigned long>(s));
    nlopt::opt opt(setup.auglag ? nlopt::AUGLAG : setup.algorithm, static_cast<unsigned>(n));
    configure_optimizer(opt, problem, config, setup, budget, run);
    // A global algorithm draws from the seed as it runs: it keeps the lock (it
    // runs alone: one start); a local one draws nothing and lets the others seed.
    if (!is_global(config.algorithm)) seeding.unlock();
    std::vector<double> x = sr.x0;
    double f = 0.0;
    const nlopt::result r = opt.optimize(x, f);
    sr.stop_reason = nlopt_result_name(r);
  } catch (const BudgetExhausted&) {
    sr.stop_reason = "maxeval_reached";
    sr.message = "evaluation budget used up (finite-difference probes included)";
  } catch (const nlopt::roundoff_limited&) {
    sr.stop_reason = "roundoff_limited";
    sr.message = "NLopt stopped: roundoff errors limited progress (the best point found is kept)";
  } catch (const nlopt::forced_stop&) {
    sr.stop_reason = run.budget_exhausted() ? "maxeval_reached" : "forced_stop";
    if (run.budget_exhausted()) sr.message = "evaluation budget used up (finite-difference probes included)";
  } catch (const std::invalid_argument& e) {
    sr.stop_reason = "invalid_args";
    sr.message = e.what();
  } catch (const std::bad_alloc&) {
    sr.stop_reason = "out_of_memory";
  } catch (const std::runtime_error& e) {
    sr.stop_reason = "failure";
    sr.message = e.what();
  }
  sr.evaluations = run.evaluations();
  sr.found = run.found();
  if (sr.found) {
    sr.best_x = run.best_x();
    sr.best_objective = run.best().value.objective;
    sr.best_feasible = run.best().value.feasible;
  }
  return sr;
}

/// The best kCandidates of all evaluated points into out.candidates (ties in
/// evaluation order), and the stop reason of the start that found the first.
void rank_candidates(const std::map<std::vector<double>, Entry>& all, SearchResult& out) {
  std::vector<std::pair<std::vector<double>, Entry>> ranked(all.begin(), all.end());
  std::sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) {
    if (StartRun::better(a.second, b.second)) return true;
    if (StartRun::better(b.second, a.second)) return false;
    return a.second.order < b.second.order;
  });
  for (std::size_t i = 0; i < ranked.size() && i < kCandidates; ++i) {
    out.candidates.push_back(ranked[i].first);
    if (ranked[i].second.value.feasible) ++out.feasible_candidates;
  }
  out.stop_reason = out.starts.front().stop_reason;
  if (!out.candidates.empty()) {
    for (const StartResult& sr : out.starts)
      if (sr.found && sr.best_x == out.candidates.front()) out.stop_reason = sr.stop_reason;
  }
}

/// The record of start `sr`, run on a rank other than 0, for rank 0: its
/// result, its counters and its valid points (`shared` holds this start's
/// only), every double as hex; `caller` is SearchProblem::start_record's text.
std::string start_record_text(const StartResult& sr, const SharedPoints& shared, std::string caller) {
  Json points = Json::array();
  for (const auto& [x, e] : shared.all) {
    std::vector<double> values{e.value.objective, e.violation};
    values.insert(values.end(), e.value.residuals.begin(), e.value.residuals.end());
    points.push_back(Json{{"x", doubles_to_hex(x)},
                          {"values", doubles_to_hex(values)},
                          {"feasible", e.value.feasible},
                          {"evaluation", e.order.second}});
  }
  const Json record{{"start", sr.index},
                    {"x0", doubles_to_hex(sr.x0)},
                    {"stop_reason", sr.stop_reason},
                    {"message", sr.message},
                    {"evaluations", sr.evaluations},
                    {"found", sr.found},
                    {"best_x", doubles_to_hex(sr.best_x)},
                    {"best", doubles_to_hex({sr.best_objective})},
                    {"best_feasible", sr.best_feasible},
                    {"total", shared.total},
                    {"invalid", shared.invalid},
                    {"points", std::move(points)},
                    {"caller", std::move(caller)}};
  return record.dump(-1, ' ', false, Json::error_handler_t::replace);
}

/// `count` doubles from the hex field `key` of a start record; throws if malformed.
std::vector<double> hex_of(const Json& record, const char* key, std::size_t count) {
  const auto values = doubles_from_hex(record.at(key).get_ref<const std::string&>(), count);
  if (!values) throw std::runtime_error(std::string("search: a start record's \"") + key + "\" is malformed");
  return *values;
}

/// Rank 0: a start record of another rank into the search's result and points
/// (a point two starts evaluated keeps the earlier start's entry, as in one process).
void take_start_record(const std::string& text, const SearchProblem& problem, SharedPoints& shared, SearchResult& out) {
  const Json record = Json::parse(text);
  const std::size_t n = problem.x0.size(), m = static_cast<std::size_t>(problem.constraint_count);
  StartResult sr;
  sr.index = record.at("start").get<int>();
  if (sr.index < 0 || static_cast<std::size_t>(sr.index) >= out.starts.size())
    throw std::runtime_error("search: a start record names no start of this search");
  sr.x0 = hex_of(record, "x0", n);
  sr.stop_reason = record.at("stop_reason").get<std::string>();
  sr.message = record.at("message").get<std::string>();
  sr.evaluations = record.at("evaluations").get<long>();
  sr.found = record.at("found").get<bool>();
  if (sr.found) sr.best_x = hex_of(record, "best_x", n);
  sr.best_objective = hex_of(record, "best", 1).front();
  sr.best_feasible = record.at("best_feasible").get<bool>();
  shared.total += record.at("total").get<long>();
  shared.invalid += record.at("invalid").get<long>();
  for (const Json& point : record.at("points")) {
    const std::vector<double> values = hex_of(point, "values", 2 + m);
    Entry e;
    e.value.objective = values[0];
    e.violation = values[1];
    e.value.residuals.assign(values.begin() + 2, values.end());
    e.value.feasible = point.at("feasible").get<bool>();
    e.order = {sr.index, point.at("evaluation").get<long>()};
    const auto [it, added] = shared.all.emplace(hex_of(point, "x", n), e);
    if (!added && e.order < it->second.order) it->second = e;
  }
  if (problem.take_start_record) problem.take_start_record(sr.index, record.at("caller").get<std::string>());
  out.starts[static_cast<std::size_t>(sr.index)] = std::move(sr);
}

/// The starts spread over the MPI ranks (start s on rank s mod N, one at a
/// time): rank 0 runs its own into setup.shared and takes the others' records.
/// A failure on any rank ends every rank (exit 1): the others would wait for it.
void run_starts_over_ranks(const SearchProblem& problem, const SearchSettings& config,
                           std::vector<std::vector<double>>& points, SearchSetup& setup,
                           const std::function<void(const SearchProgress&)>& progress, SearchResult& out) {
  const bool root = mpi::rank() == 0;
  std::vector<std::size_t> indices(out.starts.size());
  std::iota(indices.begin(), indices.end(), std::size_t{0});
  try {
    mpi::distribute_runs(
        indices,
        [&](std::size_t s) {
          const int start = static_cast<int>(s);
          if (root) {
            out.starts[s] = run_start(problem, config, start, std::move(points[s]), setup, setup.shared, progress);
            return std::string();  // already in place
          }
          SharedPoints own;
          out.starts[s] = run_start(problem, config, start, std::move(points[s]), setup, own, progress);
          return start_record_text(out.starts[s], own, problem.start_record ? problem.start_record(start) : "");
        },
        [&](const std::string& text) {
          if (!text.empty()) take_start_record(text, problem, setup.shared, out);
        });
  } catch (const std::exception& e) {
    std::cerr << "camdyn: error: rank " << mpi::rank() << ": " << e.what() << "\n";
    mpi::abort_all(1);
  }
}

}  // namespace

bool starts_over_ranks(const SearchSettings& config) {
  return !is_global(config.algorithm) && config.starts > 1 && mpi::size() > 1;
}

std::string nlopt_result_name(int code) {
  switch (code) {
    case NLOPT_SUCCESS:
      return "success";
    case NLOPT_STOPVAL_REACHED:
      return "stopval_reached";
    case NLOPT_FTOL_REACHED:
      return "ftol_reached";
    case NLOPT_XTOL_REACHED:
      return "xtol_reached";
    case NLOPT_MAXEVAL_REACHED:
      return "maxeval_reached";
    case NLOPT_MAXTIME_REACHED:
      return "maxtime_reached";
    case NLOPT_FAILURE:
      return "failure";
    case NLOPT_INVALID_ARGS:
      return "invalid_args";
    case NLOPT_OUT_OF_MEMORY:
      return "out_of_memory";
    case NLOPT_ROUNDOFF_LIMITED:
      return "roundoff_limited";
    case NLOPT_FORCED_STOP:
      return "forced_stop";
    default:
      return "unknown_status_" + std::to_string(code);
  }
}

SearchResult run_search(const SearchProblem& problem, const SearchSettings& config,
                        const std::function<void(const SearchProgress&)>& progress) {
  check_problem(problem);
  const std::size_t n = problem.x0.size();
  SearchSetup setup;
  setup.t0 = Clock::now();
  setup.algorithm = algorithm_of(config.algorithm);
  setup.auglag = problem.constraint_count > 0 && !has_native_constraints(config.algorithm);

  SearchResult out;
  out.algorithm = config.algorithm;
  out.method = setup.auglag ? "AUGLAG(" + config.algorithm + ")" : config.algorithm;
  setup.starts = is_global(config.algorithm) ? 1 : config.starts;
  setup.step.resize(n);
  for (std::size_t j = 0; j < n; ++j) setup.step[j] = config.initial_step * (problem.upper[j] - problem.lower[j]);

  std::vector<std::vector<double>> points = start_points(problem, config, setup.starts);
  out.starts.resize(static_cast<std::size_t>(setup.starts));
  if (problem.over_ranks && starts_over_ranks(config)) {
    run_starts_over_ranks(problem, config, points, setup, progress, out);
    if (mpi::rank() != 0) return out;  // rank 0 ranks the points
  } else {
    const int threads = is_global(config.algorithm) ? 1 : std::max(1, problem.parallel_starts);
    parallel_for(out.starts.size(), threads, [&](std::size_t s) {
      out.starts[s] =
          run_start(problem, config, static_cast<int>(s), std::move(points[s]), setup, setup.shared, progress);
    });
  }

  // The chosen start: the one whose best point is best.
  rank_candidates(setup.shared.all, out);
  out.evaluations = setup.shared.total;
  out.invalid_evaluations = setup.shared.invalid;
  out.run_time_s = std::chrono::duration<double>(Clock::now() - setup.t0).count();
  return out;
}

}  // namespace camdyn::optim
