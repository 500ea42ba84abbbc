#include "optim/identify/optimum_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>

#include "common/errors.h"
#include "io/json_archive.h"

namespace camdyn::optim {

namespace {

std::string percent(double x) {
  std::ostringstream s;
  s.precision(3);
  s << 100.0 * x << " %";
  return s.str();
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return out;
}

std::vector<std::string> names_of(const IdentifyProblem& problem, const std::vector<std::size_t>& indices) {
  std::vector<std::string> names;
  for (std::size_t i : indices) names.push_back(problem.parameters[i].name);
  return names;
}

}  // namespace

Optimum evaluate_optimum(const IdentifyProblem& problem, FitEvaluator& cost, const std::vector<double>& z,
                         IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const std::size_t n = problem.residual_count();
  if (!cost.evaluate(z.data(), true, true))
    throw NumericalError("identification: the Jacobian at the optimum could not be evaluated: " + cost.last_failure());
  Optimum o;
  o.r = cost.residuals();
  o.jacobian.resize(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(p));
  for (std::size_t row = 0; row < n; ++row)
    for (std::size_t i = 0; i < p; ++i)
      o.jacobian(static_cast<Eigen::Index>(row), static_cast<Eigen::Index>(i)) = cost.jacobian()[row * p + i];
  double sum2 = 0.0;
  for (double x : o.r) sum2 += x * x;
  result.residuals = n;
  result.rms_residual = std::sqrt(sum2 / static_cast<double>(n));
  o.dof = static_cast<double>(n) - static_cast<double>(p);
  result.residual_sigma = std::sqrt(2.0 * result.final_cost / o.dof);
  o.values.resize(p);
  for (std::size_t i = 0; i < p; ++i) o.values[i] = to_value(problem.parameters[i], z[i]);
  return o;
}

std::vector<bool> check_rank(const IdentifyProblem& problem, const Identifiability& id, double rank_tolerance,
                             IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const Eigen::VectorXd& sv = id.singular_values;
  for (Eigen::Index i = 0; i < sv.size(); ++i) result.singular_values.push_back(sv(i));
  result.condition_number = id.condition_number;
  const double sv_max = sv.size() > 0 ? sv(0) : 0.0;
  std::vector<bool> unidentifiable(p, false);
  for (std::size_t i = 0; i < p; ++i) {
    if (!id.no_effect[i]) continue;
    unidentifiable[i] = true;
    result.warnings.push_back(
        "not identifiable: " + problem.parameters[i].name +
        " has no effect on the fitted signals (a change of it changes them by less than the integration error)");
  }
  for (Eigen::Index k = 0; k < sv.size(); ++k) {
    if (sv(k) >= rank_tolerance * sv_max) continue;
    const Eigen::VectorXd v = id.directions.col(k);
    std::vector<std::size_t> involved;
    for (std::size_t i = 0; i < p; ++i)
      if (!id.no_effect[i] && std::abs(v(static_cast<Eigen::Index>(i))) >= 0.1) involved.push_back(i);
    if (involved.empty()) continue;
    std::ostringstream dir;
    dir.precision(3);
    for (std::size_t j = 0; j < involved.size(); ++j) {
      const FitParameter& par = problem.parameters[involved[j]];
      const double c = v(static_cast<Eigen::Index>(involved[j]));
      dir << (j == 0 ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + ")) << std::abs(c) << " "
          << (par.log_scale ? "ln " : "") << par.name;
    }
    for (std::size_t i : involved) unidentifiable[i] = true;
    std::ostringstream msg;
    msg.precision(3);
    msg << "not identifiable: the data cannot separate " << join_names(names_of(problem, involved))
        << " (rank-deficient Jacobian, singular value ratio " << sv(k) / sv_max << " below the finite-difference noise "
        << rank_tolerance << "); changing them along (" << dir.str()
        << ") [unit-normalised] leaves the fit unchanged. Fix one of them or add data that separates them.";
    result.warnings.push_back(msg.str());
  }
  return unidentifiable;
}

std::optional<Eigen::MatrixXd> covariance_at_optimum(const IdentifyProblem& problem, Stage& stage,
                                                     std::vector<double>& z, const Optimum& o, IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  if (o.dof <= 0.0) {
    result.warnings.push_back("no standard errors: as many parameters as measured values");
    return std::nullopt;
  }
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.null_space_rank = -1;
  cov_options.min_reciprocal_condition_number = 1e-14;
  cov_options.apply_loss_function = true;
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> blocks = {{z.data(), z.data()}};
  if (!covariance.Compute(blocks, stage.problem.get())) {
    result.warnings.push_back("no standard errors: Ceres could not compute the covariance at the optimum");
    return std::nullopt;
  }
  std::vector<double> c(p * p);
  if (!covariance.GetCovarianceBlock(z.data(), z.data(), c.data())) {
    result.warnings.push_back("no standard errors: Ceres could not return the covariance block");
    return std::nullopt;
  }
  const auto pp = static_cast<Eigen::Index>(p);
  const Eigen::MatrixXd a =
      Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(c.data(), pp, pp);
  std::vector<double> loss_weights(o.r.size());
  for (std::size_t i = 0; i < o.r.size(); ++i) {
    const double ri = o.r[i];
    double rho[3] = {ri * ri, 1.0, 0.0};
    if (stage.loss != nullptr) stage.loss->Evaluate(ri * ri, rho);
    loss_weights[i] = rho[1];
  }
  std::vector<std::size_t> group_rows;
  for (const FitExperiment& e : problem.experiments)
    for (std::size_t s = 0; s < e.record.signals.size(); ++s) group_rows.push_back(e.record.time.size());
  return sandwich_covariance(a, o.jacobian, o.r, loss_weights, group_rows, o.dof);
}

void record_estimates(const IdentifyProblem& problem, const std::vector<double>& z, const Optimum& o,
                      const std::optional<Eigen::MatrixXd>& cov_z, const std::vector<bool>& undetermined,
                      IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  std::vector<double> std_z(p, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < p; ++i) {
    const FitParameter& par = problem.parameters[i];
    ParameterEstimate est;
    est.name = par.name;
    est.path = par.path;
    est.value = o.values[i];
    est.initial = par.initial;
    est.log_scale = par.log_scale;
    if (std::isfinite(par.lower)) est.lower = par.lower;
    if (std::isfinite(par.upper)) est.upper = par.upper;
    const double lo = scaled_lower(par), hi = scaled_upper(par);
    const double tol = 1e-9 * std::max(1.0, std::abs(z[i]));
    est.at_bound = (std::isfinite(lo) && z[i] - lo <= tol) || (std::isfinite(hi) && hi - z[i] <= tol);
    const double var = cov_z ? (*cov_z)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i))
                             : std::numeric_limits<double>::quiet_NaN();
    if (cov_z && !undetermined[i] && std::isfinite(var) && var >= 0.0) {
      std_z[i] = std::sqrt(var);
      est.std_error = par.log_scale ? o.values[i] * std_z[i] : std_z[i];
    }
    if (est.at_bound)
      result.warnings.push_back(par.name + " ended on its " +
                                (std::isfinite(lo) && z[i] - lo <= tol ? std::string("lower") : std::string("upper")) +
                                " bound (" + format_shortest(o.values[i]) +
                                "): the optimum may lie beyond it and its standard error is not meaningful");
    result.parameters.push_back(est);
  }
  result.correlation.assign(p, std::vector<std::optional<double>>(p));
  for (std::size_t i = 0; i < p; ++i) {
    for (std::size_t j = 0; j < p; ++j) {
      if (!(std_z[i] > 0.0) || !(std_z[j] > 0.0)) continue;
      const double rho = (*cov_z)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) / (std_z[i] * std_z[j]);
      if (std::isfinite(rho)) result.correlation[i][j] = i == j ? 1.0 : std::clamp(rho, -1.0, 1.0);
    }
  }
}

