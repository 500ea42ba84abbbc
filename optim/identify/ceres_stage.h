// The Ceres glue of an identification (optim/identify/identify.h): one
// continuation stage solved as a bounded least-squares problem, each measured
// sample a residual block over one finite-difference evaluator
// (optim/identify/finite_differences.h), the robust loss, and the accepted
// iterates handed to the progress line and the journal.
#pragma once

#include <ceres/ceres.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "optim/identify/finite_differences.h"
#include "optim/identify/fit_simulator.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {

/// One least-squares solve (a continuation stage): the problem stays alive for the covariance.
struct Stage {
  std::unique_ptr<FitEvaluator> evaluator;
  std::unique_ptr<ceres::LossFunction> loss;
  std::unique_ptr<ceres::Problem> problem;
  ceres::Solver::Summary summary;
};

/// Solves one stage from z (the scaled parameters, updated to the stage's
/// solution) with the signals smoothed over `smoothing` [s] (0: raw). Throws
/// InputError when a parameter value makes an invalid scene and
/// NumericalError when the study budget runs out or the solver finds no
/// usable solution.
std::unique_ptr<Stage> solve_stage(const IdentifyProblem& problem, FitSimulator& simulator, const SolverSpec& spec,
                                   std::size_t stage_index, double smoothing, double loss_scale,
                                   const IdentifyOptions& options, const IdentifyProgress& where,
                                   std::vector<double>& z);

}  // namespace camdyn::optim
