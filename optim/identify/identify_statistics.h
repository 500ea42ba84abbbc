// The statistics of an identification at its optimum, as pure functions of
// the Jacobian and the residuals: identifiability (singular values of the
// column-equilibrated Jacobian, parameters without effect) and the sandwich
// covariance of the estimates. Tested on hand-computed small problems in
// tests/optim/identify_statistics_test.cc.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace camdyn::optim {

struct Identifiability {
  /// Per parameter: its effect on the residuals is below the rank tolerance
  /// (its column is left out of the decomposition).
  std::vector<bool> no_effect;
  Eigen::VectorXd singular_values;  ///< of the equilibrated Jacobian, largest first
  Eigen::MatrixXd directions;       ///< its right singular vectors V (column k belongs to singular value k)
  double condition_number = 0.0;    ///< largest / smallest singular value (+inf when the smallest is 0)
};

/// Identifiability of a least-squares fit from its n × p Jacobian in the
/// scaled parameters. The columns are scaled to unit norm, so that the
/// parameters' units do not matter; a parameter whose RMS effect per relative
/// change, |J_i| · magnitudes[i] / √n, is not above `rank_tolerance` is one
/// the data cannot see (no_effect; its column is zeroed).
/// `magnitudes[i]`: the parameter's size per unit of its scaled coordinate
/// (1 for a log-scale parameter, max(|p|, scale) for a linear one).
Identifiability identifiability(const Eigen::MatrixXd& jacobian, const std::vector<double>& magnitudes,
                                double rank_tolerance);

/// The sandwich covariance A (Σ_g σ_g² J_gᵀ J_g) A of the scaled parameters
/// (Huber 1981, ch. 7): A the (pseudo-)inverse of the loss-weighted normal
/// matrix, the residuals split into consecutive groups of `group_rows` rows
/// (one per record signal) and σ_g² = Σ_{i∈g} ψ_i² / (n_g · dof / n) with
/// ψ_i = weight_i · r_i, weight_i = ρ'(r_i²) of the robust loss (1 without
/// one). With one group and no loss this is σ² (JᵀJ)⁻¹, σ² = Σ r² / dof.
Eigen::MatrixXd sandwich_covariance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& jacobian,
                                    const std::vector<double>& residuals, const std::vector<double>& loss_weights,
                                    const std::vector<std::size_t>& group_rows, double dof);

}  // namespace camdyn::optim
