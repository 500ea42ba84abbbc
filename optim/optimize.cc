#include "optim/optimize.h"

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "common/errors.h"
#include "dynamics/model.h"
#include "io/json_archive.h"
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
  (*cam)["rpm"] = top;
  return d;
}

}  // namespace

OptimizeStudy read_optimize_study(const Json& doc, const ConfigSource& source) {
  Json part;
  OptimizeStudy s;
  s.baseline = scene_from_study_json(with_default_rpm(doc), source, optimize_study_keys(), part);
  s.config = optimize_config_from_json(part, source);
  return s;
}

void check_optimize(const SceneConfig& baseline, const OptimizeStudyConfig& config, const std::string& file) {
  const double cycles = config.optimizer.evaluation_cycles.value_or(baseline.simulation.cycles.value_or(0.0));
  if (config.optimizer.evaluation_cycles && cycles <= baseline.simulation.discard_cycles)
    throw InputError(file, "optimizer.evaluation_cycles",
                     "must be more than simulation.discard_cycles (" +
                         std::to_string(baseline.simulation.discard_cycles) + "), got " + format_shortest(cycles));
  for (double rpm : config.operating_rpm) {
    SceneConfig s = baseline;
    s.mechanism.cam.rpm = rpm;
    build_model(s, file);  // geometry and contact law of the baseline
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

  const int threads = std::clamp(options.threads, 1, static_cast<int>(config.operating_rpm.size()));
  SimulationPool pool(threads, file);
  DesignEvaluator evaluator(config, file, pool);
  out.constraints = evaluator.constraints();
  out.loop_simulated = evaluator.needs_simulation();
  const double top = top_speed(config);
  auto say = [&](const char* what) {
    if (options.progress) std::fprintf(stderr, "  optimize: %s\n", what);
  };

  // Baseline with the scene's settings: what the user has now, and the scales.
  say("evaluating the baseline");
  EvaluationSettings full;
  full.record_series = true;
  out.baseline = evaluator.evaluate(baseline, full, true);
  if (!out.baseline.valid) throw NumericalError("the baseline could not be simulated: " + out.baseline.error);
  out.normalisation = evaluator.normalisation_from(out.baseline);
  evaluator.set_normalisation(out.normalisation);
  evaluator.score(out.baseline);

  // The search loop.
  say("searching");
  const EvaluationSettings loop = loop_settings(config.optimizer);
  out.initial = evaluator.evaluate(space.scene(space.initial()), loop, out.loop_simulated);
  const long sims_before = pool.simulations();
  bool have_best = false;
  double best = 0.0;
  bool best_feasible = false;
  SearchProblem problem;
  problem.lower = space.lower();
  problem.upper = space.upper();
  problem.x0 = space.initial();
  problem.constraint_count = static_cast<int>(out.constraints.size());
  problem.evaluate = [&](const std::vector<double>& x, int start, PointKind kind) {
    DesignEvaluation e;
    try {
      e = evaluator.evaluate(space.scene(x), loop, out.loop_simulated);
    } catch (const InputError& err) {  // a spline the geometry code refuses
      e.valid = false;
      e.error = err.what();
      evaluator.score(e);
    }
    HistoryRecord h;
    h.evaluation = static_cast<long>(out.history.size()) + 1;
    h.start = start;
    h.kind = kind;
    h.valid = e.valid;
    h.error = e.error;
    h.objective = e.objective;
    h.constraints = e.constraints;
    h.feasible = e.feasible;
    if (e.valid &&
        (!have_best || (e.feasible && !best_feasible) || (e.feasible == best_feasible && e.objective < best))) {
      have_best = true;
      best = e.objective;
      best_feasible = e.feasible;
    }
    h.best_objective = have_best ? best : e.objective;
    h.best_feasible = best_feasible;
    out.history.push_back(std::move(h));
    PointValue v;
    v.objective = e.objective;
    v.valid = e.valid;
    v.feasible = e.feasible;
    for (const ConstraintValue& c : e.constraints) v.residuals.push_back(c.residual);
    return v;
  };
  const auto loop_t0 = Clock::now();
  double last_print = -1.0;
  auto progress = [&](const SearchProgress& p) {
    if (!options.progress) return;
    const double now = seconds_since(loop_t0);
    if (now - last_print < 0.2 && p.evaluations < config.optimizer.max_evaluations) return;
    last_print = now;
    std::fprintf(stderr, "\r  optimize: start %d/%d, evaluation %ld (%.1f/s), best objective %.6g (%s)    ",
                 p.start + 1, p.starts, p.evaluations, p.evaluations_per_second, p.best_objective,
                 p.best_feasible ? "feasible" : "infeasible");
    std::fflush(stderr);
  };
  out.search = run_search(problem, config.optimizer, progress);
  out.loop_time_s = seconds_since(loop_t0);
  out.loop_simulations = pool.simulations() - sims_before;
  if (options.progress) std::fprintf(stderr, "\n");
  if (out.search.candidates.empty())
    throw NumericalError("the optimiser found no valid design in " + std::to_string(out.search.evaluations) +
                         " evaluations (stop reason " + out.search.stop_reason + ")");

  // The best loop designs with the scene's settings: the first that holds
  // every constraint there wins (the loop settings are cheaper and can differ
  // near a constraint boundary); if none does, the best of the loop.
  say("re-evaluating the best designs with the scene's settings");
  const std::string name = baseline.name + "-optimized";
  bool chosen = false, have_fallback = false;
  DesignEvaluation fallback;
  SceneConfig fallback_scene;
  std::vector<double> fallback_x;
  // Designs infeasible in the loop are not worth a second look: only the best one is tried then.
  const std::size_t tries = std::max<std::size_t>(1, static_cast<std::size_t>(out.search.feasible_candidates));
  for (std::size_t k = 0; k < tries && k < out.search.candidates.size(); ++k) {
    const std::vector<double>& x = out.search.candidates[k];
    ++out.candidates_tried;
    const SceneConfig scene = simulate_scene(space.scene(x), top, name, file);
    DesignEvaluation e = evaluator.evaluate(scene, full, true);
    if (e.valid && e.feasible) {
      out.optimized = std::move(e);
      out.optimized_scene = scene;
      out.x_optimized = x;
      chosen = true;
      break;
    }
    if (e.valid && !have_fallback) {
      have_fallback = true;
      fallback = std::move(e);
      fallback_scene = scene;
      fallback_x = x;
    }
  }
  if (!chosen) {
    if (!have_fallback)
      throw NumericalError("none of the " + std::to_string(out.candidates_tried) +
                           " best designs of the search could be simulated with the scene's settings");
    out.optimized = std::move(fallback);
    out.optimized_scene = std::move(fallback_scene);
    out.x_optimized = std::move(fallback_x);
  }
  out.simulations = pool.simulations();
  out.run_time_s = seconds_since(t0);
  return out;
}

}  // namespace camdyn::optim
