#include "optim/optimize/lobe_bound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "common/errors.h"
#include "optim/linear_program.h"

namespace camdyn::optim {

namespace {

/// The grid: s_i at θ_i = from + i h for i = −2 … N + 2; columns for i = 1 … N − 1,
/// the rest known (from the kept law).
struct Grid {
  int n = 0;
  double from = 0.0, h = 0.0;
  std::vector<double> known;  ///< s_i for i = −2 … N + 2 (index i + 2); used where i ∉ [1, N − 1]

  double unit = 1e-3;  ///< the columns are s / unit: millimetres, so CLP's tolerances mean the same in every row
  bool free(int i) const { return i >= 1 && i <= n - 1; }
  int column(int i) const { return i - 1; }
  /// known[]'s index of grid point i (i ≥ −2).
  static std::size_t index_of(int i) {
    const int index = i + 2;
    return static_cast<std::size_t>(index);
  }
  /// Adds weight·s_i to the row: a term when s_i is a column, else into `constant`.
  void add(int i, double weight, std::vector<std::pair<int, double>>& terms, double& constant) const {
    if (free(i))
      terms.emplace_back(column(i), weight * unit);
    else
      constant += weight * known[index_of(i)];
  }
};

/// Stencil weights (offsets −2 … 2) of s, s', s'' at a point, and of s' and
/// s''' half a step after it. The half-step ones are the compact
/// differences (s_{i+1} − s_i)/h and (s_{i+2} − 3s_{i+1} + 3s_i − s_{i−1})/h³:
/// central ones would leave the even and odd points free of each other
/// (a zigzag they do not see), and the bound would be loose by it.
constexpr double kStencil[5][5] = {{0.0, 0.0, 1.0, 0.0, 0.0},
                                   {0.0, -0.5, 0.0, 0.5, 0.0},
                                   {0.0, 1.0, -2.0, 1.0, 0.0},
                                   {0.0, 0.0, -1.0, 1.0, 0.0},
                                   {0.0, -1.0, 3.0, -3.0, 1.0}};

/// Σ_k a_k (stencil k) at grid point i as terms and a constant: a = (s, s',
/// s'' at i; s', s''' at i + 1/2).
void combination(const Grid& g, int i, const std::array<double, 5>& a, std::vector<std::pair<int, double>>& terms,
                 double& constant) {
  terms.clear();
  constant = 0.0;
  const double scale[5] = {1.0, 1.0 / g.h, 1.0 / (g.h * g.h), 1.0 / g.h, 1.0 / (g.h * g.h * g.h)};
  for (int o = -2; o <= 2; ++o) {
    double w = 0.0;
    for (int k = 0; k < 5; ++k) w += a[k] * kStencil[k][o + 2] * scale[k];
    if (w != 0.0) g.add(i + o, w, terms, constant);
  }
}

}  // namespace

LobeBound lift_area_bound(const MotionLaw& law, double from, double to, const RigidFollower& f,
                          const LobeLimits& limits, int grid) {
  Grid g;
  g.n = grid;
  g.from = from;
  g.h = (to - from) / grid;
  for (int i = -2; i <= grid + 2; ++i) g.known.push_back(law.eval(from + i * g.h).s);
  g.known[2] = law.eval(from).s;
  g.known[Grid::index_of(grid)] = law.eval(to).s;

  LinearProgram lp;
  // Trapezoid rule: every interior point weighs h; the costs are −1 (CLP's
  // optimality tolerance is absolute, so the objective is kept of order N).
  for (int i = 1; i < grid; ++i) lp.add_column(-kLpInfinity, limits.max_lift / g.unit, -1.0);
  std::vector<std::pair<int, double>> terms;
  double constant = 0.0;
  for (int i = -1; i <= grid; ++i) {
    for (const double w : limits.omegas) {
      if (i < 0) break;
      combination(g, i, {f.coefficient_s(), f.coefficient_ds(w), f.coefficient_d2s(w), 0.0, 0.0}, terms, constant);
      if (!terms.empty()) lp.add_row(terms, -f.constant() - constant, kLpInfinity);  // P − P_min ≥ 0
    }
    if (std::isfinite(limits.face_limit)) {
      combination(g, i, {0.0, 0.0, 0.0, 1.0, 0.0}, terms, constant);
      if (!terms.empty()) lp.add_row(terms, -limits.face_limit - constant, limits.face_limit - constant);
    }
    if (limits.min_radius > 0.0 && i >= 0) {
      combination(g, i, {1.0, 0.0, 1.0, 0.0, 0.0}, terms, constant);
      if (!terms.empty()) lp.add_row(terms, limits.min_radius - limits.pitch_height - constant, kLpInfinity);
    }
    if (limits.max_jerk > 0.0) {
      combination(g, i, {0.0, 0.0, 0.0, 0.0, 1.0}, terms, constant);
      if (!terms.empty()) lp.add_row(terms, -limits.max_jerk - constant, limits.max_jerk - constant);
    }
  }
  lp.equilibrate_rows();
  const LpSolution sol = solve(lp);
  LobeBound out;
  out.grid = grid;
  out.status = to_string(sol.status);
  if (sol.status == LpStatus::infeasible) return out;
  if (sol.status != LpStatus::optimal)
    throw NumericalError(std::string("the lift-area certificate programme could not be solved (CLP: ") + sol.message +
                         ")");
  out.solved = true;
  out.lift.push_back(g.known[2]);
  for (int i = 1; i < grid; ++i) out.lift.push_back(g.unit * sol.x[static_cast<std::size_t>(g.column(i))]);
  out.lift.push_back(g.known[Grid::index_of(grid)]);
  out.area = -sol.objective * g.h * g.unit + 0.5 * g.h * (out.lift.front() + out.lift.back());
  return out;
}

double lift_area(const MotionLaw& law, double from, double to) {
  constexpr int kIntervals = 4096;  // even, for Simpson
  const double h = (to - from) / kIntervals;
  double sum = law.eval(from).s + law.eval(to - 1e-12 * h).s;
  for (int i = 1; i < kIntervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * law.eval(from + i * h).s;
  return sum * h / 3.0;
}

double highest_lift(const MotionLaw& law, double from, double to) {
  constexpr int kIntervals = 4096;
  const double h = (to - from) / kIntervals;
  double top = law.eval(to - 1e-12 * h).s;
  for (int i = 0; i < kIntervals; ++i) top = std::max(top, law.eval(from + i * h).s);
  return top;
}

}  // namespace camdyn::optim
