#include "dynamics/simulation.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "common/errors.h"
#include "integrate/integrator.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr int kMaxState = Model::kMaxState;
constexpr int kSamplesPerStep = 4;     // dense samples per internal step for the metrics

// The scene as an OdeSystem: the model's evaluation behind SUNDIALS' callbacks.
class SceneOde final : public OdeSystem {
 public:
  SceneOde(const Model& model, Workspace& ws) : model_(model), ws_(ws) {}
  int size() const override { return model_.state_size; }
  int quadrature_size() const override { return Model::kQuadratures; }
  int root_count() const override { return model_.root_count(); }
  int rhs(double t, const double* y, double* y_dot) override {
    evaluate(model_, ws_, t, y, ev_);
    if (!ev_.tracking_ok) return 1;  // recoverable: the integrator retries a smaller step
    state_derivative(model_, ev_, y_dot);
    return 0;
  }
  int quadrature(double t, const double* y, double* q_dot) override {
    evaluate(model_, ws_, t, y, ev_);
    quadrature_derivative(ev_, q_dot);
    return 0;
  }
  int roots(double t, const double* y, double* g) override {
    evaluate(model_, ws_, t, y, ev_);
    root_functions(model_, ws_, ev_, g);
    return 0;
  }
  bool has_jacobian() const override { return model_.exact_jacobian(); }
  int jacobian(double t, const double* y, double* J) override {
    state_jacobian(model_, ws_, t, y, J);
    return 0;
  }

 private:
  const Model& model_;
  Workspace& ws_;
  Evaluation ev_;
};

std::string where(const Model& model, double t) {
  std::ostringstream s;
  s << "at t = " << t << " s, cam angle " << std::fmod(model.theta(t) * kRadToDeg, 360.0) << " deg";
  return s.str();
}

// Initial state: given, or on the law at quasi-static equilibrium (the contact
// force supplies exactly the law's acceleration); the pair by Newton from the
// cam angle (global search if that fails); a roller spinning without slip; a
// shaft twisted to carry the initial cam torque.
void initial_state(const SceneConfig& scene, const Model& model, Workspace& ws, double* y) {
  const InitialConfig& init = scene.mechanism.follower.initial;
  const double theta = model.theta(0.0);
  const LawSample law = model.law->eval(theta);
  // The set-up probe: Newton tracking, no spin, the cam at constant speed.
  Model probe = model;
  probe.tracking = Tracking::newton;
  probe.index_u = -1;
  probe.index_v = -1;
  probe.contact_friction = model.contact_friction && !model.has_spin;
  probe.has_spin = false;
  probe.index_spin = -1;
  probe.drive = Drive::constant_speed;
  probe.index_cam_angle = probe.index_cam_speed = probe.index_motor_angle = probe.index_motor_speed = -1;
  probe.state_size = 2;
  Evaluation ev;
  std::array<double, kMaxState> s{};
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
    auto excess = [&](double y_trial) {
      s[0] = y_trial;
      ws.u_warm = u_guess;
      evaluate(probe, ws, 0.0, s.data(), ev);
      return ev.acceleration - target;
    };
    double hi = law.s;  // touching: no contact force
    if (excess(hi) >= 0.0) {
      s[0] = hi;
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

  ws.u_warm = u_guess;
  const long resets = ws.tracking_resets;
  evaluate(probe, ws, 0.0, s.data(), ev);
  ws.tracking_resets = resets;  // the set-up search is not a loss of tracking
  if (!ev.tracking_ok) throw NumericalError("could not find the initial contact pair " + where(model, 0.0));
  ws.u_warm = ev.pair.u;
  ws.v_warm = ev.pair_v;
  std::fill(y, y + model.state_size, 0.0);
  y[0] = s[0];
  y[1] = s[1];
  if (model.index_u >= 0) y[model.index_u] = ev.pair.u;
  if (model.index_v >= 0) y[model.index_v] = ev.pair_v;
  if (model.index_cam_angle >= 0) {
    y[model.index_cam_angle] = theta;
    y[model.index_cam_speed] = model.omega;
  }
  if (model.index_motor_angle >= 0) {
    y[model.index_motor_angle] = theta;
    y[model.index_motor_speed] = model.omega;
  }
  if (model.index_spin >= 0) {
    // Rolling without slip at the start: slip = slip(Ω = 0) − r_r Ω = 0.
    evaluate(model, ws, 0.0, y, ev);
    y[model.index_spin] = ev.slip / model.follower.radius;
  }
  if (model.drive == Drive::shaft) {
    // Twist the shaft so that it carries the contact torque on the cam.
    evaluate(model, ws, 0.0, y, ev);
    const double twist = -ev.cam_torque / model.shaft_stiffness;
    if (model.index_motor_angle >= 0) y[model.index_motor_angle] += twist;
    else ws.motor_phase = twist;
  }
}

struct RunPlan {
  double t_end = 0.0, t_eval = 0.0, output_dt = 0.0, max_step = 0.0;
};

RunPlan plan(const SceneConfig& scene, const Model& model) {
  const SimulationConfig& sim = scene.simulation;
  RunPlan p;
  const double period = model.omega > 0.0 ? kTwoPi / model.omega : 0.0;
  if (sim.duration) {
    p.t_end = *sim.duration;
    const double discard = sim.cycles ? 0.0 : scene.simulation.discard_cycles * period;
    p.t_eval = discard < p.t_end ? discard : 0.0;
  } else {
    const double cycles = sim.cycles.value_or(4.0);
    p.t_end = cycles * period;
    p.t_eval = sim.discard_cycles * period;
  }
  if (sim.output_step) {
    p.output_dt = *sim.output_step;
  } else {
    p.output_dt = model.omega > 0.0 ? sim.output_step_deg.value_or(0.5) / kRadToDeg / model.omega : p.t_end / 1000.0;
  }
  // Steps never longer than 2° of cam rotation, so that no contact episode fits inside one step.
  p.max_step = scene.integrator.max_step.value_or(model.omega > 0.0 ? 2.0 / kRadToDeg / model.omega : p.t_end / 200.0);
  return p;
}

}  // namespace

