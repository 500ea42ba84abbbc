#include "dynamics/model.h"

#include <Eigen/LU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/errors.h"
#include "contact/line_curve_tracking.h"
#include "dynamics/dual.h"

namespace camdyn {

namespace {

using Jet = Dual<StateLayout::kCore>;

/// The pair parameter and the profile there, solved in double precision.
struct PairSolution {
  double u = 0.0;
  CurvePoint point;
  double orientation = 1.0;  ///< sign making (r'_y, −r'_x) the outward normal
  bool ok = true;
  // General pair form only (cam frame):
  double v = 0.0;                                            ///< follower profile parameter
  double u_rate = 0.0, v_rate = 0.0;                         ///< differential tracking
  double drift = 0.0;                                        ///< Newton step back to f = 0 (differential tracking)
  double gap = 0.0;                                          ///< [m]
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();          ///< n_A, unit, towards the follower
  Eigen::Vector2d follower_point = Eigen::Vector2d::Zero();  ///< r_B [m]
};

/// The follower's contact element in the cam frame (double): circle centre
/// `a`, or face point `a` and normal `b`.
void element_in_cam_frame(const Model& m, double q, double theta, Eigen::Vector2d& a, Eigen::Vector2d& b) {
  const double phi = m.direction * theta, c = std::cos(phi), s = std::sin(phi);
  auto to_cam = [&](const Vec2<double>& w) { return to_eigen(rotate(w, c, -s)); };
  if (m.reduction == ContactReduction::circle) {
    Vec2<double> centre, rate;
    m.follower.centre(q, centre, rate);
    a = to_cam(centre);
    b.setZero();
  } else {
    Vec2<double> p, n, p_q, n_q;
    m.follower.face(q, p, n, p_q, n_q);
    a = to_cam(p);
    b = to_cam(n);
  }
}

double cam_angle(const Model& m, double t, const double* x) {
  return m.drive.shaft() ? x[*m.layout.cam_angle] : m.theta(t);
}

/// The general pair form: both profiles in their motion, tracked by
/// contact/profile_pair_tracking.h, the result turned into the cam frame.
PairSolution solve_general(const Model& m, Workspace& ws, double t, const double* x) {
  PairSolution ps;
  const double theta = cam_angle(m, t, x);
  const double omega_c = m.drive.shaft() ? x[*m.layout.cam_speed] : m.omega;
  const double phi = m.direction * theta;
  const BodyMotion cam = BodyMotion::make(phi, Eigen::Vector2d::Zero(), m.direction * omega_c);
  const BodyMotion follower = follower_motion(m.follower, x[0], x[1]);
  PairEvaluation pair;
  if (m.tracking == Tracking::differential) {
    ps.u = x[*m.layout.u];
    ps.v = x[*m.layout.v];
    pair = evaluate_profile_pair(*m.pair_cam, *m.pair_follower, cam, follower, ps.u, ps.v);
    ps.ok = pair.valid() && profile_pair_rates(pair, m.tracking_gain, ps.u_rate, ps.v_rate) == PairStatus::converged;
    ps.drift = ps.ok ? (pair.jacobian.inverse() * pair.f).cwiseAbs().maxCoeff() : INFINITY;
  } else {
    assert(ws.pair_search && ws.pair_search_cam == m.pair_cam && "make_workspace(model) before evaluate()");
    double u = ws.u_warm, v = ws.v_warm;
    const long searches = ws.pair_search->global_searches;
    ps.ok = track_profile_pair(*m.pair_cam, *m.pair_follower, cam, follower, *ws.pair_search, u, v, pair);
    ws.tracking_resets += ws.pair_search->global_searches - searches;
    ps.u = u;
    ps.v = v;
  }
  const Eigen::Matrix2d to_cam = cam.rotation.transpose();
  ps.gap = pair.gap;
  ps.normal = to_cam * pair.normal_W;
  ps.follower_point = to_cam * pair.point_B_W;
  ps.point = m.pair_cam->at(ps.u);
  ps.orientation = m.pair_cam->outward_side();
  return ps;
}

PairSolution solve_pair(const Model& m, Workspace& ws, double t, const double* x) {
  if (m.pair_form == PairForm::general) return solve_general(m, ws, t, x);
  PairSolution ps;
  TrackedPair pair;
  if (m.tracking == Tracking::differential) {
    ps.u = x[*m.layout.u];
  } else {
    const double theta = cam_angle(m, t, x);
    Eigen::Vector2d a, b;
    element_in_cam_frame(m, x[0], theta, a, b);
    double u = ws.u_warm;
    const bool circle = m.reduction == ContactReduction::circle;
    bool ok = circle ? newton_track(m.profile(), a, u, pair, m.profile_offset)
                     : newton_track_line(m.profile(), a, b, u, pair);
    if (!ok) {
      ++ws.tracking_resets;
      ok = circle ? global_pair(m.profile(), a, theta, u, pair, m.profile_offset)
                  : global_line_pair(m.profile(), a, b, theta, u, pair);
    }
    ps.ok = ok;
    ps.u = u;
  }
  ps.point = m.profile().at(ps.u);
  const Eigen::Vector2d candidate(ps.point.dr.y(), -ps.point.dr.x());
  ps.orientation = candidate.dot(ps.point.r) >= 0.0 ? 1.0 : -1.0;
  return ps;
}

/// The mechanism at one state, in scalar S (double, or dual numbers for the Jacobian).
template <class S>
struct Core {
  S theta, omega_c, q, v, spin;
  S f, f_u;  ///< common-normal residual and its u-derivative
  S gap, gap_rate, delta, delta_rate, normal_force, slip, friction_force;
  S generalised_force, cam_torque, guide, pivot;
  S acceleration, spin_acceleration, u_rate, v_rate;
  DriveRates<S> drive;
  Vec2<S> force_world;
  S contact_offset;
};

/// Guide friction of a translating follower (μ_g |side load| against q̇) and
/// pivot friction of an arm (μ_p r_pin |reaction| against q̇), from the contact
/// force already in `o`.
template <class S>
void support_friction(const Model& m, Core<S>& o) {
  m.support.forces(o.v, o.force_world.x, o.normal_force, o.friction_force, o.guide, o.pivot);
}

/// Where the contact point X (world) lies across the follower's face, from its centre [m].
template <class S>
S offset_across_face(const FollowerGeometry& fg, const S& q, const Vec2<S>& X_world) {
  Vec2<S> origin, across;
  fg.face_frame(q, origin, across);
  return dot(X_world - origin, across);
}

/// The general pair form's contact normal n, contact point X, its rate per q̇
/// X_q and the gap's partials g_q, g_θ (cam frame), from the pair the general
/// tracker solved in double (no dual-number derivatives: exact_jacobian() is
/// false). At f = 0 the gap's partials at fixed (u, v) are those of the
/// follower's material point r_B (envelope theorem).
template <class S, class ToCam, class ToWorld>
void general_pair_partials(const FollowerGeometry& fg, const PairSolution& ps, double sigma, const ToCam& to_cam,
                           const ToWorld& to_world, Core<S>& o, Vec2<S>& n, Vec2<S>& X, Vec2<S>& X_q, S& g_q,
                           S& g_theta) {
  n = Vec2<S>(ps.normal);
  X = Vec2<S>(ps.follower_point);
  o.gap = S(ps.gap);
  o.f = S(0.0);
  o.f_u = S(-1.0);
  const Vec2<S> B_q = to_cam(fg.body_point_rate(to_world(X)));
  g_q = dot(n, B_q);
  g_theta = dot(n, (-sigma) * perp(X));
  if (fg.rolls()) {
    Vec2<S> centre, centre_q;
    fg.centre(o.q, centre, centre_q);
    X_q = to_cam(centre_q);
  } else {
    X_q = B_q;
  }
}

/// `train_force`: the follower train's generalised force on q (dynamics/follower_train.h).
template <class S>
void core(const Model& m, const Workspace& ws, double t, const S* x, const PairSolution& ps, const S& u,
          double train_force, Core<S>& o) {
  using std::abs;
  using std::cos;
  using std::sin;
  using std::sqrt;
  const double sigma = m.direction;
  const FollowerGeometry& fg = m.follower;
  o.q = x[0];
  o.v = x[1];
  o.spin = m.layout.spin ? x[*m.layout.spin] : S(0.0);
  if (m.drive.shaft()) {
    o.theta = x[*m.layout.cam_angle];
    o.omega_c = x[*m.layout.cam_speed];
  } else {
    o.theta = S(m.theta(t));
    o.omega_c = S(m.omega);
  }
  const S phi = sigma * o.theta;
  const S c = cos(phi), s = sin(phi);
  const S minus_s = -s;
  auto to_cam = [&](const Vec2<S>& w) { return rotate(w, c, minus_s); };
  auto to_world = [&](const Vec2<S>& w) { return rotate(w, c, s); };

  // The profile near the pair: first order in u − u₀ carries the derivatives.
  const S du = u - ps.u;
  const CurvePoint& cp = ps.point;
  const Vec2<S> r = Vec2<S>(cp.r) + du * Vec2<S>(cp.dr);
  const Vec2<S> r1 = Vec2<S>(cp.dr) + du * Vec2<S>(cp.d2r);
  const Vec2<S> r2 = Vec2<S>(cp.d2r) + du * Vec2<S>(cp.d3r);

  // Gap g(q, θ, u), its partials at fixed u, the common-normal residual f and
  // its partials; n is the normal of the contact force on the follower, X the
  // follower's contact point, X_q its rate per q̇ (cam frame).
  Vec2<S> n, X, X_q;
  S g_q, g_theta, f_q, f_theta;
  if (m.pair_form == PairForm::general) {
    general_pair_partials(fg, ps, sigma, to_cam, to_world, o, n, X, X_q, g_q, g_theta);
    f_q = f_theta = S(0.0);
  } else if (m.reduction == ContactReduction::circle) {
    Vec2<S> centre, centre_q;
    fg.centre(o.q, centre, centre_q);
    const Vec2<S> C = to_cam(centre), C_q = to_cam(centre_q), C_theta = (-sigma) * perp(C);
    const Vec2<S> d = C - r;
    o.f = dot(r1, d);
    o.f_u = dot(r2, d) - dot(r1, r1);
    f_q = dot(r1, C_q);
    f_theta = dot(r1, C_theta);
    n = (ps.orientation / sqrt(dot(r1, r1))) * Vec2<S>(r1.y, -r1.x);
    o.gap = dot(n, d) - m.profile_offset;
    g_q = dot(n, C_q);
    g_theta = dot(n, C_theta);
    X = C - fg.radius * n;
    // A roller takes the friction force at its axle (its torque goes to the spin).
    X_q = fg.rolls() ? C_q : to_cam(fg.body_point_rate(to_world(X)));
  } else {
    Vec2<S> p, mw, p_q, mw_q;
    fg.face(o.q, p, mw, p_q, mw_q);
    const Vec2<S> P = to_cam(p), M = to_cam(mw), P_q = to_cam(p_q), M_q = to_cam(mw_q);
    const Vec2<S> P_theta = (-sigma) * perp(P), M_theta = (-sigma) * perp(M);
    o.f = -dot(r1, M);
    o.f_u = -dot(r2, M);
    f_q = -dot(r1, M_q);
    f_theta = -dot(r1, M_theta);
    const Vec2<S> rp = r - P;
    o.gap = dot(M, rp);
    g_q = dot(M_q, rp) - dot(M, P_q);
    g_theta = dot(M_theta, rp) - dot(M, P_theta);
    n = -M;
    X = r;
    X_q = to_cam(fg.body_point_rate(to_world(X)));
  }
  const Vec2<S> X_theta = (-sigma) * perp(X);  // rate of a world-fixed point in the cam frame per θ̇
  const Vec2<S> tangent = perp(n);

  o.gap_rate = g_q * o.v + g_theta * o.omega_c;
  o.delta = -o.gap;
  o.delta_rate = -o.gap_rate;
  o.normal_force = m.contact.force_t(o.delta, o.delta_rate, ws.v0);
  o.slip = S(0.0);
  o.friction_force = S(0.0);
  if (m.friction.present) {
    o.slip = dot(tangent, X_q) * o.v + dot(tangent, X_theta) * o.omega_c;
    if (m.friction.spin) o.slip = o.slip - fg.radius * o.spin;
    o.friction_force = -(m.friction.law.coefficient_t(o.slip) * o.normal_force);
  }
  // Generalised forces by virtual power: F·(∂X/∂q) on the follower, F·(∂X/∂θ) on the cam.
  o.generalised_force = o.normal_force * g_q + o.friction_force * dot(tangent, X_q);
  o.cam_torque = o.normal_force * g_theta + o.friction_force * dot(tangent, X_theta);
  o.force_world = to_world(o.normal_force * n + o.friction_force * tangent);
  o.contact_offset = offset_across_face(fg, o.q, to_world(X));

  support_friction(m, o);
  // The follower's force elements, added in their order (dynamics/follower_forces.h).
  S force = o.generalised_force;
  m.forces.for_each([&](const auto& element) { force = force + element.force(o.q, o.v, m.mass); });
  if (m.train.present()) force = force + train_force;
  o.acceleration = (force + o.guide + o.pivot) / m.mass;
  o.spin_acceleration = m.friction.spin ? -(fg.radius * o.friction_force) / m.friction.roller_inertia : S(0.0);
  o.u_rate = m.layout.u ? (-m.tracking_gain * o.f - f_q * o.v - f_theta * o.omega_c) / o.f_u : S(0.0);
  o.v_rate = S(0.0);
  if (m.pair_form == PairForm::general) {
    o.u_rate = S(ps.u_rate);
    o.v_rate = S(ps.v_rate);
  }

  // The drive's rates (dynamics/shaft_drive.h), from the cam torque.
  m.drive.rates(m.layout, x, m.theta(t) + ws.motor_phase, m.omega, o.theta, o.omega_c, o.cam_torque, o.drive);
}

/// ẋ in the model's state layout from the rates of a Core (double or dual
/// numbers) or an Evaluation, which name them alike except the cam speed.
template <class S, class Rates>
void scatter_state_rates(const Model& m, const Rates& r, const S& cam_speed, S* x_dot) {
  x_dot[0] = r.v;
  x_dot[1] = r.acceleration;
  if (m.layout.u) x_dot[*m.layout.u] = r.u_rate;
  if (m.layout.v) x_dot[*m.layout.v] = r.v_rate;
  if (m.layout.spin) x_dot[*m.layout.spin] = r.spin_acceleration;
  if (m.layout.cam_angle) {
    x_dot[*m.layout.cam_angle] = cam_speed;
    x_dot[*m.layout.cam_speed] = r.drive.cam_acceleration;
  }
  if (m.layout.motor_angle) {
    x_dot[*m.layout.motor_angle] = r.drive.motor_speed;
    x_dot[*m.layout.motor_speed] = r.drive.motor_acceleration;
  }
}

}  // namespace

BodyMotion follower_motion(const FollowerGeometry& follower, double q, double q_dot) {
  if (follower.oscillating())
    return BodyMotion::make(follower.psi0 + follower.kappa * q, follower.pivot, follower.kappa * q_dot);
  return BodyMotion::make(0.0, Eigen::Vector2d(follower.offset, follower.y0 + q), 0.0, Eigen::Vector2d(0.0, q_dot));
}

Workspace make_workspace(const Model& model) {
  Workspace ws;
  prepare_workspace(model, ws);
  return ws;
}

void prepare_workspace(const Model& model, Workspace& ws) {
  // The per-run state of a fresh workspace.
  const Workspace fresh;
  ws.v0 = fresh.v0;
  ws.u_warm = fresh.u_warm;
  ws.tracking_resets = fresh.tracking_resets;
  ws.motor_phase = fresh.motor_phase;
  ws.v_warm = fresh.v_warm;
  prepare_train_workspace(model.train, ws.train);
  if (model.pair_form != PairForm::general) {
    ws.pair_search.reset();
    ws.pair_search_cam.reset();
    ws.pair_search_follower.reset();
    return;
  }
  if (!ws.pair_search || ws.pair_search_cam != model.pair_cam || ws.pair_search_follower != model.pair_follower) {
    ws.pair_search = std::make_shared<PairTrackerWorkspace>(*model.pair_cam, *model.pair_follower);
    ws.pair_search_cam = model.pair_cam;
    ws.pair_search_follower = model.pair_follower;
  }
  // The search samples depend on the profiles only; its counters restart.
  ws.pair_search->global_searches = 0;
  ws.pair_search->newton_failures = 0;
  // Follower parameter guess: the face centre, or the roller point facing the
  // cam centre at the lowest position (body frame).
  const FollowerGeometry& fg = model.follower;
  if (fg.circle()) {
    Vec2<double> c, c_q;
    fg.centre(0.0, c, c_q);
    const double body_angle = fg.oscillating() ? fg.psi0 : 0.0;
    const Eigen::Vector2d towards_cam = -to_eigen(c);
    ws.v_warm = std::atan2(towards_cam.y(), towards_cam.x()) - body_angle;
  }
}

void evaluate(const Model& model, Workspace& ws, double t, const double* state, Evaluation& ev) {
  const PairSolution ps = solve_pair(model, ws, t, state);
  if (model.train.present()) evaluate_train(model.train, ws.train, cam_angle(model, t, state), state, ev.train);
  Core<double> o;
  core(model, ws, t, state, ps, ps.u, ev.train.follower_force, o);

  ev.theta = o.theta;
  ev.cam_speed = o.omega_c;
  ev.y = o.q;
  ev.v = o.v;
  ev.spin = o.spin;
  ev.pair.u = ps.u;
  ev.pair.gap = o.gap;
  ev.pair.f = o.f;
  ev.pair.f_u = o.f_u;
  ev.pair.point = ps.point.r;
  ev.pair.tangent_u = ps.point.dr;
  ev.pair.normal = ps.orientation * Eigen::Vector2d(ps.point.dr.y(), -ps.point.dr.x()).normalized();
  ev.pair_v = ps.v;
  if (model.pair_form == PairForm::general) {
    ev.tracking_ok = ps.ok;
    ev.pair_drift = ps.drift;
  } else {
    ev.tracking_ok = model.tracking == Tracking::differential ? o.f_u < 0.0 : ps.ok;
    ev.pair_drift = ev.tracking_ok ? std::abs(o.f / o.f_u) : INFINITY;
  }
  ev.gap = o.gap;
  ev.gap_rate = o.gap_rate;
  ev.delta = o.delta;
  ev.delta_rate = o.delta_rate;
  ev.normal_force = o.normal_force;
  ev.friction_force = o.friction_force;
  ev.slip = o.slip;
  ev.contact_offset = o.contact_offset;
  ev.force_world = to_eigen(o.force_world);
  ev.generalised_force = o.generalised_force;
  ev.cam_torque = o.cam_torque;
  ev.guide_friction = o.guide;
  ev.pivot_friction = o.pivot;
  ev.acceleration = o.acceleration;
  ev.spin_acceleration = o.spin_acceleration;
  ev.u_rate = ev.tracking_ok ? o.u_rate : 0.0;
  ev.v_rate = ev.tracking_ok ? o.v_rate : 0.0;
  ev.drive = o.drive;

  // Powers (docs/model.md §7): what the drive delivers, what dampers, contact
  // hysteresis and friction dissipate.
  ev.power_drive = model.drive.drive_power(o.drive, o.cam_torque, o.omega_c);
  ev.power_damper = model.forces.power(o.v) + model.drive.damper_power(o.drive.motor_speed, o.omega_c);
  ev.power_hysteresis = o.delta > 0.0 ? (o.normal_force - model.contact.elastic_force(o.delta)) * o.delta_rate : 0.0;
  ev.power_friction = -o.friction_force * o.slip - (o.guide + o.pivot) * o.v;
  ev.power_external = 0.0;
  if (model.train.present()) {
    ev.power_damper += ev.train.power_damper;
    ev.power_hysteresis += ev.train.power_hysteresis;
    ev.power_external = ev.train.power_external;
  }
}

void state_jacobian(const Model& model, Workspace& ws, double t, const double* state, double* jacobian) {
  assert(model.exact_jacobian());
  // The core states (follower, pair, spin, drive) by dual numbers; the
  // train's, which are linear chains of one-dimensional elements, by their
  // elements' partials (dynamics/follower_train.h).
  const int n = model.layout.size, nc = model.layout.core_size;
  const PairSolution ps = solve_pair(model, ws, t, state);
  double train_force = 0.0;
  if (model.train.present()) {
    TrainEvaluation& te = ws.train_scratch;
    evaluate_train(model.train, ws.train, cam_angle(model, t, state), state, te);
    train_force = te.follower_force;
  }
  Jet x[StateLayout::kCore];
  for (int i = 0; i < nc; ++i) x[i] = Jet::variable(state[i], i);
  Jet u = model.layout.u ? x[*model.layout.u] : Jet(ps.u);
  Core<Jet> o;
  if (!model.layout.u) {
    // Newton: u(x) solves f(x, u) = 0, so ∂u/∂x = −(∂f/∂x) / f_u.
    core(model, ws, t, x, ps, u, train_force, o);
    for (int i = 0; i < nc; ++i) u.d[i] = -o.f.d[i] / o.f_u.v;
  }
  core(model, ws, t, x, ps, u, train_force, o);
  Jet x_dot[StateLayout::kCore];
  scatter_state_rates(model, o, o.omega_c, x_dot);
  if (nc < n) std::fill(jacobian, jacobian + static_cast<std::size_t>(n) * static_cast<std::size_t>(n), 0.0);
  for (int j = 0; j < nc; ++j)
    for (int i = 0; i < nc; ++i) jacobian[i + n * j] = x_dot[i].d[j];
  if (model.train.present()) {
    const int cam_angle_state = model.drive.shaft() ? *model.layout.cam_angle : -1;
    add_train_jacobian(model.train, ws.train, cam_angle(model, t, state), cam_angle_state, state, n, jacobian);
  }
}

void state_derivative(const Model& model, const Evaluation& ev, double* state_dot) {
  scatter_state_rates(model, ev, ev.cam_speed, state_dot);
  if (model.train.has_coordinates()) train_state_derivative(model.train, ev.train, state_dot);
}

void quadrature_derivative(const Evaluation& ev, double* q_dot) {
  q_dot[quadrature::drive_work] = ev.power_drive;
  q_dot[quadrature::damper_work] = ev.power_damper;
  q_dot[quadrature::hysteresis_work] = ev.power_hysteresis;
  q_dot[quadrature::friction_work] = ev.power_friction;
  q_dot[quadrature::separation] = ev.gap > 0.0 ? ev.gap : 0.0;  // smooth within a step: g = 0 is a root
  q_dot[quadrature::external_work] = ev.power_external;
}

void root_functions(const Model& model, const Workspace& ws, const Evaluation& ev, double* g) {
  for (int r = 0; r < model.root_count(); ++r) {
    const RootSlot slot = model.root_slot(r);
    switch (slot.role) {
      case RootRole::contact_gap:
        g[r] = ev.gap;
        break;
      case RootRole::contact_clamp:
        g[r] = model.contact.clamp_switch(ev.delta, ev.delta_rate, ws.v0);
        break;
      case RootRole::train_gap:
        g[r] = ev.train.gap[static_cast<std::size_t>(slot.index)];
        break;
    }
  }
}

EnergyTerms energy_terms(const Model& model, const Evaluation& ev) {
  EnergyTerms e;
  e.kinetic = 0.5 * model.mass * ev.v * ev.v + model.friction.kinetic_energy(ev.spin);
  const StoredEnergy stored = model.forces.energy(ev.y, model.mass);
  e.spring = stored.spring;
  e.gravity = stored.gravity;
  e.contact = model.contact.elastic_energy(ev.delta);
  model.drive.add_energy(ev.cam_speed, ev.drive.motor_speed, ev.drive.twist, e.kinetic, e.spring);
  if (model.train.present()) {
    e.kinetic += ev.train.kinetic;
    e.spring += ev.train.potential;
  }
  return e;
}

}  // namespace camdyn
