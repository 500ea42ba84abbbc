#include "study/convergence.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "dynamics/simulation.h"
#include "study/progress.h"

namespace camdyn {

namespace {

/// The scene with the run's integrator settings and tracking mode.
SceneConfig configure(SceneConfig scene, IntegrationMethod method, Tracking tracking, double rtol, double atol_factor,
                      double step) {
  // The scene's integrator.order is its own method's: another method runs at its default order.
  if (method != scene.integrator.method) scene.integrator.order.reset();
  scene.integrator.method = method;
  scene.mechanism.contact.tracking = tracking;
  if (method == IntegrationMethod::rk4) {
    scene.integrator.step = step;
  } else {
    scene.integrator.rtol = rtol;
    scene.integrator.atol = rtol * atol_factor;
  }
  return scene;
}

/// Largest follower-position difference [m] over the reference's evaluated time.
double max_position_error(const SimulationResult& run, const SimulationResult& reference) {
  double worst = 0.0;
  const size_t n = std::min(run.series.time.size(), reference.series.time.size());
  for (size_t i = 0; i < n; ++i) {
    if (reference.series.time[i] < reference.evaluated_from) continue;
    worst = std::max(worst, std::abs(run.series.follower_position[i] - reference.series.follower_position[i]));
  }
  return worst;
}

ConvergenceRun make_run(size_t scene, IntegrationMethod method, Tracking tracking, double rtol, double step) {
  ConvergenceRun r;
  r.scene = scene;
  r.method = method;
  r.tracking = tracking;
  r.rtol = rtol;
  r.step = step;
  return r;
}

/// The reference run of scene `s`: as configured; after a step budget
/// exhausted, again with four times the budget (twice at most); after any
/// other failure, once with a tolerance ten times tighter. nullopt with the
/// last failure in `missing`; how it ran in `note`.
std::optional<SimulationResult> reference_run(SceneConfig s, const std::string& file, std::string& missing,
                                              std::string& note) {
  int budget_retries = 0;
  bool tightened = false;
  for (;;) {
    SimulationResult r;
    try {
      r = simulate_scene(s, file);
    } catch (const NumericalError& e) {
      r.solver.termination = Termination::integrator_failure;
      r.solver.message = e.what();
    }
    char how[128];
    std::snprintf(how, sizeof how, "rtol %.3g, max_steps %ld", s.integrator.rtol, s.integrator.max_steps);
    note = how;
    if (r.solver.converged()) return r;
    missing = r.solver.message;
    if (r.solver.termination == Termination::step_budget && budget_retries < 2) {
      ++budget_retries;
      s.integrator.max_steps *= 4;
    } else if (r.solver.termination != Termination::wall_time_budget && !tightened) {
      tightened = true;
      s.integrator.rtol /= 10.0;
      s.integrator.atol /= 10.0;
    } else {
      return std::nullopt;
    }
  }
}

/// A run's expected cost for the progress line's estimate [units]: an
/// adaptive run of relative tolerance `rtol` takes steps ∝ rtol^(−1/5) (an
/// order-5 method), one unit at 1e-3; a fixed-step run (rtol 0) one unit.
double expected_work(double rtol) { return rtol > 0.0 ? std::max(1.0, std::pow(1e-3 / rtol, 0.2)) : 1.0; }

/// The reference tolerance of scene k.
double reference_rtol(const ConvergenceConfig& config, size_t k) {
  return config.scenes[k].reference_rtol.value_or(config.reference.rtol);
}

/// The reference run of each scene variant, in parallel.
std::vector<std::optional<SimulationResult>> reference_runs(const ConvergenceStudy& study, const StudyContext& ctx,
                                                            int threads, ConvergenceResult& out,
                                                            ProgressMeter& progress) {
  const ConvergenceConfig& config = study.config;
  std::vector<std::optional<SimulationResult>> references(study.scenes.size());
  out.reference_missing.assign(study.scenes.size(), "");
  out.reference_note.assign(study.scenes.size(), "");
  parallel_for(study.scenes.size(), threads, [&](size_t k) {
    const SceneConfig s = configure(study.scenes[k], config.reference.method, config.tracking.front(),
                                    reference_rtol(config, k), config.atol_factor, 0.0);
    std::string missing;
    references[k] = reference_run(s, ctx.config_file, missing, out.reference_note[k]);
    if (!references[k]) out.reference_missing[k] = missing;
    progress.finished(!references[k], 0.0, expected_work(reference_rtol(config, k)));
  });
  return references;
}

/// Every run of the study, not yet run: per scene, method and tracking mode,
/// each tolerance (rk4: each fixed step, given in cam degrees, as seconds).
std::vector<ConvergenceRun> plan_runs(const ConvergenceStudy& study) {
  const ConvergenceConfig& config = study.config;
  std::vector<ConvergenceRun> runs;
  for (size_t k = 0; k < study.scenes.size(); ++k) {
    const double omega = study.scenes[k].mechanism.cam.rpm * 2 * std::numbers::pi / 60;
    for (const IntegrationMethod method : config.methods)
      for (const Tracking tracking : config.tracking) {
        if (method == IntegrationMethod::rk4) {
          for (double deg : config.scenes[k].rk4_steps_deg.value_or(config.rk4_steps_deg)) {
            runs.push_back(
                make_run(k, method, tracking, 0.0, omega > 0 ? deg * std::numbers::pi / 180 / omega : deg * 1e-6));
          }
        } else {
          for (double tol : config.scenes[k].tolerances.value_or(config.tolerances))
            runs.push_back(make_run(k, method, tracking, tol, 0.0));
        }
      }
  }
  return runs;
}

/// Runs r and measures it against its scene's reference; a failure is kept in r.
void measure_run(const ConvergenceStudy& study, const std::vector<std::optional<SimulationResult>>& references,
                 const std::string& config_file, ConvergenceRun& r) {
  if (study_budget_exhausted()) {  // not started: the study's wall time is used up
    r.error = study_budget_text() + " before this run";
    return;
  }
  const SceneConfig s =
      configure(study.scenes[r.scene], r.method, r.tracking, r.rtol, study.config.atol_factor, r.step);
  try {
    const SimulationResult result = simulate_scene(s, config_file);
    throw_if_failed(result);
    r.energy_residual = result.metrics.energy_residual;
    r.run_time_s = result.solver.run_time_s;
    r.steps = result.solver.counters.steps;
    r.rhs_evaluations = result.solver.counters.rhs_evaluations;
    if (!references[r.scene]) {
      r.error = "no reference to measure against (its run failed)";
      return;
    }
    const SimulationResult& ref = *references[r.scene];
    r.error_position = max_position_error(result, ref);
    r.error_peak_force = std::abs(result.metrics.peak_contact_force / ref.metrics.peak_contact_force - 1.0);
    r.ok = std::isfinite(r.error_position) && std::isfinite(r.error_peak_force);
    if (!r.ok) r.error = "non-finite error";
  } catch (const std::exception& e) {
    r.error = e.what();
  }
}

}  // namespace

ConvergenceResult run_convergence(const ConvergenceStudy& study, const StudyContext& ctx) {
  ConvergenceResult out;
  out.started = std::chrono::steady_clock::now();
  const int threads = ctx.threads();
  out.runs = plan_runs(study);
  std::vector<ConvergenceRun>& runs = out.runs;
  // One line for the reference runs and the runs measured against them.
  double work = 0.0;
  for (size_t k = 0; k < study.scenes.size(); ++k) work += expected_work(reference_rtol(study.config, k));
  for (const ConvergenceRun& r : runs) work += expected_work(r.rtol);
  ProgressMeter progress("convergence", study.scenes.size() + runs.size(), 0, 0, static_cast<size_t>(threads),
                         ctx.progress, work);
  const std::vector<std::optional<SimulationResult>> references = reference_runs(study, ctx, threads, out, progress);
  parallel_for(runs.size(), threads, [&](size_t i) {
    measure_run(study, references, ctx.config_file, runs[i]);
    progress.finished(!runs[i].ok, 0.0, expected_work(runs[i].rtol));
  });
  return out;
}

}  // namespace camdyn
