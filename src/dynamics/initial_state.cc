#include "dynamics/initial_state.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/errors.h"

namespace camdyn {

// Initial state: given, or on the law at quasi-static equilibrium (the contact
// force supplies exactly the law's acceleration); the pair by Newton from the
// cam angle (global search if that fails); a roller spinning without slip; a
// shaft twisted to carry the initial cam torque.
namespace {

/// The follower's seat position [m | rad], or −inf without a seat.
double follower_seat_position(const Model& model) {
  const FollowerTrain& train = model.train;
  if (train.bodies.empty() || train.bodies[0].seat < 0) return -std::numeric_limits<double>::infinity();
  return train.elements[static_cast<std::size_t>(train.bodies[0].seat)].offset;
}

}  // namespace

RunFailure initial_state(const SceneConfig& scene, const Model& model, Workspace& ws, double* y) {
  const InitialConfig& init = scene.mechanism.follower.initial;
  const double theta = model.theta(0.0);
  const LawSample law = model.law->eval(theta);
  // The set-up probe: Newton tracking, no spin, the cam at constant speed.
  Model probe = model;
  probe.tracking = Tracking::newton;
  probe.friction.present = model.friction.present && !model.friction.spin;
  probe.friction.spin = false;
  probe.drive = ShaftDrive{};
  probe.layout = StateLayout::follower_only(model.follower.oscillating());
  Evaluation ev;
  RunState s{};
  ws.v0 = model.contact.reference_velocity;
  const double u_guess = model.pair_guess(theta);
  ws.u_warm = u_guess;
  ws.motor_phase = 0.0;

  if (init.position) {
    s[0] = *init.position;
    s[1] = init.velocity;
  } else {
    s[1] = model.omega * law.ds + init.velocity;
    const double target = model.omega * model.omega * law.d2s;
    // The train (docs/model.md §12) at rest in static equilibrium on the follower.
    auto excess = [&](double y_trial) {
      s[0] = y_trial;
      ws.u_warm = u_guess;
      if (model.train.has_coordinates()) train_static_state(model.train, ws.train, model.theta(0.0), s.data());
      evaluate(probe, ws, 0.0, s.data(), ev);
      return ev.acceleration - target;
    };
    double hi = law.s;  // touching: no contact force
    if (excess(hi) >= 0.0) {
      s[0] = hi;
      // A seat above the cam holds the follower off it: the equilibrium on the seat.
      if (const double seat = follower_seat_position(model); seat > hi && excess(seat) < 0.0) {
        double lo = hi, up = seat;
        for (int it = 0; it < 200 && up - lo > 1e-15; ++it) {
          const double mid = 0.5 * (lo + up);
          (excess(mid) < 0.0 ? up : lo) = mid;
        }
        s[0] = 0.5 * (lo + up);
      }
    } else {
      // Penetrations far below the base radius (metres or, for an arm, radians times its length).
      const double limit = model.follower.oscillating() ? 0.1 * model.follower.base_radius / model.follower.arm_length
                                                        : 0.1 * model.follower.base_radius;
      double span = 1e-9;
      while (excess(hi - span) < 0.0) {
        span *= 4.0;
        if (span > limit)
          throw InputError("", "mechanism.follower.initial.position",
                           "no static equilibrium in contact: the contact cannot carry the spring load");
      }
      double lo = hi - span;
      for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
        const double mid = 0.5 * (lo + hi);
        (excess(mid) < 0.0 ? hi : lo) = mid;
      }
      s[0] = 0.5 * (lo + hi);
    }
  }
  if (model.train.has_coordinates()) train_static_state(model.train, ws.train, model.theta(0.0), s.data());

  ws.u_warm = u_guess;
  const long resets = ws.tracking_resets;
  evaluate(probe, ws, 0.0, s.data(), ev);
  ws.tracking_resets = resets;  // the set-up search is not a loss of tracking
  if (!ev.tracking_ok)
    return {Termination::no_initial_contact, "could not find the initial contact pair " + where(model, 0.0)};
  ws.u_warm = ev.pair.u;
  ws.v_warm = ev.pair_v;
  std::fill(y, y + model.layout.size, 0.0);
  std::copy(s.begin() + model.layout.core_size, s.begin() + model.layout.size, y + model.layout.core_size);
  y[0] = s[0];
  y[1] = s[1];
  if (model.layout.u) y[*model.layout.u] = ev.pair.u;
  if (model.layout.v) y[*model.layout.v] = ev.pair_v;
  if (model.layout.cam_angle) {
    y[*model.layout.cam_angle] = theta;
    y[*model.layout.cam_speed] = model.omega;
  }
  if (model.layout.motor_angle) {
    y[*model.layout.motor_angle] = theta;
    y[*model.layout.motor_speed] = model.omega;
  }
  if (model.layout.spin) {
    // Rolling without slip at the start: slip = slip(Ω = 0) − r_r Ω = 0.
    evaluate(model, ws, 0.0, y, ev);
    y[*model.layout.spin] = ev.slip / model.follower.radius;
  }
  if (model.drive.shaft()) {
    // Twist the shaft so that it carries the contact torque on the cam.
    evaluate(model, ws, 0.0, y, ev);
    const double twist = -ev.cam_torque / model.drive.stiffness;
    if (model.layout.motor_angle)
      y[*model.layout.motor_angle] += twist;
    else
      ws.motor_phase = twist;
  }
  return {};
}

// A given start (SimulationOptions::start): every state as given except the
// pair parameters, which warm-started Newton (global search if that fails)
// finds from the others at t = 0, as the drift projection does.
RunFailure given_state(const Model& model, Workspace& ws, const StartState& start, double* y) {
  if (static_cast<int>(start.y.size()) != model.layout.size)
    throw std::logic_error("simulate: a start state of " + std::to_string(start.y.size()) + " values for a model of " +
                           std::to_string(model.layout.size) + " states");
  std::copy(start.y.begin(), start.y.end(), y);
  ws.v0 = std::max(start.approach_speed, model.contact.reference_velocity);
  ws.motor_phase = start.motor_phase;
  ws.u_warm = model.pair_guess(model.theta(0.0));
  Model newton_model = model;
  newton_model.tracking = Tracking::newton;
  Evaluation ev;
  const long resets = ws.tracking_resets;
  evaluate(newton_model, ws, 0.0, y, ev);
  ws.tracking_resets = resets;  // the set-up search is not a loss of tracking
  if (!ev.tracking_ok)
    return {Termination::no_initial_contact, "could not find the contact pair of the start state " + where(model, 0.0)};
  ws.u_warm = ev.pair.u;
  ws.v_warm = ev.pair_v;
  if (model.layout.u) y[*model.layout.u] = ev.pair.u;
  if (model.layout.v) y[*model.layout.v] = ev.pair_v;
  return {};
}

}  // namespace camdyn
