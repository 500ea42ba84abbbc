#include "dynamics/simulation.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/free_flight.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/step_extremes.h"
#include "dynamics/step_quadrature.h"
#include "geometry/check_text.h"
#include "integrate/integrator.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr int kMaxState = StateLayout::kMax;

using State = std::array<double, kMaxState>;
using Quadratures = std::array<double, Model::kQuadratures>;
using Clock = std::chrono::steady_clock;

// The quadratures a model reports (docs/model.md §7; Quadratures holds all of
// them, by index): the drive's work only where the cam turns or a motor
// drives it, the damper's only with a damper, the contact hysteresis only for
// a dissipative law, the friction work only with friction, the separation
// integral always. The others have a zero integrand.
bool quadrature_reported(const Model& m, int i) {
  switch (i) {
    case 0:
      return m.omega != 0.0 || m.drive == Drive::shaft;
    case 1:
      return m.forces.damper.present() || (m.drive == Drive::shaft && m.shaft_damping > 0.0);
    case 2:
      return force_form(m.contact.model) != ForceForm::elastic;
    case 3:
      return m.contact_friction || m.has_guide_friction || m.has_pivot_friction;
    default:
      return true;
  }
}

// The quadratures' integrand at an evaluation.
Quadratures integrand(const Evaluation& ev) {
  Quadratures f;
  quadrature_derivative(ev, f.data());
  return f;
}

// The scene as an OdeSystem: the model's evaluation behind SUNDIALS' callbacks.
// After each step CVODE asks for the roots at the state it accepted, and the
// loop evaluates there once more: evaluated() reuses the
// last evaluation when its point is the same to the bit. Only where an
// evaluation is a function of (t, y) and the contact episode's approach speed
// alone: Newton tracking also depends on its warm start, so it always solves.
class SceneOde final : public OdeSystem {
 public:
  SceneOde(const Model& model, Workspace& ws) : model_(model), ws_(ws), reuse_(model.tracking != Tracking::newton) {}
  int size() const override { return model_.layout.size; }
  int root_count() const override { return model_.root_count(); }
  int rhs(double t, const double* y, double* y_dot) override {
    const Evaluation& ev = evaluated(t, y);
    if (!ev.tracking_ok) return 1;  // recoverable: the integrator retries a smaller step
    state_derivative(model_, ev, y_dot);
    return 0;
  }
  int roots(double t, const double* y, double* g) override {
    root_functions(model_, ws_, evaluated(t, y), g);
    return 0;
  }
  bool has_jacobian() const override { return model_.exact_jacobian(); }
  int jacobian(double t, const double* y, double* J) override {
    state_jacobian(model_, ws_, t, y, J);
    return 0;
  }

  // The model evaluated at (t, y).
  const Evaluation& evaluated(double t, const double* y) {
    const std::size_t n = static_cast<std::size_t>(model_.layout.size);
    const bool same = reuse_ && valid_ && same_bits(t, t_) && same_bits(ws_.v0, v0_) &&
                      same_bits(ws_.motor_phase, motor_phase_) &&
                      std::equal(y, y + n, y_.begin(), [](double a, double b) { return same_bits(a, b); });
    if (same) return ev_;
    evaluate(model_, ws_, t, y, ev_);
    std::copy(y, y + n, y_.begin());
    t_ = t;
    v0_ = ws_.v0;
    motor_phase_ = ws_.motor_phase;
    valid_ = true;
    return ev_;
  }

 private:
  static bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
  }

  const Model& model_;
  Workspace& ws_;
  const bool reuse_;
  Evaluation ev_;
  bool valid_ = false;
  double t_ = 0.0, v0_ = 0.0, motor_phase_ = 0.0;  // the point of ev_ [s], [m/s], [rad]
  std::array<double, kMaxState> y_{};
};

std::string where(const Model& model, double t) {
  std::ostringstream s;
  s << "at t = " << t << " s, cam angle " << std::fmod(model.theta(t) * kRadToDeg, 360.0) << " deg";
  return s.str();
}

// Why a run stopped before its end time; converged while it did not.
struct Failure {
  Termination termination = Termination::converged;
  std::string message;
  explicit operator bool() const { return termination != Termination::converged; }
};

