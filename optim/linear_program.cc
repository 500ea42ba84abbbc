#include "optim/linear_program.h"

#include <ClpSimplex.hpp>
#include <CoinError.hpp>
#include <CoinPackedMatrix.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <tuple>

#include "common/errors.h"
#include "common/study_budget.h"

namespace camdyn::optim {

namespace {

/// Beyond this magnitude CLP reads a bound as infinite (1e30) and asserts
/// on it in places (1e100): a bound past it is made infinite, and a side
/// that then cannot hold (a lower bound of +1e29 or more) is refused.
constexpr double kClpLargest = 1e29;

/// CLP's infinity for a bound that is infinite here or beyond kClpLargest.
double clp_bound(double v) {
  if (v >= kClpLargest) return COIN_DBL_MAX;
  if (v <= -kClpLargest) return -COIN_DBL_MAX;
  return v;
}

std::vector<double> clp_bounds(const std::vector<double>& v) {
  std::vector<double> out(v.size());
  std::transform(v.begin(), v.end(), out.begin(), clp_bound);
  return out;
}

/// CLP's problem status in words.
std::string clp_status_text(const ClpSimplex& model) {
  switch (model.problemStatus()) {
    case 0:
      return "optimal";
    case 1:
      return "primal infeasible";
    case 2:
      return "dual infeasible (unbounded)";
    case 3:
      return "stopped on the iteration limit";
    case 4:
      return "stopped on numerical difficulties";
    default:
      return "status " + std::to_string(model.problemStatus());
  }
}

/// Largest violation of the rows and column bounds by x, relative to the
/// size of the bound (at least 1).
double worst_violation(const LinearProgram& lp, const std::vector<double>& x, const std::vector<double>& activity) {
  double worst = 0.0;
  auto check = [&worst](double v, double lo, double hi) {
    const double scale =
        std::max({1.0, std::isfinite(lo) ? std::abs(lo) : 0.0, std::isfinite(hi) ? std::abs(hi) : 0.0});
    if (v < lo) worst = std::max(worst, (lo - v) / scale);
    if (v > hi) worst = std::max(worst, (v - hi) / scale);
  };
  for (int j = 0; j < lp.columns(); ++j) check(x[j], lp.column_lower()[j], lp.column_upper()[j]);
  for (int r = 0; r < lp.rows(); ++r) check(activity[r], lp.row_lower()[r], lp.row_upper()[r]);
  return worst;
}

}  // namespace

int LinearProgram::add_column(double lower, double upper, double cost) {
  col_lower_.push_back(lower);
  col_upper_.push_back(upper);
  cost_.push_back(cost);
  return columns() - 1;
}

int LinearProgram::add_row(const std::vector<std::pair<int, double>>& terms, double lower, double upper) {
  const int row = rows();
  for (const auto& [column, value] : terms) {
    if (column < 0 || column >= columns()) throw std::out_of_range("LinearProgram::add_row: no such column");
    if (value == 0.0) continue;
    t_row_.push_back(row);
    t_col_.push_back(column);
    t_val_.push_back(value);
  }
  row_lower_.push_back(lower);
  row_upper_.push_back(upper);
  return row;
}

void LinearProgram::set_cost(int column, double cost) { cost_.at(static_cast<std::size_t>(column)) = cost; }

void LinearProgram::equilibrate_rows() {
  std::vector<double> largest(row_lower_.size(), 0.0);
  for (std::size_t k = 0; k < t_val_.size(); ++k)
    largest[static_cast<std::size_t>(t_row_[k])] =
        std::max(largest[static_cast<std::size_t>(t_row_[k])], std::abs(t_val_[k]));
  for (std::size_t k = 0; k < t_val_.size(); ++k) t_val_[k] /= largest[static_cast<std::size_t>(t_row_[k])];
  for (std::size_t r = 0; r < largest.size(); ++r) {
    if (largest[r] == 0.0) continue;
    row_lower_[r] /= largest[r];  // ±inf stays infinite
    row_upper_[r] /= largest[r];
  }
}

const char* to_string(LpStatus status) {
  switch (status) {
    case LpStatus::optimal:
      return "optimal";
    case LpStatus::infeasible:
      return "infeasible";
    case LpStatus::unbounded:
      return "unbounded";
    case LpStatus::failed:
      return "failed";
  }
  return "failed";
}

namespace {

/// CLP's answer to `lp` into `out` (what solve() returns; CLP may throw).
void solve_with_clp(const LinearProgram& lp, LpSolution& out) {
  const CoinPackedMatrix matrix(true, lp.triplet_rows().data(), lp.triplet_columns().data(), lp.triplet_values().data(),
                                static_cast<CoinBigIndex>(lp.triplet_values().size()));
  ClpSimplex model;
  model.setLogLevel(0);
  const std::vector<double> cl = clp_bounds(lp.column_lower()), cu = clp_bounds(lp.column_upper());
  const std::vector<double> rl = clp_bounds(lp.row_lower()), ru = clp_bounds(lp.row_upper());
  // The triplet constructor sizes the matrix by the largest index used; rows
  // or columns without a nonzero are added explicitly.
  CoinPackedMatrix full = matrix;
  full.setDimensions(lp.rows(), lp.columns());
  model.loadProblem(full, cl.data(), cu.data(), lp.costs().data(), rl.data(), ru.data());
  model.setMaximumIterations(200000);
  model.dual();
  if (model.problemStatus() == 3 || model.problemStatus() == 4) model.primal();  // a second opinion
  out.iterations = model.numberIterations();
  switch (model.problemStatus()) {
    case 0:
      out.status = LpStatus::optimal;
      break;
    case 1:
      out.status = LpStatus::infeasible;
      break;
    case 2:
      out.status = LpStatus::unbounded;
      break;
    default:
      out.status = LpStatus::failed;
      break;
  }
  if (out.status != LpStatus::optimal) {
    out.message = clp_status_text(model);
    return;
  }
  const double* x = model.primalColumnSolution();
  const double* activity = model.primalRowSolution();
  out.x.assign(x, x + lp.columns());
  out.row_activity.assign(activity, activity + lp.rows());
  out.objective = 0.0;
  for (int j = 0; j < lp.columns(); ++j) out.objective += lp.costs()[j] * out.x[j];
  const double violation = worst_violation(lp, out.x, out.row_activity);
  if (!(violation <= 1e-7)) {
    out.status = LpStatus::failed;
    out.message = "CLP reported optimal but the solution violates a row or bound by " + std::to_string(violation);
  }
}

std::string shortest(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

/// The first number CLP cannot take ("" when none): a coefficient or cost
/// that is not finite or at or beyond kClpLargest, a NaN bound, or a lower
/// bound at or above +kClpLargest (an upper one at or below −kClpLargest),
/// which CLP would read as infinite: a side that cannot hold.
std::string beyond_clp(const LinearProgram& lp) {
  auto find = [](const std::vector<double>& values, double sign, const char* what) -> std::string {
    for (const double v : values) {
      if (std::isnan(v)) return std::string("a ") + what + " is not a number";
      // sign 0: a coefficient or cost (finite, below kClpLargest); ±1: a lower
      // (+1) or upper (−1) bound, refused only on its impossible side.
      const bool bad = sign == 0.0 ? !(std::abs(v) < kClpLargest) : sign * v >= kClpLargest;
      if (bad) return std::string("a ") + what + " of " + shortest(v) + " is beyond what CLP solves (|x| < 1e29)";
    }
    return {};
  };
  for (const auto& [values, sign, what] :
       {std::tuple{&lp.triplet_values(), 0.0, "coefficient"}, std::tuple{&lp.costs(), 0.0, "cost"},
        std::tuple{&lp.column_lower(), 1.0, "column lower bound"},
        std::tuple{&lp.column_upper(), -1.0, "column upper bound"}, std::tuple{&lp.row_lower(), 1.0, "row lower bound"},
        std::tuple{&lp.row_upper(), -1.0, "row upper bound"}}) {
    std::string found = find(*values, sign, what);
    if (!found.empty()) return found;
  }
  return {};
}

}  // namespace

LpSolution solve(const LinearProgram& lp) {
  // The rigid stage's programmes are many: the study's wall time caps them (common/study_budget.h).
  if (study_budget_exhausted()) throw NumericalError(study_budget_text() + " in the rigid stage's linear programmes");
  LpSolution out;
  out.message = beyond_clp(lp);
  if (!out.message.empty()) return out;
  try {
    solve_with_clp(lp, out);
  } catch (const CoinError& e) {
    out = LpSolution{};
    out.message = "CLP threw: " + e.message();
  } catch (const std::bad_alloc&) {
    throw;  // the CLI's out-of-memory message
  } catch (const std::exception& e) {
    out = LpSolution{};
    out.message = std::string("CLP threw: ") + e.what();
  }
  return out;
}

}  // namespace camdyn::optim
