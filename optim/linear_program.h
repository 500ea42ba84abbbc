// A linear programme and its solution with COIN-OR CLP (Debian
// coinor-libclp-dev): minimise cᵀx subject to row bounds l_r ≤ A x ≤ u_r and
// column bounds l_c ≤ x ≤ u_c. The rigid-model stage of an optimize study
// (optim/optimize/rigid_design.h) and its jump-speed certificate (optim/optimize/jump_bound.h)
// build their programmes with this and never see CLP.
//
// CLP is chosen because it is a mature, exact (simplex) LP solver packaged by
// Debian, small, and good at the dense-ish, few-hundred-row programmes these
// stages solve many times during a bisection; an interior-point or a
// general NLP solver would give a less exact vertex and no infeasibility proof.
#pragma once

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace camdyn::optim {

inline constexpr double kLpInfinity = std::numeric_limits<double>::infinity();

/// The programme: columns (variables) and rows (linear constraints), built
/// one at a time. Infinite bounds mean "no bound".
class LinearProgram {
 public:
  /// Adds a variable with bounds [lower, upper] and objective coefficient
  /// `cost`; returns its index.
  int add_column(double lower, double upper, double cost = 0.0);

  /// Adds the row lower ≤ Σ coefficient · x[index] ≤ upper; returns its index.
  /// Zero coefficients are dropped; an index repeated adds up.
  int add_row(const std::vector<std::pair<int, double>>& terms, double lower, double upper);

  /// Changes the objective coefficient of column `column`.
  void set_cost(int column, double cost);

  /// Divides every row (coefficients and bounds) by its largest |coefficient|,
  /// so rows whose coefficients span many decades (finite differences of
  /// third order, m ω² s'') are checked against the same relative tolerance.
  /// The feasible set and the optimum are unchanged; row activities are then
  /// of the scaled rows.
  void equilibrate_rows();

  int columns() const { return static_cast<int>(col_lower_.size()); }
  int rows() const { return static_cast<int>(row_lower_.size()); }

  const std::vector<double>& column_lower() const { return col_lower_; }
  const std::vector<double>& column_upper() const { return col_upper_; }
  const std::vector<double>& costs() const { return cost_; }
  const std::vector<double>& row_lower() const { return row_lower_; }
  const std::vector<double>& row_upper() const { return row_upper_; }
  /// Nonzeros as (row, column, value) triplets.
  const std::vector<int>& triplet_rows() const { return t_row_; }
  const std::vector<int>& triplet_columns() const { return t_col_; }
  const std::vector<double>& triplet_values() const { return t_val_; }

 private:
  std::vector<double> col_lower_, col_upper_, cost_;
  std::vector<double> row_lower_, row_upper_;
  std::vector<int> t_row_, t_col_;
  std::vector<double> t_val_;
};

enum class LpStatus {
  optimal,     ///< an optimal vertex was found
  infeasible,  ///< CLP proved that no x satisfies the rows and bounds
  unbounded,   ///< the objective decreases without bound (dual infeasible)
  failed,      ///< iteration limit, numerical trouble or an invalid programme
};

/// "optimal", "infeasible", "unbounded", "failed".
const char* to_string(LpStatus status);

struct LpSolution {
  LpStatus status = LpStatus::failed;
  std::vector<double> x;             ///< the optimal point (only when optimal)
  std::vector<double> row_activity;  ///< A x (only when optimal)
  double objective = 0.0;            ///< cᵀx (only when optimal)
  int iterations = 0;                ///< simplex iterations
  std::string message;               ///< CLP's status in words (when not optimal)
};

/// Solves `lp` with CLP's dual simplex (quiet). Never throws for an
/// infeasible or unbounded programme: the status says so. An optimal
/// solution is checked against the rows and bounds (to 1e-7 relative); a
/// violated one is reported as failed.
LpSolution solve(const LinearProgram& lp);

}  // namespace camdyn::optim