// Initial state: given, or on the law at quasi-static equilibrium (the contact
// force supplies exactly the law's acceleration); the pair by Newton from the
// cam angle (global search if that fails); a roller spinning without slip; a
// shaft twisted to carry the initial cam torque.
Failure initial_state(const SceneConfig& scene, const Model& model, Workspace& ws, double* y) {
  const InitialConfig& init = scene.mechanism.follower.initial;
  const double theta = model.theta(0.0);
  const LawSample law = model.law->eval(theta);
  // The set-up probe: Newton tracking, no spin, the cam at constant speed.
  Model probe = model;
  probe.tracking = Tracking::newton;
  probe.contact_friction = model.contact_friction && !model.has_spin;
  probe.has_spin = false;
  probe.drive = Drive::constant_speed;
  probe.layout = StateLayout::follower_only(model.follower.oscillating());
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
  if (!ev.tracking_ok)
    return {Termination::no_initial_contact, "could not find the initial contact pair " + where(model, 0.0)};
  ws.u_warm = ev.pair.u;
  ws.v_warm = ev.pair_v;
  std::fill(y, y + model.layout.size, 0.0);
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
  if (model.drive == Drive::shaft) {
    // Twist the shaft so that it carries the contact torque on the cam.
    evaluate(model, ws, 0.0, y, ev);
    const double twist = -ev.cam_torque / model.shaft_stiffness;
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
Failure given_state(const Model& model, Workspace& ws, const StartState& start, double* y) {
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

// Builds the integrator's options from the config and the plan.
IntegratorOptions integrator_options(const IntegratorConfig& ic, const RunPlan& p) {
  IntegratorOptions io;
  io.method = ic.method;
  io.rtol = ic.rtol;
  io.atol = ic.atol;
  io.max_step = p.max_step;
  io.fixed_step = ic.step.value_or(0.0);
  io.analytic_jacobian = ic.jacobian == JacobianSource::analytic;
  return io;
}

// Where the observer reads the state and quadratures between the loop's
// stops: the integrator's dense output over its last step, or the flight in
// closed form.
class StateSource {
 public:
  virtual ~StateSource() = default;
  // The state at t into y and all quadratures into q; either may be null.
  virtual void state(double t, double* y, double* q) = 0;
};

class IntegratorSource final : public StateSource {
 public:
  // `quadrature` null: the run integrates no quadratures.
  IntegratorSource(Integrator& integrator, SceneOde& ode, StepQuadrature* quadrature)
      : integrator_(integrator), ode_(ode), quadrature_(quadrature) {}
  void state(double t, double* y, double* q) override {
    if (y) integrator_.dense(t, y);
    if (q) quadratures_at(t, q);
  }
  // All quadratures at t, within the last step.
  void quadratures_at(double t, double* q) const {
    if (quadrature_)
      quadrature_->at(t, q);
    else
      std::fill(q, q + Model::kQuadratures, 0.0);
  }
  // Starts the quadratures at (t, y) with the values q.
  void start_quadratures(double t, const double* y, const Quadratures& q) {
    if (quadrature_) quadrature_->start(t, q, integrand(ode_.evaluated(t, y)));
  }
  // Restarts the integrator and the quadratures at (t, y, all quadratures q).
  void restart(double t, const double* y, const Quadratures& q) {
    integrator_.reinit(t, y);
    start_quadratures(t, y, q);
  }

 private:
  Integrator& integrator_;
  SceneOde& ode_;
  StepQuadrature* quadrature_;
};

// The flight: q, q̇ in closed form, the pair by Newton, the quadratures that
// change in flight (damper work, separation integral); everything else as it
// was at take-off (`y`, `q`: the state and quadratures the loop holds).
class FlightSource final : public StateSource {
 public:
  FlightSource(const Model& model, Workspace& ws, FlightTrack& track, const State& y, const Quadratures& q)
      : model_(model), ws_(ws), track_(track), y_(y), q_(q) {}
  void state(double t, double* y, double* q) override {
    FlightPoint p;
    ok_ = track_.at(ws_, t, p) && ok_;
    if (y) {
      std::copy(y_.begin(), y_.end(), y);
      y[0] = p.q;
      y[1] = p.v;
      if (model_.layout.u) y[*model_.layout.u] = p.u;
    }
    if (q) {
      std::copy(q_.begin(), q_.end(), q);
      q[1] = p.damper_work;
      q[4] = p.separation;
    }
  }
  bool ok() const { return ok_; }

 private:
  const Model& model_;
  Workspace& ws_;
  FlightTrack& track_;
  const State& y_;
  const Quadratures& q_;
  bool ok_ = true;
};

// The metrics over the evaluated window (docs/model.md §8) and the energy
// balance over the whole run (§7), folded in from dense-output samples. Its
// evaluation and dense-output buffers are the run's scratch: the loop and the
// series recorder read the evaluation it leaves behind.
class WindowObserver {
 public:
  WindowObserver(const Model& model, Workspace& ws, StateSource& source, const State& y0, const Quadratures& q0,
                 double t_eval, bool every_step, Metrics& m)
      : model_(model), ws_(ws), source_(&source), y0_(y0), q0_(q0), t_eval_(t_eval), every_step_(every_step), m_(m) {}

  // Evaluates the model at a dense-output time into ev() and folds it into the
  // metrics; returns the energy deviation E(t) − E(0) [J]. Before the first
  // step there is no dense output yet: the initial values are used.
  double observe(double t) {
    if (stepped_) {
      source_->state(t, ys_.data(), qs_.data());
    } else {
      ys_ = y0_;
      qs_ = q0_;
    }
    evaluate_keeping_warm_start(t, ev_);
    if (!stepped_) start_ = extreme_values(ev_);
    fold_extremes(t, extreme_values(ev_));
    return fold_energy(ev_);
  }

  // The step [t0, t] the integrator just took, but for its end
  // (observe_step_end): the model at its midpoint. The gap keeps its sign
  // inside a step (its zeros are located as roots), so the midpoint decides
  // separation; the quadratures' integrand there goes to `f_mid` unless it is
  // null. Without `every_step` the midpoint is evaluated only when the
  // quadratures or Newton tracking need it. Newton tracking solves there and
  // keeps the pair as the warm start of the evaluation after the step, with
  // and without `every_step`, so that the run is the same to the last bit.
  void observe_step(double t0, double t, Quadratures* f_mid) {
    stepped_ = true;
    step_start_ = t0;
    if (!every_step_ && !f_mid && model_.tracking != Tracking::newton) return;
    const double t_mid = t0 + (t - t0) * 0.5;
    source_->state(t_mid, ys_.data(), nullptr);
    evaluate(model_, ws_, t_mid, ys_.data(), ev_);
    if (f_mid) *f_mid = integrand(ev_);
    if (every_step_) {
      mid_ = extreme_values(ev_);
      fold_extremes(t_mid, mid_);
    }
    if (ev_.gap > 0.0) separated_time_ += std::max(0.0, t - std::max(t0, t_eval_));
  }

  // The end t of the step just taken, evaluated there by the loop (`at_end`):
  // its metrics and energy, with the quadratures at t; where the extremes'
  // parabola through the step's start, middle and end promises a record
  // inside the step, the model evaluated there too (state only).
  void observe_step_end(double t, const Evaluation& at_end) {
    if (!every_step_) return;
    source_->state(t, nullptr, qs_.data());
    const StepExtremes::Values end = extreme_values(at_end);
    fold_extremes(t, end);
    StepExtremes::Values s{};
    const std::size_t probes = extremes_.probes(start_, mid_, end, s);
    for (std::size_t i = 0; i < probes; ++i) {
      const double t_probe = step_start_ + (t - step_start_) * s[i];
      fold_extremes(t_probe, extreme_values(probe(t_probe)));
    }
    start_ = end;
    fold_energy(at_end);
  }

  // The flight interval [t0, t] (open throughout but at a landing that ends
  // it): the metrics at its end; the largest gap inside it from the cubic
  // through its ends (`largest_gap` [m]), the others (contact force,
  // penetration) being zero in flight.
  void observe_flight(double t0, double t, double largest_gap) {
    stepped_ = true;
    if (every_step_) {
      observe(t);
      start_ = extreme_values(ev_);
      if (t >= t_eval_) flight_gap_ = std::max(flight_gap_, largest_gap);
    }
    separated_time_ += std::max(0.0, t - std::max(t0, t_eval_));
  }

  // Reads the state from `source` from now on.
  void read_from(StateSource& source) { source_ = &source; }

  // The metrics that are not extremes (publish_extremes), once the run
  // reached `t_end` [s]; `separation_integral` is ∫ max(g, 0) dt over the
  // evaluated window [m s].
  void finish(double t_end, double separation_integral) {
    const double evaluated = t_end - t_eval_;
    m_.separation_fraction = evaluated > 0.0 ? separated_time_ / evaluated : 0.0;
    m_.energy_residual = energy_scale_ > 0.0 ? energy_max_dev_ / energy_scale_ : 0.0;
    m_.max_pressure_angle_deg = model_.geometry.max_pressure_angle_deg;
    m_.min_radius_of_curvature = model_.geometry.min_radius_of_curvature;
    m_.jump_speed_rpm = jump_speed_rpm(model_);
    m_.separation_integral = separation_integral;
  }

  // The extremes so far into the metrics (a failed run's too).
  void publish_extremes() {
    const StepExtremes::Values& best = extremes_.best();
    m_.max_separation_gap = std::max({0.0, best[0], flight_gap_});
    m_.peak_contact_force = std::max(0.0, best[1]);
    m_.min_contact_force = std::isfinite(best[2]) ? -best[2] : 0.0;
    m_.max_penetration = std::max(0.0, best[3]);
    m_.max_kinematic_error = std::max(0.0, best[4]);
  }

  Evaluation& ev() { return ev_; }
  // The separation integral quadrature at the last observation [m s].
  double separation_quadrature() const { return qs_[4]; }
  // Energy deviation [J] → energy residual [-].
  double residual(double deviation) const { return energy_scale_ > 0.0 ? deviation / energy_scale_ : 0.0; }

 private:
  // The model at t [s] from the state in ys_ into `out`, the Newton warm
  // start kept as it was.
  void evaluate_keeping_warm_start(double t, Evaluation& out) {
    const double u_keep = ws_.u_warm;
    evaluate(model_, ws_, t, ys_.data(), out);
    ws_.u_warm = u_keep;
  }

  // The model at t inside the step just taken (state only).
  const Evaluation& probe(double t) {
    source_->state(t, ys_.data(), nullptr);
    evaluate_keeping_warm_start(t, probe_);
    return probe_;
  }

  // What the window's extremes follow, at the evaluation `e`.
  StepExtremes::Values extreme_values(const Evaluation& e) const {
    return {e.gap, e.normal_force, -e.normal_force, e.delta, std::abs(e.y - model_.law->eval(e.theta).s)};
  }

  // Folds the extremes' values `x` at t [s] into the window's records.
  void fold_extremes(double t, const StepExtremes::Values& x) {
    if (t >= t_eval_) extremes_.fold(x);
  }

  // Folds the energy of `e` with the quadratures qs_ into the balance;
  // returns the deviation E(t) − E(0) [J].
  double fold_energy(const Evaluation& e) {
    const EnergyTerms terms = energy_terms(model_, e);
    const double energy =
        terms.kinetic + terms.spring + terms.gravity + terms.contact - qs_[0] + qs_[1] + qs_[2] + qs_[3];
    if (!energy_initialised_) {
      energy0_ = energy;
      energy_initialised_ = true;
    }
    energy_scale_ = std::max(energy_scale_, terms.kinetic + terms.spring + std::abs(qs_[0]));
    energy_max_dev_ = std::max(energy_max_dev_, std::abs(energy - energy0_));
    return energy - energy0_;
  }

  const Model& model_;
  Workspace& ws_;
  StateSource* source_;
  const State& y0_;
  const Quadratures& q0_;
  const double t_eval_;  // start of the evaluated window [s]
  const bool every_step_;
  Metrics& m_;
  bool stepped_ = false;
  Evaluation ev_, probe_;
  StepExtremes extremes_;
  StepExtremes::Values start_{}, mid_{};  // the extremes' values at the step's start and middle
  double step_start_ = 0.0;               // [s]
  double flight_gap_ = 0.0;               // the largest gap inside the flights in the window [m]
  State ys_{};
  Quadratures qs_{};
  double energy0_ = 0.0, energy_scale_ = 0.0, energy_max_dev_ = 0.0;  // [J]
  bool energy_initialised_ = false;
  double separated_time_ = 0.0;  // within the evaluated window [s]
};

// One row of a time series from an evaluation at t [s].
void push_row(const Model& model, const Evaluation& ev, TimeSeries& series, double t) {
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
}

// The series recording: the rows of timeseries.csv on the output grid, the
// samples at SimulationOptions::sample_times, and the separation integral at
// the start of the evaluated window, each observed as the integration passes.
class SeriesRecorder {
 public:
  SeriesRecorder(const Model& model, const RunPlan& p, const SimulationOptions& options, WindowObserver& observer,
                 SimulationResult& result)
      : model_(model),
        p_(p),
        options_(options),
        observer_(observer),
        result_(result),
        eval_start_seen_(p.t_eval <= 0.0) {}

  // Records everything due up to t_hi [s].
  void record_until(double t_hi) {
    for (;; ++next_output_) {
      const double t_nominal = static_cast<double>(next_output_) * p_.output_dt;
      const double t_out = std::min(t_nominal, p_.t_end);
      if (t_out > t_hi * (1.0 + 1e-14) + 1e-300) break;
      if (t_nominal > p_.t_end * (1.0 + 1e-12)) break;
      const double de = observer_.observe(t_out);
      if (!options_.record_series) continue;
      push_row(model_, observer_.ev(), result_.series, t_out);
      energy_deviation_.push_back(de);
    }
    const std::vector<double>& sample_times = options_.sample_times;
    for (; next_sample_ < sample_times.size() && sample_times[next_sample_] <= t_hi; ++next_sample_) {
      const double t_sample = sample_times[next_sample_];
      sample_energy_deviation_.push_back(observer_.observe(t_sample));
      push_row(model_, observer_.ev(), result_.samples, t_sample);
    }
    if (!eval_start_seen_ && p_.t_eval <= t_hi) {
      observer_.observe(p_.t_eval);
      separation_integral_at_eval_ = observer_.separation_quadrature();
      eval_start_seen_ = true;
    }
  }

  // The energy residual columns, once the run's energy scale is known.
  void finish() {
    for (double de : energy_deviation_) result_.series.energy_residual.push_back(observer_.residual(de));
    for (double de : sample_energy_deviation_) result_.samples.energy_residual.push_back(observer_.residual(de));
  }

  double separation_integral_at_eval() const { return separation_integral_at_eval_; }  // [m s]

 private:
  const Model& model_;
  const RunPlan& p_;
  const SimulationOptions& options_;
  WindowObserver& observer_;
  SimulationResult& result_;
  long next_output_ = 0;
  std::size_t next_sample_ = 0;
  std::vector<double> energy_deviation_, sample_energy_deviation_;  // [J]
  double separation_integral_at_eval_ = 0.0;
  bool eval_start_seen_;
};

// What one run's pieces share besides the observer and the recorder.
struct RunContext {
  const SceneConfig& scene;
  const Model& model;
  Workspace& ws;
  const SimulationOptions& options;
  const RunPlan& plan;
  Clock::time_point wall_start;
  SimulationResult& result;
};

// The loop's state besides the integrator: the state and quadratures at the
// last stop, where the observer reads between stops, and the flight.
struct LoopState {
  State y{};
  Quadratures q{};
  double t = 0.0;  // time of the last stop [s]
  bool separated = false;
  double last_progress = 0.0;  // wall time of the last progress report [s]
  IntegratorSource* integrator_source = nullptr;
  FlightSource* flight_source = nullptr;
  FlightTrack* flight = nullptr;         // null: flights are integrated
  StepQuadrature* quadrature = nullptr;  // null: no quadratures
  const Model* newton_model = nullptr;   // the model with Newton tracking, for the drift projection
  bool last_flight_short = false;        // the last flight landed at once: integrate the next one
  bool ended_in_flight = false;          // the run's end came in a flight
};

// A contact onset at t (docs/model.md §6): an impact when the follower was
// separated; the episode's approach speed v₀ from the gap's closing rate.
void record_onset(const RunContext& run, const Evaluation& ev, double t, bool& separated) {
  SimulationResult& result = run.result;
  const double approach = -ev.gap_rate;
  run.ws.v0 = std::max(approach, run.model.contact.reference_velocity);
  if (separated && t >= run.plan.t_eval) {
    ++result.metrics.impact_count;
    result.metrics.max_impact_velocity = std::max(result.metrics.max_impact_velocity, approach);
  }
  result.events.push_back({t, ev.theta * kRadToDeg, true, approach, separated, ev.v});
  separated = false;
}

// A root the integrator stopped at (docs/model.md §6): records a contact onset
// (an impact when the follower was separated) or a separation. Returns whether
// the right-hand side changed, so that the integrator must restart.
bool handle_root(const RunContext& run, const Integrator& integrator, const Evaluation& ev, double t,
                 std::array<int, 2>& root_dirs, bool& separated) {
  const Model& model = run.model;
  bool restart = false;
  integrator.root_info(root_dirs.data());
  ++run.result.solver.events;
  if (root_dirs[0] < 0) {  // gap closing: contact onset
    record_onset(run, ev, t, separated);
    restart = true;
  } else if (root_dirs[0] > 0) {  // gap opening: separation
    run.result.events.push_back({t, ev.theta * kRadToDeg, false, ev.gap_rate, false, ev.v});
    separated = true;
    restart = true;
  }
  if (model.root_count() > 1 && root_dirs[1] != 0 && ev.delta > 0.0) restart = true;  // force clamp switches
  return restart;
}

// Differential tracking: projects u back onto the common-normal condition
// f = 0 by warm-started Newton (global search if that fails) when it drifted
// beyond `tolerance` [rad]; sets `restart` when it did.
// `newton_model` is the model with Newton tracking (made once per run: a
// Model copy allocates).
Failure project_pair(const RunContext& run, const Model& newton_model, const Evaluation& ev, double t, double tolerance,
                     State& y, bool& restart) {
  const Model& model = run.model;
  Workspace& ws = run.ws;
  if (!model.layout.u || !(ev.pair_drift > tolerance)) return {};
  Evaluation projected;
  ws.u_warm = y[*model.layout.u];
  if (model.layout.v) ws.v_warm = y[*model.layout.v];
  const long resets_before = ws.tracking_resets;
  evaluate(newton_model, ws, t, y.data(), projected);
  if (!projected.tracking_ok) return {Termination::tracking_lost, "contact pair tracking lost " + where(model, t)};
  if (ws.tracking_resets == resets_before) ++run.result.solver.projections;
  y[*model.layout.u] = projected.pair.u;
  if (model.layout.v) y[*model.layout.v] = projected.pair_v;
  restart = true;
  return {};
}

// The contact left what the compliant-contact model describes.
Failure check_contact(const Model& model, const Evaluation& ev, double t) {
  // A penetration beyond half the roller radius (a tenth of the base radius
  // for a flat face) means the contact is far too soft for its load.
  if (ev.delta > model.penetration_limit)
    return {Termination::penetration_limit, "contact penetration " + check_text::num(ev.delta) + " m exceeds " +
                                                check_text::num(model.penetration_limit) +
                                                " m (the contact stiffness is far too low for the load) " +
                                                where(model, t)};
  // A flat face whose contact point runs off its edge: the design check
  // (check_cam) passed on the law, so the dynamics drove it there.
  if (model.reduction == ContactReduction::line && ev.delta > 0.0 &&
      std::abs(ev.contact_offset) > 0.5 * model.follower.face_width)
    return {Termination::left_flat_face, "the contact point left the flat face (" + check_text::num(ev.contact_offset) +
                                             " m from its centre, face_width " +
                                             check_text::num(model.follower.face_width) + " m) " + where(model, t)};
  return {};
}

// The step and wall-time budgets; reports progress now and then (at most
// every 0.25 s of wall time, the last report's time in `last_progress` [s]).
Failure check_budgets(const RunContext& run, const Integrator& integrator, double t, double& last_progress) {
  const IntegratorConfig& ic = run.scene.integrator;
  const SolverCounters c = integrator.counters();
  if (c.steps > ic.max_steps)
    return {Termination::step_budget, "step budget of " + std::to_string(ic.max_steps) +
                                          " steps (integrator.max_steps) exceeded " + where(run.model, t)};
  const Clock::time_point now = Clock::now();
  const double wall = std::chrono::duration<double>(now - run.wall_start).count();  // [s]
  if (wall > ic.max_wall_time_s)
    return {Termination::wall_time_budget, "wall-time budget of " + std::to_string(ic.max_wall_time_s) +
                                               " s (integrator.max_wall_time_s) exceeded " + where(run.model, t)};
  if (study_budget_exhausted(now))
    return {Termination::wall_time_budget, study_budget_text() + " " + where(run.model, t)};
  if (run.options.progress && wall - last_progress > 0.25) {
    last_progress = wall;
    run.options.progress(t / run.plan.t_end);
  }
  return {};
}

// A flight in closed form from the loop's stop (the follower separated):
// interval by interval to the landing or the run's end, the observer and the
// recorder reading the flight. At a landing the contact onset is recorded
// and the integrator restarts there.
Failure fly(const RunContext& run, SceneOde& ode, Integrator& integrator, LoopState& loop, WindowObserver& observer,
            SeriesRecorder& recorder) {
  const Model& model = run.model;
  FlightTrack& track = *loop.flight;
  const Evaluation& ev = ode.evaluated(loop.t, loop.y.data());
  const double t_start = loop.t;
  FlightPoint start;
  start.t = loop.t;
  start.q = loop.y[0];
  start.v = loop.y[1];
  start.u = ev.pair.u;
  start.gap = std::max(ev.gap, 0.0);
  start.gap_rate = ev.gap_rate;
  start.damper_work = loop.q[1];
  start.separation = loop.q[4];
  track.start(start);
  observer.read_from(*loop.flight_source);
  ++run.result.solver.flights;
  bool landed = false;
  while (!landed && track.now().t < run.plan.t_end) {
    bool ok = true;
    landed = track.advance(run.ws, run.plan.t_end, ok);
    ++run.result.solver.flight_intervals;
    if (ok) {
      observer.observe_flight(track.before().t, track.now().t, track.largest_gap());
      recorder.record_until(track.now().t);
    }
    if (!ok || !loop.flight_source->ok())
      return {Termination::tracking_lost, "contact pair lost in flight " + where(model, track.now().t)};
    if (Failure f = check_budgets(run, integrator, track.now().t, loop.last_progress)) return f;
  }
  const FlightPoint& end = track.now();
  loop.t = end.t;
  loop.y[0] = end.q;
  loop.y[1] = end.v;
  if (model.layout.u) loop.y[*model.layout.u] = end.u;
  loop.q[1] = end.damper_work;
  loop.q[4] = end.separation;
  run.ws.u_warm = end.u;
  observer.read_from(*loop.integrator_source);
  loop.last_flight_short = landed && end.t - t_start < 1e-9 * (run.plan.max_step + end.t);
  loop.ended_in_flight = !landed;
  if (landed) {
    ++run.result.solver.events;
    record_onset(run, ode.evaluated(end.t, loop.y.data()), end.t, loop.separated);
    loop.integrator_source->restart(end.t, loop.y.data(), loop.q);
  }
  return {};
}

// The integration loop (docs/model.md §6): one internal step at a time; metrics
// and outputs from dense output over each step; contact events at roots and
// drift projection, each followed by a restart; then the contact checks and
// the budgets; the flights in closed form where the model allows. `loop`
// holds the state and quadratures at the last stop, and at the end.
Failure integrate(const RunContext& run, SceneOde& ode, Integrator& integrator, LoopState& loop,
                  WindowObserver& observer, SeriesRecorder& recorder) {
  const Model& model = run.model;
  Workspace& ws = run.ws;
  const double t_end = run.plan.t_end;
  Evaluation& ev = observer.ev();
  observer.observe(0.0);
  recorder.record_until(0.0);
  loop.integrator_source->start_quadratures(0.0, loop.y.data(), loop.q);
  loop.separated = ev.gap > 0.0;
  std::array<int, 2> root_dirs{};
  const double projection_tolerance = std::max(1e-9, 10.0 * run.scene.integrator.rtol);  // [rad]
  bool in_flight = loop.flight && loop.separated;  // a start off the cam flies first

  while (loop.t < t_end) {
    if (in_flight) {
      if (Failure f = fly(run, ode, integrator, loop, observer, recorder)) return f;
      in_flight = false;
      continue;
    }
    Integrator::Result result_kind;
    try {
      result_kind = integrator.step(t_end);
    } catch (const NumericalError& e) {
      return {Termination::integrator_failure,
              std::string(e.what()) + " (integrating " + where(model, integrator.time()) + ")"};
    }
    const double t = loop.t = integrator.time();
    Quadratures f_mid{};
    observer.observe_step(integrator.last_step_start(), t, loop.quadrature ? &f_mid : nullptr);
    const double* state = integrator.state();
    std::copy(state, state + model.layout.size, loop.y.begin());
    // The step's end; the recorder's evaluations do not touch the ode's.
    const Evaluation& at_end = ode.evaluated(t, loop.y.data());
    if (loop.quadrature) loop.quadrature->step(t, f_mid, integrand(at_end));
    recorder.record_until(t);
    ev = at_end;
    observer.observe_step_end(t, ev);
    if (model.tracking == Tracking::newton) {
      ws.u_warm = ev.pair.u;
      ws.v_warm = ev.pair_v;
    }
    bool restart = false;
    if (result_kind == Integrator::Result::root)
      restart = handle_root(run, integrator, ev, t, root_dirs, loop.separated);
    if (Failure f = check_contact(model, ev, t)) return f;
    // A take-off: the flight in closed form, unless the last one landed at once.
    in_flight = restart && loop.separated && loop.flight && !loop.last_flight_short;
    if (restart && loop.separated) loop.last_flight_short = false;
    if (!in_flight)
      if (Failure f = project_pair(run, *loop.newton_model, ev, t, projection_tolerance, loop.y, restart)) return f;
    if (in_flight || restart) loop.integrator_source->quadratures_at(t, loop.q.data());
    if (restart && !in_flight) loop.integrator_source->restart(t, loop.y.data(), loop.q);
    if (Failure f = check_budgets(run, integrator, t, loop.last_progress)) return f;
    if (result_kind == Integrator::Result::stop) break;
  }
  recorder.record_until(t_end);
  // The quadratures at the end: the flight's own when the run ended in one.
  if (!loop.ended_in_flight) loop.integrator_source->quadratures_at(integrator.time(), loop.q.data());
  return {};
}

// Without the quadratures the energy balance and the separation integral
// are not known: NaN, never a number that looks measured.
void forget_quadrature_figures(SimulationResult& result) {
  constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  result.metrics.energy_residual = kUnknown;
  result.metrics.separation_integral = kUnknown;
  std::fill(result.series.energy_residual.begin(), result.series.energy_residual.end(), kUnknown);
  std::fill(result.samples.energy_residual.begin(), result.samples.energy_residual.end(), kUnknown);
}

// Initial conditions, the integration and the metrics of one run; fills
// run.result except the solver's configuration, run time and status.
Failure run_scene(const RunContext& run) {
  const Model& model = run.model;
  LoopState loop;
  if (Failure f = run.options.start ? given_state(model, run.ws, *run.options.start, loop.y.data())
                                    : initial_state(run.scene, model, run.ws, loop.y.data()))
    return f;

  SceneOde ode(model, run.ws);
  const std::unique_ptr<Integrator> integrator_ptr =
      make_integrator(ode, integrator_options(run.scene.integrator, run.plan), 0.0, loop.y.data());
  Integrator& integrator = *integrator_ptr;
  StepQuadrature quadrature;
  if (run.options.quadratures) loop.quadrature = &quadrature;
  IntegratorSource integrator_source(integrator, ode, loop.quadrature);
  std::optional<FlightTrack> flight;
  if (run.scene.integrator.flight == FlightMethod::closed_form && flight_has_closed_form(model)) flight.emplace(model);
  std::optional<FlightSource> flight_source;
  if (flight) flight_source.emplace(model, run.ws, *flight, loop.y, loop.q);
  Model newton_model = model;
  newton_model.tracking = Tracking::newton;
  loop.newton_model = &newton_model;
  loop.integrator_source = &integrator_source;
  loop.flight = flight ? &*flight : nullptr;
  loop.flight_source = flight_source ? &*flight_source : nullptr;
  const State y0 = loop.y;
  const Quadratures q0 = loop.q;
  WindowObserver observer(model, run.ws, integrator_source, y0, q0, run.plan.t_eval, run.options.step_metrics,
                          run.result.metrics);
  SeriesRecorder recorder(model, run.plan, run.options, observer, run.result);
  Failure failure;
  try {
    failure = integrate(run, ode, integrator, loop, observer, recorder);
    observer.publish_extremes();
    if (!failure) {
      observer.finish(run.plan.t_end, loop.q[4] - recorder.separation_integral_at_eval());
      recorder.finish();
      if (!run.options.quadratures) forget_quadrature_figures(run.result);
      run.result.error.energy_residual = run.result.metrics.energy_residual;
    }
  } catch (const NumericalError& e) {  // a SUNDIALS call other than the step failed
    failure = {Termination::integrator_failure, e.what()};
  }
  run.result.solver.counters = integrator.counters();
  run.result.final_state.assign(loop.y.begin(), loop.y.begin() + model.layout.size);
  run.result.final_approach_speed = run.ws.v0;
  run.result.final_motor_phase = run.ws.motor_phase;
  return failure;
}

}  // namespace

std::vector<std::string> integrated_quadratures(const Model& model) {
  static constexpr const char* kNames[] = {"drive_work", "damper_work", "hysteresis_work", "friction_work"};
  std::vector<std::string> names;
  for (int i = 0; i < 4; ++i)
    if (quadrature_reported(model, i)) names.emplace_back(kNames[i]);
  return names;
}

void throw_if_failed(const SimulationResult& result) {
  if (!result.solver.converged()) throw NumericalError(result.solver.message);
}

std::vector<std::string> TimeSeries::column_names() {
  return {
      "time", "cam_angle_deg", "follower_position", "follower_velocity", "follower_acceleration", "kinematic_position",
      "gap",  "contact_force", "friction_force",    "energy_residual",   "contact_offset",        "cam_speed_rpm"};
}

std::vector<const std::vector<double>*> TimeSeries::columns() const {
  return {&time, &cam_angle_deg, &follower_position, &follower_velocity, &follower_acceleration, &kinematic_position,
          &gap,  &contact_force, &friction_force,    &energy_residual,   &contact_offset,        &cam_speed_rpm};
}

SimulationResult simulate(const SceneConfig& scene, const Model& model, Workspace& ws,
                          const SimulationOptions& options) {
  const Clock::time_point wall_start = Clock::now();
  const RunPlan p = plan(scene, model);
  SimulationResult result;
  result.evaluated_from = p.t_eval;
  result.end_time = p.t_end;
  ws.tracking_resets = 0;
  prepare_workspace(model, ws);

  Failure failure;
  try {
    failure = run_scene({scene, model, ws, options, p, wall_start, result});
  } catch (const NumericalError& e) {  // SUNDIALS could not be set up
    failure = {Termination::integrator_failure, e.what()};
  }

  SolverSummary& s = result.solver;
  s.method = to_string(scene.integrator.method);
  s.rtol = scene.integrator.rtol;
  s.atol = scene.integrator.atol;
  s.tracking_resets = ws.tracking_resets;
  s.run_time_s = std::chrono::duration<double>(Clock::now() - wall_start).count();
  s.termination = failure.termination;
  s.message = std::move(failure.message);
  if (s.converged() && options.progress) options.progress(1.0);
  return result;
}

void estimate_error(const SceneConfig& scene, const Model& model, SimulationResult& result) {
  if (scene.integrator.error_estimate != ErrorEstimateMethod::richardson || !result.solver.converged()) return;
  SceneConfig tight = scene;
  if (scene.integrator.method == IntegrationMethod::rk4) {
    tight.integrator.step = scene.integrator.step.value_or(0.0) / std::pow(100.0, 0.25);
  } else {
    tight.integrator.rtol = scene.integrator.rtol / 100.0;
    tight.integrator.atol = scene.integrator.atol / 100.0;
  }
  Workspace ws;
  const SimulationResult reference = simulate(tight, model, ws);
  if (!reference.solver.converged()) {
    result.solver.termination = reference.solver.termination;
    result.solver.message = reference.solver.message;
    return;
  }
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
  return simulate_scene(*build_cam_geometry(scene, file), scene, file, options);
}

SimulationResult simulate_scene(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file,
                                const SimulationOptions& options) {
  const Model model = build_model(geometry, scene, file);
  Workspace ws;
  SimulationResult result = simulate(scene, model, ws, options);
  estimate_error(scene, model, result);
  return result;
}

}  // namespace camdyn
