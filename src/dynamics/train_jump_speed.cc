#include "dynamics/train_jump_speed.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "dynamics/held_train.h"
#include "dynamics/rigid_jump_speed.h"

namespace camdyn {

namespace {

constexpr double kRpmPerRadPerSecond = 60.0 / (2.0 * std::numbers::pi);
constexpr int kJumpSpeedAngles = 1024;  ///< of the held train's response grid (dynamics/held_train.h)

/// The train's own elements (links held; seats, stops and clash left out)
/// and the follower forces' linear part `follower` (its massless spring,
/// damper and weight, F₀ = preload + M g summed in that order) into `lt`.
void add_train_elements(const Model& model, const LinearPart& follower, LinearTrain& lt) {
  const int n = static_cast<int>(lt.M.rows());
  lt.K(0, 0) += follower.stiffness;
  lt.C(0, 0) += follower.damping;
  lt.f0[0] -= follower.load;
  for (const TrainElement& e : model.train.elements) {
    if (e.role == TrainRole::seat || e.role == TrainRole::stop || e.role == TrainRole::clash) continue;
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n);
    if (e.a >= 0) c[e.a] += e.ca;
    if (e.b >= 0) c[e.b] += e.cb;
    const double constant = e.preload + e.stiffness * e.offset;  // F at x = 0, ẋ = 0 [N]
    lt.K += e.stiffness * c * c.transpose();
    lt.C += e.damping * c * c.transpose();
    lt.f0 -= constant * c;
    LinearForce force{e.stiffness * c, e.damping * c, 0.0, 0.0, constant, ""};
    if (e.role == TrainRole::link) {
      force.name = "link " + model.train.bodies[static_cast<std::size_t>(e.body)].name;
      lt.held.push_back(force);
    } else if (e.role == TrainRole::spring) {
      force.name = "spring " + model.train.bodies[static_cast<std::size_t>(e.body)].name;
      lt.peaks.push_back(force);
    }
  }
}

/// The cam contact held as a linear spring and damper of stiffness k_c and
/// damping c_c between the lift and q, with force F̄ − k_c δ̄ at δ = 0, in
/// generalised units (lever L: an arm's length, 1 for a translating follower).
LinearForce contact_force(double k_c, double c_c, double offset, double lever, int n) {
  LinearForce f;
  f.a = Eigen::VectorXd::Zero(n);
  f.b = Eigen::VectorXd::Zero(n);
  f.a[0] = -k_c * lever;
  f.b[0] = -c_c * lever;
  f.e = k_c * lever;
  f.f = c_c * lever;
  f.constant = offset;
  f.name = "cam contact";
  return f;
}

}  // namespace

LinearTrain linear_train_without_contact(const Model& model) {
  return linear_train_without_contact(model, follower_linear_parts(model));
}

LinearTrain linear_train_without_contact(const Model& model, const std::optional<FollowerLinearParts>& linear) {
  if (!linear) throw std::invalid_argument(std::string("the held, linearised train: ") + kNoLinearPart);
  const int n = std::max(1, static_cast<int>(model.train.coordinates.size()));  // a model without a train: 1
  LinearTrain base;
  base.M = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    base.M(i, i) = i == 0 ? model.mass : model.train.coordinates[static_cast<std::size_t>(i)].mass;
  base.C = base.K = Eigen::MatrixXd::Zero(n, n);
  base.f0 = base.k_in = base.c_in = Eigen::VectorXd::Zero(n);
  add_train_elements(model, linear->total(), base);
  return base;
}

LinearTrain linearised_train(const Model& model) {
  const int n = std::max(1, static_cast<int>(model.train.coordinates.size()));
  const LinearTrain base = linear_train_without_contact(model);
  const double lever = model.follower.oscillating() ? model.follower.arm_length : 1.0;  // [m/rad | -]
  const ForceLaw& law = model.contact;
  const double mean_lift = lift_harmonics(*model.law, 0).mean;  // [m | rad]
  // The mean contact force F̄ [N] of the static train, with the contact first
  // taken rigid, then at its stiffness there (twice: exact for exponent 1).
  double k_c = 1e3 * std::max(law.stiffness, 1.0), mean_force = 0.0, mean_delta = 0.0;
  LinearTrain lt;
  for (int pass = 0; pass < 3; ++pass) {
    const double c_c = force_form(law.model) == ForceForm::viscous ? law.damping
                       : force_form(law.model) == ForceForm::hysteresis
                           ? law.chi() * mean_force / law.reference_velocity
                           : 0.0;
    lt = base;
    const LinearForce f = contact_force(k_c, c_c, mean_force - k_c * mean_delta, lever, n);
    lt.K(0, 0) += k_c * lever * lever;
    lt.C(0, 0) += c_c * lever * lever;
    lt.k_in[0] += k_c * lever * lever;
    lt.c_in[0] += c_c * lever * lever;
    lt.f0[0] += f.constant * lever;
    lt.held.insert(lt.held.begin(), f);
    const Eigen::VectorXd x = lt.K.fullPivLu().solve(lt.f0 + lt.k_in * mean_lift);
    const double force = f.a.dot(x) + f.e * mean_lift + f.constant;  // [N]
    if (pass > 0 && !(force > 0.0)) break;
    mean_force = std::max(force, 0.0);
    mean_delta = mean_force > 0.0 ? std::pow(mean_force / law.stiffness, 1.0 / law.exponent) : 0.0;
    k_c = mean_delta > 0.0 ? law.exponent * mean_force / mean_delta : law.stiffness;
  }
  return lt;
}

namespace {

// jump_speed_rpm of the model, as made when it was assembled (made now when it was not).
double rigid_jump_speed_rpm(const Model& model) {
  return std::isnan(model.rigid_jump_speed_rpm) ? jump_speed_rpm(model) : model.rigid_jump_speed_rpm;
}

}  // namespace

double train_jump_speed_rpm(const Model& model) { return train_jump_speed_rpm(model, follower_linear_parts(model)); }

double train_jump_speed_rpm(const Model& model, const std::optional<FollowerLinearParts>& linear) {
  if (!linear) return std::numeric_limits<double>::quiet_NaN();
  const double rigid_rpm = rigid_jump_speed_rpm(model);
  const double limit_rpm = std::isfinite(rigid_rpm) && rigid_rpm > 0.0 ? 20.0 * rigid_rpm : 1e5;
  const GridSignal law = grid_signal([&](double theta) { return model.law->eval(theta); }, kJumpSpeedAngles);
  const double omega =
      held_train_jump_speed(held_train(model), law, limit_rpm / kRpmPerRadPerSecond, 0.0, 0.0);  // [rad/s]
  return std::isfinite(omega) ? omega * kRpmPerRadPerSecond : std::numeric_limits<double>::infinity();
}

double model_jump_speed_rpm(const Model& model) {
  return model.train.has_coordinates() ? model.train_jump_speed_rpm : rigid_jump_speed_rpm(model);
}

std::string jump_speed_text(double rpm, int digits) {
  if (std::isnan(rpm)) return std::string("not available (") + kNoLinearPart + ")";
  if (!std::isfinite(rpm)) return "none (the law never decelerates)";
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*g rpm", digits, rpm);
  return buffer;
}

const char* jump_speed_name(const Model& model) {
  return model.train.has_coordinates() ? "train jump speed (held, linearised)" : "rigid-model jump speed";
}

bool rigid_spring_sizing_applies(const Model& model) { return !model.train.has_coordinates(); }

}  // namespace camdyn
