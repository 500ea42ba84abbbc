#include "optim/optimize/jump_bound.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/model.h"

namespace camdyn::optim {

namespace {

/// One rise or return piece as the any-law programme samples it.
struct PieceGrid {
  double beta = 0.0;                  ///< [rad]
  double s_start = 0.0, s_end = 0.0;  ///< end levels [m]
  double v_in = 0.0, v_out = 0.0;     ///< neighbours' slopes at the ends [m/rad]
  int n = 600;                        ///< intervals
};

/// The margin LP of one piece at the speeds `omegas`: maximise t subject to
/// P_i(ω) − P_min ≥ t at every grid point, the lift between its end levels.
/// Returns t* [N]; throws NumericalError when CLP fails.
double piece_margin(const PieceGrid& g, const RigidFollower& f, const std::vector<double>& omegas) {
  LinearProgram lp;
  const double lo = std::min(g.s_start, g.s_end), hi = std::max(g.s_start, g.s_end);
  // Columns 0..n−2 are s_1..s_{n−1}; the last is t.
  for (int i = 1; i < g.n; ++i) lp.add_column(lo, hi);
  const double scale = std::abs(f.constant()) + f.stiffness * (hi - lo) + 1.0;  // a force scale [N]
  const int t = lp.add_column(-kLpInfinity, 10.0 * scale, -1.0);
  const double d = g.beta / g.n;
  // Known lifts: s_{−1}, s_0, s_n, s_{n+1} (ghosts from the neighbours' slopes).
  auto known = [&](int i) -> double {
    if (i <= 0) return g.s_start + i * d * g.v_in;
    return g.s_end + (i - g.n) * d * g.v_out;
  };
  std::vector<std::pair<int, double>> terms;
  for (const double w : omegas) {
    const double a2 = f.coefficient_d2s(w) / (d * d), a1 = f.coefficient_ds(w) / (2.0 * d), a0 = f.coefficient_s();
    for (int i = 0; i <= g.n; ++i) {
      // P_i − P_min = a2 (s₊ − 2 s + s₋) + a1 (s₊ − s₋) + a0 s + constant ≥ t
      const std::array<std::pair<int, double>, 3> stencil = {std::pair{i - 1, a2 - a1}, std::pair{i, a0 - 2.0 * a2},
                                                             std::pair{i + 1, a2 + a1}};
      double rhs = -f.constant();
      terms.clear();
      for (const auto& [k, coefficient] : stencil) {
        if (k >= 1 && k <= g.n - 1)
          terms.emplace_back(k - 1, coefficient);
        else
          rhs -= coefficient * known(k);
      }
      terms.emplace_back(t, -1.0);
      lp.add_row(terms, rhs, kLpInfinity);
    }
  }
  const LpSolution sol = solve(lp);
  if (sol.status != LpStatus::optimal)
    throw NumericalError(std::string("the any-law jump-speed programme could not be solved (CLP: ") + sol.message +
                         ")");
  return sol.x[t];
}

/// Whether two pieces have the same programme: equal, or (without a damper,
/// whose c ω s' changes sign) one the time reversal of the other, which
/// leaves s and s'' and so every row unchanged.
/// Equal to round-off (angles that went through degrees differ in the last bits).
bool same_bound(const PieceGrid& a, const PieceGrid& b, bool reversible) {
  const double ds = 1e-12 * (std::abs(a.s_start) + std::abs(a.s_end) + 1e-9);
  const double dv = 1e-12 * (std::abs(a.v_in) + std::abs(a.v_out) + 1e-9);
  auto near = [](double x, double y, double tol) { return std::abs(x - y) <= tol; };
  if (!near(a.beta, b.beta, 1e-12 * a.beta) || a.n != b.n) return false;
  if (near(a.s_start, b.s_start, ds) && near(a.s_end, b.s_end, ds) && near(a.v_in, b.v_in, dv) &&
      near(a.v_out, b.v_out, dv))
    return true;
  return reversible && near(a.s_start, b.s_end, ds) && near(a.s_end, b.s_start, ds) && near(a.v_in, -b.v_out, dv) &&
         near(a.v_out, -b.v_in, dv);
}

/// 0 … n − 1 for the n pieces of `law`.
std::vector<std::size_t> all_pieces(const MotionLaw& law) {
  std::vector<std::size_t> all(law.pieces().size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  return all;
}

}  // namespace

std::optional<RigidFollower> rigid_follower(const Model& model, double min_force) {
  return rigid_follower(model, min_force, follower_linear_parts(model));
}

std::optional<RigidFollower> rigid_follower(const Model& model, double min_force,
                                            const std::optional<FollowerLinearParts>& linear) {
  if (!linear) return std::nullopt;
  const LinearPart total = linear->total();
  RigidFollower f;
  f.mass = model.mass;
  f.stiffness = total.stiffness;
  f.preload = linear->spring.load;  // F₀ + M g kept in the spring's and gravity's order
  f.damping = total.damping;
  f.weight = linear->others.load;
  f.min_force = min_force;
  if (model.follower.oscillating()) {
    // On an arm the same P is the torque Q about the pivot, and the normal
    // force is Q / g_q with the lever g_q (less μ r_pin with pivot friction).
    // Q ≥ 0 is exact; Q ≥ P_min · 1.2 max g_q keeps N ≥ P_min with room for
    // a design whose lever differs a little from the baseline's.
    double lever = 0.0;
    for (int i = 0; i < 720; ++i) lever = std::max(lever, std::abs(model.cam->kinematics(kTwoPi * i / 720).g_q));
    f.min_force = min_force * 1.2 * lever;
  }
  return f;
}

std::vector<double> check_speeds(double omega, const RigidFollower& follower) {
  std::vector<double> w = {omega};
  for (int k = 1; k < follower.sampled_speeds; ++k) w.push_back(omega * k / follower.sampled_speeds);
  if (follower.damping != 0.0 && follower.sampled_speeds == 0)
    for (int k = 1; k < 8; ++k) w.push_back(omega * k / 8.0);
  return w;
}

double highest_feasible_speed(const std::function<bool(double)>& feasible, double omega_hint, double omega_cap,
                              double rtol, double growth) {
  double lo = 0.0, hi = 0.0;
  double w = std::min(omega_hint, omega_cap);
  if (feasible(w)) {
    lo = w;
    while (true) {
      if (lo >= omega_cap) return omega_cap;
      const double next = std::min(growth * lo, omega_cap);
      if (!feasible(next)) {
        hi = next;
        break;
      }
      lo = next;
    }
  } else {
    hi = w;
    while (true) {
      const double next = hi / growth;
      if (next < omega_hint * 1e-6) return 0.0;
      if (feasible(next)) {
        lo = next;
        break;
      }
      hi = next;
    }
  }
  while (hi - lo > rtol * hi) {
    const double mid = 0.5 * (lo + hi);
    (feasible(mid) ? lo : hi) = mid;
  }
  return lo;
}

SampledLaw::SampledLaw(const MotionLaw& law, int samples) : SampledLaw(law, all_pieces(law), samples) {}

SampledLaw::SampledLaw(const MotionLaw& law, const std::vector<std::size_t>& pieces, int samples) {
  for (const std::size_t i : pieces) {
    const MotionLaw::Piece& pc = law.pieces().at(i);
    for (int n = 0; n <= samples; ++n) {
      const double x = std::clamp(static_cast<double>(n) / samples, 1e-12, 1.0 - 1e-12);
      samples_.push_back(law.eval(pc.start + x * (pc.end - pc.start)));
    }
  }
}

double SampledLaw::worst_margin(const RigidFollower& follower, const std::vector<double>& omegas) const {
  double worst = std::numeric_limits<double>::infinity();
  for (const LawSample& s : samples_)
    for (const double w : omegas) worst = std::min(worst, follower.margin(w, s));
  return worst;
}

std::vector<SegmentJumpBound> any_law_jump_bounds(const MotionLaw& law, const RigidFollower& follower,
                                                  const std::vector<std::size_t>& pieces, double omega_hint, int grid,
                                                  double rtol) {
  std::vector<SegmentJumpBound> out;
  std::vector<PieceGrid> solved;  // grids already bisected, beside `out`
  const auto& all = law.pieces();
  for (const std::size_t index : pieces) {
    const MotionLaw::Piece& pc = all.at(index);
    PieceGrid g;
    g.beta = pc.end - pc.start;
    g.s_start = pc.base;
    g.s_end = pc.base + pc.lift;
    g.v_in = law.eval(pc.start - 1e-9).ds;
    g.v_out = law.eval(pc.end + 1e-9).ds;
    g.n = grid;
    const double scale = std::abs(follower.constant()) + follower.stiffness * std::abs(pc.lift) + 1.0;
    auto feasible = [&](double w) { return piece_margin(g, follower, check_speeds(w, follower)) >= -1e-9 * scale; };
    SegmentJumpBound b;
    b.piece = index;
    b.start_deg = pc.start * kRadToDeg;
    b.end_deg = pc.end * kRadToDeg;
    b.lift = pc.lift;
    const auto same = std::find_if(solved.begin(), solved.end(),
                                   [&](const PieceGrid& o) { return same_bound(o, g, follower.damping == 0.0); });
    if (same != solved.end()) {
      b.omega = out[static_cast<std::size_t>(same - solved.begin())].omega;
      out.push_back(b);
      solved.push_back(g);
      continue;
    }
    const double guess = any_law_jump_speed_closed_form(follower, g.s_start, g.s_end, g.beta);
    // The closed form ignores a damper, so it is then only a rough start.
    const bool good_guess = std::isfinite(guess) && guess > 0.0;
    b.omega = highest_feasible_speed(feasible, good_guess ? guess : omega_hint, 1e3 * omega_hint, rtol,
                                     !good_guess               ? 2.0
                                     : follower.damping == 0.0 ? 1.01
                                                               : 1.1);
    if (b.omega >= 1e3 * omega_hint) b.omega = std::numeric_limits<double>::infinity();
    out.push_back(b);
    solved.push_back(g);
  }
  return out;
}

double any_law_jump_speed_closed_form(const RigidFollower& f, double s_start, double s_end, double beta) {
  const double lo = std::min(s_start, s_end), hi = std::max(s_start, s_end);
  const double hold = f.constant();  // P − P_min at s = 0 and rest [N]
  if (f.stiffness == 0.0) {
    // Constant spring force: decelerate at hold / M ω² over the whole piece, h = a β² / 2.
    if (hold <= 0.0) return 0.0;
    return beta * std::sqrt(hold / (2.0 * (hi - lo) * f.mass));
  }
  // Where u < 0 (the spring cannot hold the follower there at rest) the law
  // must accelerate at least as fast as −λ² u: the extremal keeps
  // u'' = −λ² u throughout and so passes u = 0 on its way up.
  const double u_start = lo + hold / f.stiffness, u_top = hi + hold / f.stiffness;
  if (u_top <= 0.0) return 0.0;
  return beta * std::sqrt(f.stiffness / f.mass) / std::acos(std::max(-1.0, u_start / u_top));
}

}  // namespace camdyn::optim