void check_standard_errors(const IdentifyProblem& problem, const Identifiability& id, std::vector<bool>& unidentifiable,
                           IdentifyResult& result) {
  const std::size_t p = problem.parameters.size();
  const SolverSpec& spec = problem.solver;
  std::vector<std::size_t> weak;
  for (std::size_t i = 0; i < p; ++i) {
    const ParameterEstimate& est = result.parameters[i];
    if (unidentifiable[i] || !est.std_error) continue;
    const double rel = *est.std_error / (est.value != 0.0 ? std::abs(est.value) : problem.parameters[i].scale);
    if (rel > spec.max_relative_std_error) weak.push_back(i);
  }
  if (weak.empty()) return;
  std::vector<std::size_t> involved = weak;
  const Eigen::VectorXd v = id.directions.col(id.directions.cols() - 1);
  bool weak_in_direction = false;
  for (std::size_t i : weak) weak_in_direction = weak_in_direction || std::abs(v(static_cast<Eigen::Index>(i))) >= 0.2;
  if (weak_in_direction) {
    for (std::size_t i = 0; i < p; ++i)
      if (std::abs(v(static_cast<Eigen::Index>(i))) >= 0.2 &&
          std::find(involved.begin(), involved.end(), i) == involved.end())
        involved.push_back(i);
    std::sort(involved.begin(), involved.end());
  }
  std::ostringstream msg;
  msg.precision(3);
  msg << "not identifiable: the data do not determine " << join_names(names_of(problem, involved))
      << " (relative standard error";
  for (std::size_t j = 0; j < involved.size(); ++j) {
    const ParameterEstimate& est = result.parameters[involved[j]];
    msg << (j == 0 ? " " : ", ")
        << (est.std_error ? percent(*est.std_error / std::max(std::abs(est.value), 1e-300)) : std::string("undefined"));
  }
  msg << "; limit solver.max_relative_std_error = " << percent(spec.max_relative_std_error) << ")";
  if (involved.size() == 2 && result.correlation[involved[0]][involved[1]])
    msg << ", correlation " << *result.correlation[involved[0]][involved[1]];
  if (involved.size() > 1)
    msg << ": they trade off against each other. Fix one of them or add data that separates them"
           " (other drop heights, other speeds).";
  else
    msg << ": the signals hardly depend on it. Fix it or add data that excites it.";
  result.warnings.push_back(msg.str());
  for (std::size_t i : involved) unidentifiable[i] = true;
}

}  // namespace camdyn::optim
