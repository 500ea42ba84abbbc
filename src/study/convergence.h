// The compute step of a convergence study: a reference run per scene variant,
// then every method × tracking mode × tolerance (rk4: × fixed step), each
// measured against its scene's reference.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "study/convergence_config.h"
#include "study/study.h"

namespace camdyn {

/// One run of the study and what it measured against its scene's reference.
struct ConvergenceRun {
  std::size_t scene = 0;  ///< index into the study's scenes
  IntegrationMethod method = IntegrationMethod::cvode_bdf;
  Tracking tracking = Tracking::differential;
  double rtol = 0.0;  ///< 0 for rk4
  double step = 0.0;  ///< rk4 fixed step [s]
  // results
  bool ok = false;
  std::string error;
  double error_position = 0.0;    ///< max |q − q_ref| over the evaluated time [m | rad] (coordinate_units.h)
  double error_peak_force = 0.0;  ///< |F_peak / F_peak,ref − 1| [-]
  double energy_residual = 0.0, run_time_s = 0.0;
  long steps = 0, rhs_evaluations = 0;
};

/// The runs of a study, in plan order, and when the study started computing.
struct ConvergenceResult {
  std::vector<ConvergenceRun> runs;
  std::chrono::steady_clock::time_point started;
  /// Per scene variant: why its reference is missing (empty: it ran). Its
  /// runs then ran but measured no error (ok false, their counters kept).
  std::vector<std::string> reference_missing;
  /// Per scene variant: how its reference ran ("rtol 1e-10", with the retries that made it run).
  std::vector<std::string> reference_note;

  /// How many runs failed.
  long failed() const {
    return std::count_if(runs.begin(), runs.end(), [](const ConvergenceRun& r) { return !r.ok; });
  }
};

/// Runs the study on ctx.threads() threads (progress on stderr with
/// ctx.progress). A failed run is recorded in its ConvergenceRun. A reference
/// run that fails is retried (a step budget four times larger, twice; then a
/// tolerance ten times tighter); one that still fails is recorded in
/// reference_missing and its scene's runs measure no error.
ConvergenceResult run_convergence(const ConvergenceStudy& study, const StudyContext& ctx);

}  // namespace camdyn
