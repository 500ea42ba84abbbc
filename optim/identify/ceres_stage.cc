#include "optim/identify/ceres_stage.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <stdexcept>
#include <string>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/json_archive.h"
#include "optim/identify/identify_journal.h"

namespace camdyn::optim {

namespace {

/// Relative cost and step tolerance of the smoothed continuation stages.
constexpr double kStageTolerance = 1e-4;

/// One measured sample as a Ceres residual block, so that a robust loss acts
/// on each sample (Ceres applies it to the squared norm of a whole block).
/// All blocks share the evaluator, which simulates once per point.
class SampleCost final : public ceres::CostFunction {
 public:
  SampleCost(FitEvaluator& evaluator, std::size_t row, int parameters) : evaluator_(evaluator), row_(row) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->push_back(parameters);
  }

  bool Evaluate(double const* const* parameters, double* r, double** jacobians) const override {
    const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    if (!evaluator_.evaluate(parameters[0], jacobian)) return false;
    r[0] = evaluator_.residuals()[row_];
    if (jacobian) {
      const auto p = static_cast<std::size_t>(parameter_block_sizes()[0]);
      const double* row = evaluator_.jacobian().data() + row_ * p;
      std::copy(row, row + p, jacobians[0]);
    }
    return true;
  }

 private:
  FitEvaluator& evaluator_;
  std::size_t row_;
};

/// After each solver iteration: the progress callback, and the accepted
/// iterates into the journal (Ceres has written them into z by then:
/// update_state_every_iteration).
class IterationCallback final : public ceres::IterationCallback {
 public:
  IterationCallback(const IdentifyProblem& problem, const IdentifyOptions& options, std::size_t stage, double smoothing,
                    const std::vector<double>& z, IdentifyProgress where)
      : problem_(problem), options_(options), stage_(stage), smoothing_(smoothing), z_(z), where_(where) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (study_budget_exhausted()) return ceres::SOLVER_ABORT;  // solve_stage says why
    if (options_.progress) {
      where_.iteration = summary.iteration;
      where_.cost = summary.cost;
      options_.progress(where_);
    }
    if (options_.journal != nullptr && summary.step_is_successful) {
      std::vector<double> values(z_.size());
      for (std::size_t i = 0; i < z_.size(); ++i) values[i] = to_value(problem_.parameters[i], z_[i]);
      options_.journal->add_iterate(stage_, smoothing_, summary.iteration, summary.cost, values);
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const IdentifyProblem& problem_;
  const IdentifyOptions& options_;
  std::size_t stage_;
  double smoothing_;
  const std::vector<double>& z_;
  IdentifyProgress where_;
};

ceres::LossFunction* make_loss(const std::string& loss, double scale) {
  if (loss == "huber") return new ceres::HuberLoss(scale);
  if (loss == "cauchy") return new ceres::CauchyLoss(scale);
  if (loss == "soft_l1") return new ceres::SoftLOneLoss(scale);
  return nullptr;  // "none": plain least squares
}

}  // namespace

std::unique_ptr<Stage> solve_stage(const IdentifyProblem& problem, FitSimulator& simulator, const SolverSpec& spec,
                                   std::size_t stage_index, double smoothing, double loss_scale,
                                   const IdentifyOptions& options, const IdentifyProgress& where,
                                   std::vector<double>& z) {
  auto stage = std::make_unique<Stage>();
  stage->evaluator = std::make_unique<FitEvaluator>(problem, simulator, smoothing);
  // One loss object for all blocks; the problem must then not delete it per block.
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  stage->loss.reset(make_loss(spec.loss, loss_scale));
  stage->problem = std::make_unique<ceres::Problem>(problem_options);
  const int p = static_cast<int>(problem.parameters.size());
  for (std::size_t row = 0; row < problem.residual_count(); ++row)
    stage->problem->AddResidualBlock(new SampleCost(*stage->evaluator, row, p), stage->loss.get(), z.data());
  for (std::size_t i = 0; i < problem.parameters.size(); ++i) {
    const double lo = scaled_lower(problem.parameters[i]), hi = scaled_upper(problem.parameters[i]);
    if (std::isfinite(lo)) stage->problem->SetParameterLowerBound(z.data(), static_cast<int>(i), lo);
    if (std::isfinite(hi)) stage->problem->SetParameterUpperBound(z.data(), static_cast<int>(i), hi);
  }

  ceres::Solver::Options solver_options;
  solver_options.minimizer_type = ceres::TRUST_REGION;
  solver_options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = spec.max_iterations;
  solver_options.initial_trust_region_radius = spec.initial_trust_region_radius;
  // A smoothed stage only has to bring the next one into its basin.
  solver_options.function_tolerance =
      smoothing > 0.0 ? std::max(spec.function_tolerance, kStageTolerance) : spec.function_tolerance;
  solver_options.gradient_tolerance = spec.gradient_tolerance;
  solver_options.parameter_tolerance =
      smoothing > 0.0 ? std::max(spec.parameter_tolerance, kStageTolerance) : spec.parameter_tolerance;
  // With bounds, Ceres runs a projected Armijo line search on each step; its
  // cubic interpolation wants the gradient at every trial, which here is a
  // whole finite-difference Jacobian. Bisection needs only the cost.
  solver_options.line_search_interpolation_type = ceres::BISECTION;
  solver_options.num_threads = 1;  // one residual block; the simulations run in parallel inside it
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  IterationCallback callback(problem, options, stage_index, smoothing, z, where);
  solver_options.callbacks.push_back(&callback);
  solver_options.update_state_every_iteration = true;  // z is the accepted iterate in the callback
  std::string options_error;
  // identify_config.cc holds every option to Ceres' ranges; one that still
  // fails is a bad option of the config (exit 2), not a bug.
  if (!solver_options.IsValid(&options_error))
    throw InputError(problem.config_file, "solver", "Ceres refuses the options: " + options_error);

  ceres::Solve(solver_options, stage->problem.get(), &stage->summary);
  const FitEvaluator& cost = *stage->evaluator;
  if (cost.input_error()) std::rethrow_exception(cost.input_error());
  if (study_budget_exhausted())
    throw NumericalError(study_budget_text() + " in continuation stage " + std::to_string(stage_index + 1) +
                         (options.journal == nullptr
                              ? std::string()
                              : "; the simulations so far are kept in " + options.journal->path().string() + ": " +
                                    study_rerun_advice()));
  if (!stage->summary.IsSolutionUsable()) {
    std::string why = stage->summary.message;
    if (!cost.last_failure().empty()) why += "; last failed simulation: " + cost.last_failure();
    if (cost.exception() && cost.last_failure().empty()) {
      try {
        std::rethrow_exception(cost.exception());
      } catch (const std::exception& e) {
        why += std::string("; ") + e.what();
      }
    }
    throw NumericalError(
        "identification failed (" + std::string(ceres::TerminationTypeToString(stage->summary.termination_type)) +
        (smoothing > 0.0 ? ", stage smoothed over " + format_shortest(smoothing) + " s" : std::string()) + "): " + why);
  }
  return stage;
}

}  // namespace camdyn::optim
