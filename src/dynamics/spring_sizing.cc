#include "dynamics/spring_sizing.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "common/constants.h"

namespace camdyn {

namespace {

/// Below this share of the law's lift, s counts as zero for the rate (the rate cannot help there).
constexpr double kZeroLift = 1e-12;

/// min over ω ∈ [0, W] of a ω² + b ω.
double min_quadratic(double a, double b, double w_max) {
  double m = std::min(0.0, a * w_max * w_max + b * w_max);
  if (a > 0.0) {
    const double vertex = -b / (2.0 * a);
    if (vertex > 0.0 && vertex < w_max) m = std::min(m, -b * b / (4.0 * a));
  }
  return m;
}

/// D(θ) of the file comment.
double demand(const LawSample& s, const RigidSpringLoad& load, double omega_max) {
  return load.min_force - load.weight - min_quadratic(load.mass * s.d2s, load.damping * s.ds, omega_max);
}

/// The largest f over [a, b] near a sampled maximum: golden section.
double refine_max(const std::function<double(double)>& f, double a, double b, double& at) {
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 60 && b - a > 1e-14; ++it) {
    const double x1 = b - r * (b - a), x2 = a + r * (b - a);
    if (f(x1) > f(x2))
      b = x2;
    else
      a = x1;
  }
  at = 0.5 * (a + b);
  return f(at);
}

}  // namespace

SpringSizing size_spring(const MotionLaw& law, const RigidSpringLoad& load, double omega_max, int samples) {
  SpringSizing out;
  double best = -kInf, best_theta = 0.0;
  double rate = 0.0;
  bool no_rate = false;
  const double zero = kZeroLift * std::max(law.lift(), 1e-300);
  for (const MotionLaw::Piece& pc : law.pieces()) {
    // Each end from inside its own piece, so a jump in s'' at a join counts on both sides.
    auto theta_at = [&](double x) { return pc.start + std::clamp(x, 1e-12, 1.0 - 1e-12) * (pc.end - pc.start); };
    auto preload_need = [&](double x) {
      const LawSample s = law.eval(theta_at(x));
      return demand(s, load, omega_max) - load.stiffness * s.s;
    };
    int best_n = -1;
    double piece_best = -kInf;
    for (int n = 0; n <= samples; ++n) {
      const double x = static_cast<double>(n) / samples;
      const LawSample s = law.eval(theta_at(x));
      const double d = demand(s, load, omega_max);
      if (d - load.stiffness * s.s > piece_best) piece_best = d - load.stiffness * s.s, best_n = n;
      if (s.s > zero)
        rate = std::max(rate, (d - load.preload) / s.s);
      else if (d > load.preload)
        no_rate = true;
    }
    double x_at = static_cast<double>(best_n) / samples;
    const double lo = std::max(0.0, x_at - 1.0 / samples), hi = std::min(1.0, x_at + 1.0 / samples);
    double refined_at = x_at;
    const double refined = refine_max(preload_need, lo, hi, refined_at);
    if (refined > piece_best) piece_best = refined, x_at = refined_at;
    if (piece_best > best) best = piece_best, best_theta = theta_at(x_at);
  }
  out.required_preload = std::max(0.0, best);
  out.preload_at_deg = best_theta * 180.0 / std::numbers::pi;
  out.required_stiffness = no_rate ? kInf : rate;
  return out;
}

RigidSpringLoad rigid_spring_load(const Model& model, double min_force) {
  RigidSpringLoad load;
  load.mass = model.mass;
  load.damping = model.forces.damper.damping;
  load.weight = model.forces.weight(model.mass);
  load.stiffness = model.forces.spring.stiffness;
  load.preload = model.forces.spring.preload;
  load.min_force = min_force;
  return load;
}

}  // namespace camdyn