std::vector<std::string> TimeSeries::column_names() {
  return {"time",   "cam_angle_deg", "follower_position", "follower_velocity", "follower_acceleration",
          "kinematic_position", "gap", "contact_force", "friction_force", "energy_residual",
          "contact_offset", "cam_speed_rpm"};
}

std::vector<const std::vector<double>*> TimeSeries::columns() const {
  return {&time, &cam_angle_deg, &follower_position, &follower_velocity, &follower_acceleration,
          &kinematic_position, &gap, &contact_force, &friction_force, &energy_residual,
          &contact_offset, &cam_speed_rpm};
}

SimulationResult simulate(const SceneConfig& scene, const Model& model, Workspace& ws,
                          const SimulationOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  const IntegratorConfig& ic = scene.integrator;
  const RunPlan p = plan(scene, model);
  SimulationResult result;
  result.evaluated_from = p.t_eval;
  result.end_time = p.t_end;
  ws.tracking_resets = 0;
  prepare_workspace(model, ws);

  std::array<double, kMaxState> y{};
  initial_state(scene, model, ws, y.data());
  std::array<double, Model::kQuadratures> q{};

  SceneOde ode(model, ws);
  IntegratorOptions io;
  io.method = ic.method;
  io.rtol = ic.rtol;
  io.atol = ic.atol;
  io.quadrature_atol = ic.atol;
  io.max_step = p.max_step;
  io.fixed_step = ic.step.value_or(0.0);
  io.analytic_jacobian = ic.jacobian == JacobianSource::analytic;
  const std::unique_ptr<Integrator> integrator_ptr = make_integrator(ode, io, 0.0, y.data(), q.data());
  Integrator& integrator = *integrator_ptr;

  Metrics& m = result.metrics;
  m.min_contact_force = std::numeric_limits<double>::infinity();
  double separated_time = 0.0;
  double energy0 = 0.0, energy_scale = 0.0, energy_max_dev = 0.0;
  bool energy_initialised = false;
  Evaluation ev;
  std::array<double, kMaxState> ys{};
  std::array<double, Model::kQuadratures> qs{};

  // Evaluates the model at a dense-output time and folds it into the metrics;
  // returns the energy deviation E(t) − E(0) [J].
  // Before the first step there is no dense output yet: the initial values are used.
  bool stepped = false;
  auto observe = [&](double t) -> double {
    if (stepped) {
      integrator.dense(t, ys.data());
      integrator.dense_quadrature(t, qs.data());
    } else {
      ys = y;
      qs = q;
    }
    double u_keep = ws.u_warm;
    evaluate(model, ws, t, ys.data(), ev);
    ws.u_warm = u_keep;
    const EnergyTerms e = energy_terms(model, ev);
    const double energy = e.kinetic + e.spring + e.gravity + e.contact - qs[0] + qs[1] + qs[2] + qs[3];
    if (!energy_initialised) {
      energy0 = energy;
      energy_initialised = true;
    }
    energy_scale = std::max(energy_scale, e.kinetic + e.spring + std::abs(qs[0]));
    energy_max_dev = std::max(energy_max_dev, std::abs(energy - energy0));
    if (t >= p.t_eval) {
      m.max_separation_gap = std::max(m.max_separation_gap, ev.gap);
      m.peak_contact_force = std::max(m.peak_contact_force, ev.normal_force);
      m.min_contact_force = std::min(m.min_contact_force, ev.normal_force);
      m.max_penetration = std::max(m.max_penetration, ev.delta);
      m.max_kinematic_error = std::max(m.max_kinematic_error, std::abs(ev.y - model.law->eval(ev.theta).s));
    }
    return energy - energy0;
  };

  TimeSeries& ts = result.series;
  std::vector<double> energy_deviation, sample_energy_deviation;
  auto push_row = [&](TimeSeries& series, double t) {
    series.time.push_back(t);
    series.cam_angle_deg.push_back(ev.theta * kRadToDeg);
    series.follower_position.push_back(ev.y);
    series.follower_velocity.push_back(ev.v);
    series.follower_acceleration.push_back(ev.acceleration);
    series.kinematic_position.push_back(model.law->eval(ev.theta).s);
    series.gap.push_back(ev.gap);
    series.contact_force.push_back(ev.normal_force);
    series.friction_force.push_back(ev.friction_force);
    series.contact_offset.push_back(ev.contact_offset);
    series.cam_speed_rpm.push_back(ev.cam_speed * 60.0 / kTwoPi);
  };
  long next_output = 0;
  size_t next_sample = 0;
  double separation_integral_at_eval = 0.0;
  bool eval_start_seen = p.t_eval <= 0.0;
  auto record_outputs_until = [&](double t_hi) {
    for (;; ++next_output) {
      const double t_nominal = static_cast<double>(next_output) * p.output_dt;
      const double t_out = std::min(t_nominal, p.t_end);
      if (t_out > t_hi * (1.0 + 1e-14) + 1e-300) break;
      if (t_nominal > p.t_end * (1.0 + 1e-12)) break;
      const double de = observe(t_out);
      if (!options.record_series) continue;
      push_row(ts, t_out);
      energy_deviation.push_back(de);
    }
    for (; next_sample < options.sample_times.size() && options.sample_times[next_sample] <= t_hi; ++next_sample) {
      const double t_sample = options.sample_times[next_sample];
      sample_energy_deviation.push_back(observe(t_sample));
      push_row(result.samples, t_sample);
    }
    if (!eval_start_seen && p.t_eval <= t_hi) {
      observe(p.t_eval);
      separation_integral_at_eval = qs[4];
      eval_start_seen = true;
    }
  };

  observe(0.0);
  record_outputs_until(0.0);
  bool separated = ev.gap > 0.0;
  const long step_budget = ic.max_steps;
  const int roots = model.root_count();
  std::array<int, 2> root_dirs{};
  double last_progress = 0.0;
  const double projection_tolerance = std::max(1e-9, 10.0 * ic.rtol);  // [rad]

  while (integrator.time() < p.t_end) {
    Integrator::Result result_kind;
    try {
      result_kind = integrator.step(p.t_end);
    } catch (const NumericalError& e) {
      throw NumericalError(std::string(e.what()) + " (integrating " + where(model, integrator.time()) + ")");
    }
    stepped = true;
    const double t = integrator.time();
    const double t0 = integrator.last_step_start();

    // Metrics from dense samples over the step; the gap keeps its sign inside
    // a step (its zeros are located as roots), so the midpoint decides separation.
    for (int j = 1; j <= kSamplesPerStep; ++j) observe(t0 + (t - t0) * j / kSamplesPerStep);
    const double t_mid = 0.5 * (t0 + t);
    integrator.dense(t_mid, ys.data());
    evaluate(model, ws, t_mid, ys.data(), ev);
    if (ev.gap > 0.0) separated_time += std::max(0.0, t - std::max(t0, p.t_eval));
    record_outputs_until(t);

    const double* state = integrator.state();
    std::copy(state, state + model.state_size, y.begin());
    evaluate(model, ws, t, y.data(), ev);
    if (model.tracking == Tracking::newton) {
      ws.u_warm = ev.pair.u;
      ws.v_warm = ev.pair_v;
    }
    bool restart = false;

    if (result_kind == Integrator::Result::root) {
      integrator.root_info(root_dirs.data());
      ++result.solver.events;
      if (root_dirs[0] < 0) {  // gap closing: contact onset
        const double approach = -ev.gap_rate;
        ws.v0 = std::max(approach, model.contact.reference_velocity);
        ContactEvent event{t, ev.theta * kRadToDeg, true, approach, separated};
        if (separated && t >= p.t_eval) {
          ++m.impact_count;
          m.max_impact_velocity = std::max(m.max_impact_velocity, approach);
        }
        result.events.push_back(event);
        separated = false;
        restart = true;
      } else if (root_dirs[0] > 0) {  // gap opening: separation
        result.events.push_back({t, ev.theta * kRadToDeg, false, ev.gap_rate, false});
        separated = true;
        restart = true;
      }
      if (roots > 1 && root_dirs[1] != 0 && ev.delta > 0.0) restart = true;  // force clamp switches
    }

    // Differential tracking: remove drift of the common-normal condition, or
    // re-initialise the pair when it is lost.
    if (model.index_u >= 0) {
      if (ev.pair_drift > projection_tolerance) {
        // Project u back onto f = 0 by warm-started Newton (global search if that fails).
        Model newton_model = model;
        newton_model.tracking = Tracking::newton;
        Evaluation projected;
        ws.u_warm = y[model.index_u];
        if (model.index_v >= 0) ws.v_warm = y[model.index_v];
        const long resets_before = ws.tracking_resets;
        evaluate(newton_model, ws, t, y.data(), projected);
        if (!projected.tracking_ok) throw NumericalError("contact pair tracking lost " + where(model, t));
        if (ws.tracking_resets == resets_before) ++result.solver.projections;
        y[model.index_u] = projected.pair.u;
        if (model.index_v >= 0) y[model.index_v] = projected.pair_v;
        restart = true;
      }
    }

    if (restart) {
      integrator.dense_quadrature(t, q.data());
      integrator.reinit(t, y.data(), q.data());
    }

    // A penetration beyond half the roller radius (a tenth of the base radius
    // for a flat face) means the contact is far too soft for its load: the
    // compliant-contact model no longer describes it.
    if (ev.delta > model.penetration_limit)
      throw NumericalError("contact penetration " + std::to_string(ev.delta) + " m exceeds " +
                           std::to_string(model.penetration_limit) +
                           " m (the contact stiffness is far too low for the load) " + where(model, t));
    // A flat face whose contact point runs off its edge: the design check
    // (check_cam) passed on the law, so the dynamics drove it there.
    if (model.reduction == ContactReduction::line && ev.delta > 0.0 &&
        std::abs(ev.contact_offset) > 0.5 * model.follower.face_width)
      throw NumericalError("the contact point left the flat face (" + std::to_string(ev.contact_offset) +
                           " m from its centre, face_width " + std::to_string(model.follower.face_width) + " m) " +
                           where(model, t));

    const SolverCounters c = integrator.counters();
    if (c.steps > step_budget)
      throw NumericalError("step budget of " + std::to_string(step_budget) + " steps (integrator.max_steps) exceeded " +
                           where(model, t));
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (wall > ic.max_wall_time_s)
      throw NumericalError("wall-time budget of " + std::to_string(ic.max_wall_time_s) +
                           " s (integrator.max_wall_time_s) exceeded " + where(model, t));
    if (options.progress && wall - last_progress > 0.25) {
      last_progress = wall;
      options.progress(t / p.t_end);
    }
    if (result_kind == Integrator::Result::stop) break;
  }
  record_outputs_until(p.t_end);

  const double evaluated = p.t_end - p.t_eval;
  m.separation_fraction = evaluated > 0.0 ? separated_time / evaluated : 0.0;
  if (!std::isfinite(m.min_contact_force)) m.min_contact_force = 0.0;
  m.energy_residual = energy_scale > 0.0 ? energy_max_dev / energy_scale : 0.0;
  result.error.energy_residual = m.energy_residual;
  m.max_pressure_angle_deg = model.geometry.max_pressure_angle_deg;
  m.min_radius_of_curvature = model.geometry.min_radius_of_curvature;
  m.jump_speed_rpm = jump_speed_rpm(model);
  for (double de : energy_deviation) ts.energy_residual.push_back(energy_scale > 0.0 ? de / energy_scale : 0.0);
  for (double de : sample_energy_deviation)
    result.samples.energy_residual.push_back(energy_scale > 0.0 ? de / energy_scale : 0.0);
  integrator.dense_quadrature(integrator.time(), q.data());
  m.separation_integral = q[4] - separation_integral_at_eval;

  result.solver.method = to_string(ic.method);
  result.solver.rtol = ic.rtol;
  result.solver.atol = ic.atol;
  result.solver.counters = integrator.counters();
  result.solver.tracking_resets = ws.tracking_resets;
  result.solver.run_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (options.progress) options.progress(1.0);
  return result;
}

