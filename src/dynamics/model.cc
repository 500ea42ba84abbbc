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

void state_jacobian(const Model& model, Workspace& ws, double t, const double* state, double* jacobian) {
  using Row = Eigen::Matrix<double, 1, 4>;  // gradient over the state (at most y, ẏ, u, Ω)
  const int n = model.state_size;
  const int iy = 0, iv = 1, iu = model.index_u, iw = model.index_spin;
  const double sigma = model.direction;
  Evaluation ev;
  evaluate(model, ws, t, state, ev);
  const double phi = sigma * ev.theta;
  const Eigen::Vector2d c_world(model.cam.offset, model.cam.y0() + ev.y);
  const Eigen::Vector2d c_cam = rotate(c_world, -phi);
  const Eigen::Vector2d v_cam = rotate(Eigen::Vector2d(0.0, ev.v) - sigma * model.omega * perp(c_world), -phi);
  // ∂c/∂y and ∂v_c/∂y, ∂v_c/∂ẏ in the cam frame.
  const Eigen::Vector2d e_y = rotate(Eigen::Vector2d(0.0, 1.0), -phi);
  const Eigen::Vector2d dvc_dy = rotate(Eigen::Vector2d(sigma * model.omega, 0.0), -phi);

  // Pair geometry at u and its u-derivatives.
  const CurvePoint p = model.cam.pitch(ev.pair.u);
  const Eigen::Vector2d d = c_cam - p.r;
  const double speed = p.dr.norm();
  const Eigen::Vector2d& nrm = ev.pair.normal;
  const double orientation = nrm.dot(Eigen::Vector2d(p.dr.y(), -p.dr.x())) > 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d n_u =
      orientation * Eigen::Vector2d(p.d2r.y(), -p.d2r.x()) / speed - nrm * (p.dr.dot(p.d2r) / (speed * speed));
  const Eigen::Vector2d t_dir = perp(nrm), t_u = perp(n_u);
  const double f_u = ev.pair.f_u;

  // ∂u/∂x: a state (differential) or the implicit solution of f(c, u) = 0 (Newton).
  Row du = Row::Zero();
  if (iu >= 0) du(iu) = 1.0;
  else du(iy) = -p.dr.dot(e_y) / f_u;
  Row dc_n = Row::Zero();  // n · ∂c/∂x
  dc_n(iy) = nrm.dot(e_y);
  const Row gap = dc_n + (n_u.dot(d)) * du;
  Row gap_rate = Row::Zero();
  gap_rate(iy) = nrm.dot(dvc_dy);
  gap_rate(iv) = nrm.dot(e_y);
  gap_rate += n_u.dot(v_cam) * du;

  // Normal force.
  Row force_n = Row::Zero();
  if (ev.normal_force > 0.0) {
    const ForceLaw& law = model.contact;
    const double delta_n = std::pow(ev.delta, law.exponent);
    double df_ddelta = law.exponent * law.stiffness * delta_n / ev.delta, df_drate = 0.0;
    if (law.model == ContactModel::kelvin_voigt) {
      df_drate = law.damping;
    } else if (law.model != ContactModel::hertz) {
      df_ddelta *= 1.0 + law.chi() * ev.delta_rate / ws.v0;
      df_drate = law.stiffness * delta_n * law.chi() / ws.v0;
    }
    force_n = -df_ddelta * gap - df_drate * gap_rate;
  }

  // Friction and roller spin.
  Row force_t = Row::Zero();
  if (model.has_spin) {
    Row slip = Row::Zero();
    slip(iy) = t_dir.dot(dvc_dy);
    slip(iv) = t_dir.dot(e_y);
    slip += t_u.dot(v_cam) * du;
    slip(iw) -= model.cam.roller_radius;
    const FrictionLaw& fr = model.friction;
    const double x = ev.slip / fr.regularization_velocity;
    const double shape = fr.coefficient(ev.slip) / fr.mu;
    const double dshape = fr.linear_ramp ? (std::abs(x) < 1.0 ? 1.0 / fr.regularization_velocity : 0.0)
                                         : (1.0 - shape * shape) / fr.regularization_velocity;
    force_t = -fr.mu * (dshape * ev.normal_force * slip + shape * force_n);
  }

  // World y-component of the contact force F = F_n n + F_t t (rotated by φ).
  const double sp = std::sin(phi), cp = std::cos(phi);
  auto world_y = [&](const Eigen::Vector2d& v) { return sp * v.x() + cp * v.y(); };
  const Row force_y = world_y(nrm) * force_n + ev.normal_force * world_y(n_u) * du + world_y(t_dir) * force_t +
                      ev.friction_force * world_y(t_u) * du;

  Eigen::Map<Eigen::MatrixXd> J(jacobian, n, n);
  J.setZero();
  J(0, iv) = 1.0;
  Row accel = force_y;
  accel(iy) -= model.spring_stiffness;
  accel(iv) -= model.damping;
  J.row(1) = (accel / model.mass).head(n);
  if (iw >= 0) J.row(iw) = (-model.cam.roller_radius / model.roller_inertia * force_t).head(n);
  if (iu >= 0) {
    // u̇ = (−α f − P'·v_c) / f_u.
    Row f = Row::Zero(), pv = Row::Zero(), fu = Row::Zero();
    f(iy) = p.dr.dot(e_y);
    f(iu) = f_u;
    pv(iy) = p.dr.dot(dvc_dy);
    pv(iv) = p.dr.dot(e_y);
    pv(iu) = p.d2r.dot(v_cam);
    fu(iy) = p.d2r.dot(e_y);
    fu(iu) = p.d3r.dot(d) - 3.0 * p.dr.dot(p.d2r);
    J.row(iu) = ((-model.tracking_gain * f - pv - ev.u_rate * fu) / f_u).head(n);
  }
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
