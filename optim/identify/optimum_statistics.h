// The statistics of an identification at its optimum
// (optim/identify/identify.h), written into its result: the residuals and
// Jacobian there, the structural identifiability (rank of the Jacobian), the
// covariance from Ceres made a sandwich (optim/identify/identify_statistics.h),
// the estimates with their standard errors and correlations, and the
// practical identifiability (relative standard errors).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "optim/identify/ceres_stage.h"
#include "optim/identify/finite_differences.h"
#include "optim/identify/identify.h"
#include "optim/identify/identify_statistics.h"

namespace camdyn::optim {

/// The fit at the optimum: values, weighted residuals and their Jacobian in
/// the scaled parameters (without the loss).
struct Optimum {
  std::vector<double> values;  ///< [unit of each field]
  std::vector<double> r;
  Eigen::MatrixXd jacobian;  ///< n × p
  double dof = 0.0;          ///< n − p
};

/// The residuals and the central-difference Jacobian at z, the optimum
/// (simulated already: the run cache keeps them); fills result's residual
/// count, RMS residual and residual sigma. Throws NumericalError when a
/// simulation there fails.
Optimum evaluate_optimum(const IdentifyProblem& problem, FitEvaluator& cost, const std::vector<double>& z,
                         IdentifyResult& result);

/// Structural identifiability: a direction whose effect is below the
/// finite-difference noise (integration error / step) is one the data cannot
/// see at all. Fills the singular values and warnings; returns, per
/// parameter, whether it is not identifiable (its standard error undefined).
std::vector<bool> check_rank(const IdentifyProblem& problem, const Identifiability& id, double rank_tolerance,
                             IdentifyResult& result);

/// Covariance of the scaled parameters. The weights normalise units, not
/// noise, so each record's signal gets its own residual variance σ_g² (records
/// of different drops or sensors are not equally noisy): the sandwich of
/// sandwich_covariance() with A = (Σ ψ'(r) JᵀJ)⁻¹ from Ceres (pseudo-inverse
/// where rank-deficient; ψ = ρ'(r²) r is the influence of a residual under the
/// robust loss ρ, ψ' = 1 without one): with one record and no loss σ² (JᵀJ)⁻¹,
/// with a loss the M-estimator covariance (Huber 1981, ch. 7). Null (and a
/// warning) when it cannot be computed.
std::optional<Eigen::MatrixXd> covariance_at_optimum(const IdentifyProblem& problem, Stage& stage,
                                                     std::vector<double>& z, const Optimum& o, IdentifyResult& result);

/// Estimates, their standard errors (the delta method scales log-parameter
/// errors back: σ_p = p σ_ln p) and correlations; warns of estimates on a bound.
void record_estimates(const IdentifyProblem& problem, const std::vector<double>& z, const Optimum& o,
                      const std::optional<Eigen::MatrixXd>& cov_z, const std::vector<bool>& undetermined,
                      IdentifyResult& result);

/// Practical identifiability: a parameter known only to worse than
/// max_relative_std_error of its value is not determined by these data. The
/// weakest direction of the Jacobian says which parameters trade off with it.
void check_standard_errors(const IdentifyProblem& problem, const Identifiability& id, std::vector<bool>& unidentifiable,
                           IdentifyResult& result);

}  // namespace camdyn::optim
