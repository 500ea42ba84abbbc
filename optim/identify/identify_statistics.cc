#include "optim/identify/identify_statistics.h"

#include <Eigen/SVD>
#include <cmath>
#include <limits>

namespace camdyn::optim {

Identifiability identifiability(const Eigen::MatrixXd& jacobian, const std::vector<double>& magnitudes,
                                double rank_tolerance) {
  const auto p = static_cast<std::size_t>(jacobian.cols());
  const Eigen::Index n = jacobian.rows();
  Identifiability result;
  result.no_effect.assign(p, false);
  const Eigen::VectorXd norms = jacobian.colwise().norm().transpose();
  Eigen::MatrixXd equilibrated = jacobian;
  for (std::size_t i = 0; i < p; ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    // RMS change of the weighted signals (each of RMS 1) per relative change
    // of the parameter: below the integration noise over the step, the
    // parameter has no effect the simulation can resolve.
    const double sensitivity = norms(c) * magnitudes[i] / std::sqrt(static_cast<double>(n));
    if (!(sensitivity > rank_tolerance)) {
      result.no_effect[i] = true;
      equilibrated.col(c).setZero();
    } else {
      equilibrated.col(c) /= norms(c);
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(equilibrated, Eigen::ComputeThinV);
  result.singular_values = svd.singularValues();
  result.directions = svd.matrixV();
  const Eigen::VectorXd& sv = result.singular_values;
  const double sv_max = sv.size() > 0 ? sv(0) : 0.0;
  const double sv_min = sv.size() > 0 ? sv(sv.size() - 1) : 0.0;
  result.condition_number = sv_min > 0.0 ? sv_max / sv_min : std::numeric_limits<double>::infinity();
  return result;
}

Eigen::MatrixXd sandwich_covariance(const Eigen::MatrixXd& a, const Eigen::MatrixXd& jacobian,
                                    const std::vector<double>& residuals, const std::vector<double>& loss_weights,
                                    const std::vector<std::size_t>& group_rows, double dof) {
  const Eigen::Index p = jacobian.cols();
  const auto n = static_cast<double>(jacobian.rows());
  Eigen::MatrixXd b = Eigen::MatrixXd::Zero(p, p);
  Eigen::Index row = 0;
  for (const std::size_t group : group_rows) {
    const auto rows = static_cast<Eigen::Index>(group);
    double group2 = 0.0;
    for (Eigen::Index i = row; i < row + rows; ++i) {
      const double ri = residuals[static_cast<std::size_t>(i)];
      const double w = loss_weights[static_cast<std::size_t>(i)];
      group2 += w * w * ri * ri;  // ψ²
    }
    const double group_dof = static_cast<double>(rows) * dof / n;
    const auto j_g = jacobian.middleRows(row, rows);
    b.noalias() += (group2 / group_dof) * (j_g.transpose() * j_g);
    row += rows;
  }
  return a * b * a;
}

}  // namespace camdyn::optim