void estimate_error(const SceneConfig& scene, const Model& model, SimulationResult& result) {
  if (scene.integrator.error_estimate != ErrorEstimateMethod::richardson) return;
  SceneConfig tight = scene;
  if (scene.integrator.method == IntegrationMethod::rk4) {
    tight.integrator.step = scene.integrator.step.value_or(0.0) / std::pow(100.0, 0.25);
  } else {
    tight.integrator.rtol = scene.integrator.rtol / 100.0;
    tight.integrator.atol = scene.integrator.atol / 100.0;
  }
  Workspace ws;
  const SimulationResult reference = simulate(tight, model, ws);
  ErrorEstimate& e = result.error;
  e.richardson = true;
  e.position = 0.0;
  const TimeSeries& a = result.series;
  const TimeSeries& b = reference.series;
  for (size_t i = 0; i < std::min(a.time.size(), b.time.size()); ++i)
    if (a.time[i] >= result.evaluated_from)
      e.position = std::max(e.position, std::abs(a.follower_position[i] - b.follower_position[i]));
  const double f_ref = reference.metrics.peak_contact_force;
  e.peak_contact_force = f_ref > 0.0 ? std::abs(result.metrics.peak_contact_force / f_ref - 1.0) : 0.0;
  e.tight_run_time_s = reference.solver.run_time_s;
}

SimulationResult simulate_scene(const SceneConfig& scene, const std::string& file, const SimulationOptions& options) {
  const Model model = build_model(scene, file);
  Workspace ws;
  SimulationResult result = simulate(scene, model, ws, options);
  estimate_error(scene, model, result);
  return result;
}

}  // namespace camdyn
