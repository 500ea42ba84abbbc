#include "dynamics/rigid_jump_speed.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "common/constants.h"

namespace camdyn {

namespace {

/// What the rigid-model force needs at one cam angle, none of it depending
/// on the cam speed.
struct RigidSample {
  double d2s = 0.0;           ///< s'' [m/rad²]
  double ds = 0.0;            ///< s' [m/rad]
  double spring_force = 0.0;  ///< k (s + x₀), or the constant-force spring's preload [N]
  double others = 0.0;        ///< the other elements' linear force F₀ + k s (gravity: M g) [N]
  double g_q = 1.0;           ///< ∂g/∂q of the rigid contact
};

/// The return spring's x₀ = F₀ / k [m | rad] (0 without a rate).
double spring_offset(const LinearPart& spring) { return spring.stiffness > 0.0 ? spring.load / spring.stiffness : 0.0; }

RigidSample rigid_sample(const Model& model, const FollowerLinearParts& linear, double theta) {
  const LinearPart& spring = linear.spring;
  const LawSample s = model.law->eval(theta);
  const double x0 = spring_offset(spring);
  return {s.d2s, s.ds, spring.stiffness > 0.0 ? spring.stiffness * (s.s + x0) : spring.load, linear.others.at(s.s),
          model.cam->kinematics(theta).g_q};
}

/// Q / (∂g/∂q) at cam speed omega [rad/s] (rigid_normal_force) [N]; c the linear parts' damping.
double rigid_force(const Model& model, double damping, const RigidSample& a, double omega) {
  const double generalised = model.mass * omega * omega * a.d2s + damping * omega * a.ds + a.spring_force + a.others;
  return generalised / a.g_q;
}

constexpr double kNoFigure = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double jump_speed_rpm(const Model& model) { return jump_speed_rpm(model, follower_linear_parts(model)); }

double jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear) {
  if (!linear) return kNoFigure;
  const LinearPart& spring = linear->spring;
  const LinearPart& others = linear->others;
  const double x0 = spring_offset(spring);
  auto omega_at = [&](double theta) {
    const LawSample s = model.law->eval(theta);
    if (!(s.d2s < 0.0)) return std::numeric_limits<double>::infinity();
    const double hold = spring.stiffness * (s.s + x0) + others.at(s.s);
    if (spring.stiffness == 0.0 && spring.load > 0.0) {
      // Constant-force spring: the preload alone holds the follower.
      return std::sqrt(std::max(0.0, spring.load + others.at(s.s)) / (-model.mass * s.d2s));
    }
    return hold > 0.0 ? std::sqrt(hold / (-model.mass * s.d2s)) : 0.0;
  };
  constexpr int kSamples = 7200;
  double best = std::numeric_limits<double>::infinity();
  int best_i = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double w = omega_at(kTwoPi * i / kSamples);
    if (w < best) best = w, best_i = i;
  }
  if (!std::isfinite(best)) return best;
  // Golden-section refinement around the best sample.
  double a = kTwoPi * (best_i - 1) / kSamples, b = kTwoPi * (best_i + 1) / kSamples;
  const double r = (std::sqrt(5.0) - 1.0) / 2.0;
  for (int it = 0; it < 60; ++it) {
    const double x1 = b - r * (b - a), x2 = a + r * (b - a);
    if (omega_at(x1) < omega_at(x2))
      b = x2;
    else
      a = x1;
  }
  best = std::min(best, omega_at(0.5 * (a + b)));
  return best * 60.0 / kTwoPi;
}

double damped_jump_speed_rpm(const Model& model) { return damped_jump_speed_rpm(model, follower_linear_parts(model)); }

double damped_jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear) {
  const double undamped = jump_speed_rpm(model, linear);  // [rpm]; NaN without a linear part
  if (!std::isfinite(undamped)) return undamped;
  const double damping = linear->total().damping;
  if (damping == 0.0) return undamped;
  constexpr int kAngles = 3600, kSpeeds = 200;
  // The law and the cam are sampled once, not at every trial speed: up to
  // 260 speeds × 3,600 angles had cost two thirds of a quickstart CLI run.
  std::vector<RigidSample> samples(kAngles);
  for (int i = 0; i < kAngles; ++i)
    samples[static_cast<std::size_t>(i)] = rigid_sample(model, *linear, kTwoPi * i / kAngles);
  auto holds = [&](double omega) {
    for (const RigidSample& a : samples)
      if (rigid_force(model, damping, a, omega) < 0.0) return false;
    return true;
  };
  // A scan up to twice the undamped bound (the force need not change sign
  // once only), then bisection in the first interval where it fails [rad/s].
  const double top = 2.0 * undamped * kTwoPi / 60.0;
  for (int j = 1; j <= kSpeeds; ++j) {
    if (holds(top * j / kSpeeds)) continue;
    double lo = top * (j - 1) / kSpeeds, hi = top * j / kSpeeds;
    for (int it = 0; it < 60 && hi - lo > 1e-12 * hi; ++it) {
      const double mid = 0.5 * (lo + hi);
      (holds(mid) ? lo : hi) = mid;
    }
    return lo * 60.0 / kTwoPi;
  }
  return std::numeric_limits<double>::infinity();
}

double rigid_normal_force(const Model& model, double theta) { return rigid_normal_force(model, theta, model.omega); }

double rigid_normal_force(const Model& model, double theta, double omega) {
  return rigid_normal_force(model, follower_linear_parts(model), theta, omega);
}

double rigid_normal_force(const Model& model, const std::optional<FollowerLinearParts>& linear, double theta,
                          double omega) {
  if (!linear) return kNoFigure;
  return rigid_force(model, linear->total().damping, rigid_sample(model, *linear, theta), omega);
}

}  // namespace camdyn
