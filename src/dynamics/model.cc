#include "dynamics/model.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "common/errors.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

Eigen::Vector2d rotate(const Eigen::Vector2d& p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * p.x() - s * p.y(), s * p.x() + c * p.y()};
}

// J p: p rotated by +90°.
Eigen::Vector2d perp(const Eigen::Vector2d& p) { return {-p.y(), p.x()}; }

ForceLaw build_force_law(const SceneConfig& scene, const std::string& file) {
  const ContactConfig& c = scene.mechanism.contact;
  ForceLaw law;
  try {
    law.model = contact_model_from_string(c.model);
  } catch (const std::invalid_argument& e) {
    throw InputError(file, "mechanism.contact.model", e.what());
  }
  law.exponent = c.exponent;
  law.restitution = c.restitution;
  law.reference_velocity = c.reference_velocity;
  law.damping = c.damping.value_or(0.0);
  if (c.from_materials) {
    const MaterialsConfig& m = *c.from_materials;
    const bool line = m.width.has_value();
    const double implied_exponent = line ? 1.0 : 1.5;
    if (std::abs(c.exponent - implied_exponent) > 1e-12)
      throw InputError(file, "mechanism.contact.exponent",
                       std::string("stiffness from materials is for ") + (line ? "line" : "point") +
                           " contact, which needs exponent " + (line ? "1" : "1.5"));
    law.stiffness = stiffness_from_materials(m.E1, m.nu1, m.E2, m.nu2, scene.mechanism.cam.base_radius,
                                             scene.mechanism.follower.shape.radius, line, m.width.value_or(0.0));
  } else if (c.stiffness) {
    law.stiffness = *c.stiffness;
  } else {
    throw InputError(file, "mechanism.contact.stiffness", "a stiffness or { \"from_materials\": ... } is required");
  }
  if (!(law.stiffness > 0.0) || !std::isfinite(law.stiffness))
    throw InputError(file, "mechanism.contact.stiffness", "must be a finite number > 0");
  return law;
}

}  // namespace

Model build_model(const SceneConfig& scene, const std::string& file) {
  const MechanismConfig& mech = scene.mechanism;
  Model model;
  model.law = std::make_shared<const MotionLaw>(build_motion_law(mech.cam.motion_law, file));
  model.direction = mech.cam.direction == "cw" ? -1 : +1;
  model.cam.law = model.law.get();
  model.cam.base_radius = mech.cam.base_radius;
  model.cam.roller_radius = mech.follower.shape.radius;
  model.cam.offset = mech.follower.offset;
  model.cam.direction = model.direction;
  model.omega = mech.cam.rpm * kTwoPi / 60.0;
  model.theta0 = mech.cam.initial_angle_deg * std::numbers::pi / 180.0;
  model.geometry = check_cam(model.cam, file);

  const FollowerConfig& f = mech.follower;
  model.mass = f.mass;
  model.spring_stiffness = f.spring.stiffness;
  model.spring_preload = f.spring.preload;
  model.damping = f.damping;
  model.gravity = scene.gravity;

  model.contact = build_force_law(scene, file);
  model.friction.mu = mech.contact.friction.mu;
  model.friction.regularization_velocity = mech.contact.friction.regularization_velocity;
  model.friction.linear_ramp = mech.contact.friction.regularization == "linear";
  model.roller_inertia = f.shape.inertia;
  // A roller without inertia rolls freely: friction can do no work, so neither
  // the spin state nor the friction force is assembled (physics.md §3).
  model.has_spin = model.roller_inertia > 0.0 && model.friction.mu > 0.0;

  model.tracking = mech.contact.tracking == "newton" ? Tracking::newton : Tracking::differential;
  // Drift of f decays with time constant 1/α, well below a cam degree.
  model.tracking_gain = 1000.0 + 100.0 * model.omega;

  model.state_names = {"follower_position", "follower_velocity"};
  int next = 2;
  if (model.tracking == Tracking::differential) {
    model.index_u = next++;
    model.state_names.push_back("contact_parameter_u");
  }
  if (model.has_spin) {
    model.index_spin = next++;
    model.state_names.push_back("roller_spin");
  }
  model.state_size = next;

  model.elements.push_back("follower_mass");
  if (model.spring_stiffness > 0.0 || model.spring_preload > 0.0) model.elements.push_back("spring");
  if (model.damping > 0.0) model.elements.push_back("damper");
  if (model.gravity != 0.0) model.elements.push_back("gravity");
  model.elements.push_back(std::string("contact:") + to_string(model.contact.model));
  if (model.has_spin)
    model.elements.push_back(std::string("friction:coulomb_") + (model.friction.linear_ramp ? "linear" : "tanh"));
  return model;
}

