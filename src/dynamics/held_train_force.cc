#include "dynamics/held_train_force.h"

#include <cmath>

#include "common/constants.h"
#include "dynamics/held_train.h"
#include "dynamics/rigid_jump_speed.h"

namespace camdyn {

bool rigid_figures_held(const Model& model) {
  return model.train.has_coordinates() && follower_linear_parts(model).has_value();
}

std::vector<double> held_contact_generalised_force(const Model& model, double omega, int angles) {
  return held_contact_generalised_force(model, *model.law, omega, angles);
}

std::vector<double> held_contact_generalised_force(const Model& model, const MotionLaw& law, double omega, int angles,
                                                   double tolerance) {
  const GridSignal lift = grid_signal([&](double theta) { return law.eval(theta); }, angles);
  HeldTrainResponse response(held_train(model), {lift}, angles, tolerance);  // held_train_values at 1e-4
  const SpeedResponse& r = response.at(omega);
  const Eigen::VectorXd contact = r.fixed[0] + r.per_signal[0].col(0);  // quantity 0: the contact
  // The contact is held along the follower's coordinate with δ = L (s − q):
  // its force times L is its generalised force (dynamics/train_jump_speed.h).
  const double lever = model.follower.oscillating() ? model.follower.arm_length : 1.0;  // [m/rad | -]
  std::vector<double> q(static_cast<std::size_t>(angles));
  for (int i = 0; i < angles; ++i) q[static_cast<std::size_t>(i)] = lever * contact[i];
  return q;
}

RigidContactForce::RigidContactForce(const Model& model, double omega) : model_(&model), omega_(omega) {
  if (rigid_figures_held(model)) q_ = held_contact_generalised_force(model, omega, kHeldAngles);
}

double on_revolution_grid(const std::vector<double>& values, double theta) {
  const double n = static_cast<double>(values.size());
  double x = std::fmod(theta / kTwoPi, 1.0) * n;  // [grid steps]
  if (x < 0.0) x += n;
  const double below = std::floor(x), w = x - below;
  const std::size_t i = static_cast<std::size_t>(below) % values.size(), j = (i + 1) % values.size();
  return w == 0.0 ? values[i] : (1.0 - w) * values[i] + w * values[j];
}

double RigidContactForce::generalised(double theta) const {
  if (q_.empty()) return rigid_normal_force(*model_, theta, omega_) * model_->cam->kinematics(theta).g_q;
  return on_revolution_grid(q_, theta);
}

double RigidContactForce::normal(double theta) const {
  if (q_.empty()) return rigid_normal_force(*model_, theta, omega_);
  return generalised(theta) / model_->cam->kinematics(theta).g_q;
}

double RigidContactForce::torque(double theta) const {
  if (q_.empty())
    return rigid_normal_force(*model_, theta, omega_) * model_->cam->kinematics(theta).g_q *
           model_->law->eval(theta).ds;
  return generalised(theta) * model_->law->eval(theta).ds;
}

}  // namespace camdyn
