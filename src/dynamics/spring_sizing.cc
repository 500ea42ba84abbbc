#include "dynamics/spring_sizing.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/held_train.h"

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
  return load.min_force - load.weight - min_quadratic(load.mass * s.d2s, load.damping * s.ds, omega_max) -
         load.other_stiffness * s.s;
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

std::optional<RigidSpringLoad> rigid_spring_load(const Model& model, double min_force) {
  return rigid_spring_load(model, min_force, follower_linear_parts(model));
}

std::optional<RigidSpringLoad> rigid_spring_load(const Model& model, double min_force,
                                                 const std::optional<FollowerLinearParts>& linear) {
  if (!linear) return std::nullopt;
  RigidSpringLoad load;
  load.mass = model.mass;
  load.damping = linear->others.damping;
  load.weight = linear->others.load;
  load.other_stiffness = linear->others.stiffness;
  load.stiffness = linear->spring.stiffness;
  load.preload = linear->spring.load;
  load.min_force = min_force;
  return load;
}

namespace {

constexpr int kHeldSizingAngles = 1024;  ///< the held train's response grid (as its jump speed's)
constexpr int kHeldSizingSteps = 200;    ///< equal speed steps up to ω_max
/// |g| below this [N/N] (or [N/(N m)]): the preload does not reach the quantity.
constexpr double kNoReach = 1e-9;

bool body_has_spring(const Model& model, int body) {
  return std::any_of(model.train.elements.begin(), model.train.elements.end(), [&](const TrainElement& e) {
    return e.body == body && (e.role == TrainRole::spring || e.role == TrainRole::spring_segment);
  });
}

/// A spring of the train: its body, preload F₀ [N | N m] and ∂f0/∂F₀, the
/// held train's constant load per unit preload.
struct TrainSpring {
  int body = 0;
  double preload = 0.0;
  Eigen::VectorXd d;
};

/// Every spring of the model, the follower's first.
std::vector<TrainSpring> train_springs(const Model& model, int n) {
  std::vector<TrainSpring> out;
  if (model.forces.spring().present()) {  // the follower's massless spring: f0[0] −= F₀
    out.push_back({0, model.forces.spring().preload, Eigen::VectorXd::Zero(n)});
    out.back().d[0] = -1.0;
  }
  for (int b = 0; b < static_cast<int>(model.train.bodies.size()); ++b) {
    if (!body_has_spring(model, b)) continue;
    TrainSpring spring{b, 0.0, Eigen::VectorXd::Zero(n)};
    // Every segment of the spring carries F₀: the body gets −F₀, each lump F₀ − F₀ (docs/model.md §12).
    for (const TrainElement& e : model.train.elements) {
      if (e.body != b || (e.role != TrainRole::spring && e.role != TrainRole::spring_segment)) continue;
      if (e.a >= 0) spring.d[e.a] -= e.ca;
      if (e.b >= 0) spring.d[e.b] -= e.cb;
      spring.preload = e.preload;
    }
    out.push_back(std::move(spring));
  }
  return out;
}

std::string spring_path(int body) {
  return body == 0 ? "mechanism.follower.spring" : "mechanism.train[" + std::to_string(body - 1) + "].spring";
}

/// The spring to size: the first (the follower's first) whose preload raises
/// or leaves every held quantity; `g` receives its static response per unit
/// preload of each quantity. Null with out.reason when there is none.
const TrainSpring* sized_spring(const HeldTrain& train, const std::vector<TrainSpring>& springs, std::vector<double>& g,
                                HeldSpringSizing& out) {
  if (springs.empty()) {
    out.reason = "the scene has no spring to size";
    return nullptr;
  }
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(train.K);
  for (const TrainSpring& spring : springs) {
    const Eigen::VectorXd y = lu.solve(spring.d);  // static response per unit preload [m/N]
    g.assign(train.quantities.size(), 0.0);
    std::string unloads;
    for (std::size_t k = 0; k < train.quantities.size(); ++k) {
      if (!train.quantities[k].held()) continue;
      g[k] = train.quantities[k].a.dot(y);  // [N/N | N/(N m)]
      if (g[k] < -kNoReach && unloads.empty()) unloads = train.quantities[k].name;
    }
    if (unloads.empty()) return &spring;
    out.reason += std::string(out.reason.empty() ? "" : "; ") + "a preload on " + spring_path(spring.body) +
                  " unloads the " + unloads;
  }
  out.reason = "no spring's preload raises every held force (" + out.reason + ")";
  return nullptr;
}

/// The speeds the sizing is checked at [rad/s]: 0 … ω_max in equal steps and
/// each undamped natural frequency over each significant harmonic below ω_max.
std::vector<double> sizing_speeds(const HeldTrain& train, const GridSignal& law, double omega_max) {
  std::vector<double> speeds;
  for (int j = 0; j <= kHeldSizingSteps; ++j) speeds.push_back(omega_max * j / kHeldSizingSteps);
  for (const double w : resonance_speeds(train, law, omega_max)) speeds.push_back(w);
  return speeds;
}

}  // namespace

HeldSpringSizing size_held_spring(const Model& model, double min_force, double omega_max) {
  return size_held_spring(model, min_force, omega_max, follower_linear_parts(model));
}

HeldSpringSizing size_held_spring(const Model& model, double min_force, double omega_max,
                                  const std::optional<FollowerLinearParts>& linear) {
  HeldSpringSizing out;
  if (!linear) {
    out.reason = kNoLinearPart;
    return out;
  }
  const HeldTrain train = held_train(model);
  std::vector<double> g;  // per held quantity, its change per unit preload [N/N | N/(N m)]
  const std::vector<TrainSpring> springs = train_springs(model, train.free_coordinates());
  const TrainSpring* spring = sized_spring(train, springs, g, out);  // into `springs`
  if (!spring) return out;
  out.body = spring->body;
  out.spring = spring_path(spring->body);
  out.unit = spring->body == 0 ? coordinate_units(model).force : "N";
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, kHeldSizingAngles);
  HeldTrainResponse response(train, {law}, kHeldSizingAngles);
  // Each held quantity is L + Δ g (Δ = F₀' − F₀): Δ ≥ (floor − min L) / g where g > 0.
  double need = -kInf;
  for (const double w : sizing_speeds(train, law, omega_max)) {
    const SpeedResponse& r = response.at(w);
    for (std::size_t k = 0; k < train.quantities.size(); ++k) {
      const HeldQuantity& q = train.quantities[k];
      if (!q.held()) continue;
      const Eigen::VectorXd values = r.fixed[k] + r.per_signal[k].col(0);
      Eigen::Index at = 0;
      const double margin = values.minCoeff(&at) - min_force;  // [N]
      if (g[k] > kNoReach) {
        if (-margin / g[k] > need) {
          need = -margin / g[k];
          out.binding = q.name;
          out.preload_at_deg = 360.0 * static_cast<double>(at) / kHeldSizingAngles;
          out.preload_at_rpm = w * 60.0 / kTwoPi;
        }
      } else if (margin < 0.0) {
        out.reason = "the preload of " + out.spring + " does not reach the " + q.name + ", which falls below " +
                     std::to_string(min_force) + " N at " + std::to_string(w * 60.0 / kTwoPi) + " rpm";
        return out;
      }
    }
  }
  out.required_preload = std::max(0.0, spring->preload + need);
  out.available = true;
  return out;
}

}  // namespace camdyn