void evaluate(const Model& model, Workspace& ws, double t, const double* state, Evaluation& ev) {
  const double sigma = model.direction;
  ev.theta = model.theta(t);
  ev.y = state[0];
  ev.v = state[1];
  ev.spin = model.has_spin ? state[model.index_spin] : 0.0;

  // Roller centre in the world and in the cam frame, and its velocity relative to the cam.
  const double phi = sigma * ev.theta;
  const Eigen::Vector2d c_world(model.cam.offset, model.cam.y0() + ev.y);
  const Eigen::Vector2d v_world(0.0, ev.v);
  const Eigen::Vector2d c_cam = rotate(c_world, -phi);
  const Eigen::Vector2d v_cam = rotate(v_world - sigma * model.omega * perp(c_world), -phi);

  ev.tracking_ok = true;
  if (model.tracking == Tracking::differential) {
    ev.pair = evaluate_pair(model.cam, c_cam, state[model.index_u]);
    ev.tracking_ok = ev.pair.f_u < 0.0;
    ev.u_rate = ev.tracking_ok
                    ? (-model.tracking_gain * ev.pair.f - ev.pair.tangent_u.dot(v_cam)) / ev.pair.f_u
                    : 0.0;
  } else {
    double u = ws.u_warm;
    if (!newton_track(model.cam, c_cam, u, ev.pair)) {
      ++ws.tracking_resets;
      ev.tracking_ok = global_pair(model.cam, c_cam, ev.theta, u, ev.pair);
    }
  }

  const Eigen::Vector2d& n = ev.pair.normal;
  ev.gap = ev.pair.gap;
  ev.gap_rate = n.dot(v_cam);
  ev.delta = -ev.gap;
  ev.delta_rate = -ev.gap_rate;
  ev.normal_force = model.contact.force(ev.delta, ev.delta_rate, ws.v0);

  const Eigen::Vector2d t_dir = perp(n);
  ev.slip = 0.0;
  ev.friction_force = 0.0;
  if (model.has_spin) {
    ev.slip = t_dir.dot(v_cam) - (ev.spin - sigma * model.omega) * model.cam.roller_radius;
    ev.friction_force = -model.friction.coefficient(ev.slip) * ev.normal_force;
  }
  const Eigen::Vector2d force_cam = ev.normal_force * n + ev.friction_force * t_dir;
  ev.force_world = rotate(force_cam, phi);

  const double spring = model.spring_preload + model.spring_stiffness * ev.y;
  ev.acceleration =
      (ev.force_world.y() - spring - model.damping * ev.v - model.mass * model.gravity) / model.mass;
  ev.spin_acceleration =
      model.has_spin ? -model.cam.roller_radius * ev.friction_force / model.roller_inertia : 0.0;

  // Powers (physics.md §5). The drive power acts at the roller-side contact
  // point p = c − r_r n, which makes the balance exact for the tracked pair.
  const Eigen::Vector2d p = c_cam - model.cam.roller_radius * n;
  ev.power_drive = sigma * model.omega * (p.x() * force_cam.y() - p.y() * force_cam.x());
  ev.power_damper = model.damping * ev.v * ev.v;
  ev.power_hysteresis =
      ev.delta > 0.0 ? (ev.normal_force - model.contact.elastic_force(ev.delta)) * ev.delta_rate : 0.0;
  ev.power_friction = -ev.friction_force * ev.slip;
}

void state_derivative(const Model& model, const Evaluation& ev, double* state_dot) {
  state_dot[0] = ev.v;
  state_dot[1] = ev.acceleration;
  if (model.index_u >= 0) state_dot[model.index_u] = ev.u_rate;
  if (model.index_spin >= 0) state_dot[model.index_spin] = ev.spin_acceleration;
}

void quadrature_derivative(const Evaluation& ev, double* q_dot) {
  q_dot[0] = ev.power_drive;
  q_dot[1] = ev.power_damper;
  q_dot[2] = ev.power_hysteresis;
  q_dot[3] = ev.power_friction;
  q_dot[4] = ev.gap > 0.0 ? ev.gap : 0.0;  // smooth within a step: g = 0 is a root
}

void root_functions(const Model& model, const Workspace& ws, const Evaluation& ev, double* g) {
  g[0] = ev.gap;
  if (model.contact.has_clamp_switch()) g[1] = model.contact.clamp_switch(ev.delta, ev.delta_rate, ws.v0);
}

EnergyTerms energy_terms(const Model& model, const Evaluation& ev) {
  EnergyTerms e;
  e.kinetic = 0.5 * model.mass * ev.v * ev.v + 0.5 * model.roller_inertia * ev.spin * ev.spin;
  // Spring energy measured from its free length, so that it is never negative.
  const double k = model.spring_stiffness, f0 = model.spring_preload;
  e.spring = f0 * ev.y + 0.5 * k * ev.y * ev.y + (k > 0.0 ? 0.5 * f0 * f0 / k : 0.0);
  e.gravity = model.mass * model.gravity * ev.y;
  e.contact = model.contact.elastic_energy(ev.delta);
  return e;
}

double jump_speed_rpm(const Model& model) {
  const double x0 = model.spring_stiffness > 0.0 ? model.spring_preload / model.spring_stiffness : 0.0;
  auto omega_at = [&](double theta) {
    const LawSample s = model.law->eval(theta);
    if (!(s.d2s < 0.0)) return std::numeric_limits<double>::infinity();
    const double hold = model.spring_stiffness * (s.s + x0) + model.mass * model.gravity;
    if (model.spring_stiffness == 0.0 && model.spring_preload > 0.0) {
      // Constant-force spring: the preload alone holds the follower.
      return std::sqrt(std::max(0.0, model.spring_preload + model.mass * model.gravity) / (-model.mass * s.d2s));
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
    if (omega_at(x1) < omega_at(x2)) b = x2; else a = x1;
  }
  best = std::min(best, omega_at(0.5 * (a + b)));
  return best * 60.0 / kTwoPi;
}

}  // namespace camdyn
