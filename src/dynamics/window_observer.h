// What a run observes (docs/model.md §8, §7): the window's metrics and the
// energy balance folded in from dense-output samples (WindowObserver), and the
// rows of the time series and the requested samples (SeriesRecorder), read
// from a StateSource between the loop's stops. Internal to dynamics/:
// simulation.h is the interface.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "dynamics/contact_stress.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/run_plan.h"
#include "dynamics/simulation.h"
#include "dynamics/step_extremes.h"
#include "dynamics/train_jump_speed.h"
#include "dynamics/train_observer.h"

namespace camdyn {

// ∫ f dt over the evaluated window by Simpson's rule on each step's start,
// middle and end (a step across the window's start: the trapezoid of its
// middle and end over the part inside).
struct WindowSimpson {
  double start = 0.0, mid = 0.0;  // f at the step's start and middle
  double integral = 0.0;
  // Folds the step [step_start, t] [s] with f = `end` at t; the window starts at t_eval [s].
  void fold(double step_start, double t, double t_eval, double end) {
    const double h = t - step_start;  // [s]
    if (step_start >= t_eval)
      integral += h / 6.0 * (start + 4.0 * mid + end);
    else if (t > t_eval)
      integral += (t - t_eval) * 0.5 * (mid + end);
    start = end;
  }
};

// Where the observer reads the state and quadratures between the loop's
// stops: the integrator's dense output over its last step, or the flight in
// closed form.
class StateSource {
 public:
  virtual ~StateSource() = default;
  // The state at t into y and all quadratures into q; either may be null.
  virtual void state(double t, double* y, double* q) = 0;
};

// The metrics over the evaluated window (docs/model.md §8) and the energy
// balance over the whole run (§7), folded in from dense-output samples. Its
// evaluation and dense-output buffers are the run's scratch: the loop and the
// series recorder read the evaluation it leaves behind.
/// Whether some spring of the model gives its wire (`peak_spring_stress`).
inline bool has_spring_stress(const Model& m) {
  return m.forces.spring().stress_per_newton > 0.0 ||
         std::any_of(m.train.bodies.begin(), m.train.bodies.end(),
                     [](const TrainBody& b) { return b.spring_stress_per_newton > 0.0; });
}

/// The largest wire shear stress of the model's springs at `e` [Pa]
/// (docs/model.md §12, "Spring stress"): the follower's massless spring at
/// its force, each train spring at its most loaded segment.
inline double spring_stress(const Model& m, const Evaluation& e) {
  const ReturnSpring& s = m.forces.spring();
  double tau = s.stress_per_newton * std::abs(s.force(e.y, e.v, m.mass));
  for (std::size_t i = 0; i < m.train.bodies.size(); ++i)
    tau = std::max(tau, m.train.bodies[i].spring_stress_per_newton * e.train.spring_peak_force[i]);
  return tau;
}

class WindowObserver {
 public:
  WindowObserver(const Model& model, Workspace& ws, StateSource& source, const RunState& y0, const RunQuadratures& q0,
                 double t_eval, bool every_step, const SeparationCauses& causes, Metrics& m)
      : model_(model),
        ws_(ws),
        source_(&source),
        y0_(y0),
        q0_(q0),
        t_eval_(t_eval),
        every_step_(every_step),
        causes_(causes),
        m_(m),
        train_(model, causes, m) {
    if (has_spring_stress(model)) m_.peak_spring_stress = 0.0;
  }

  // Evaluates the model at a dense-output time into ev() and folds it into the
  // metrics; returns the energy deviation E(t) − E(0) [J]. Before the first
  // step there is no dense output yet: the initial values are used.
  double observe(double t) {
    take_up_decisions();
    if (stepped_) {
      source_->state(t, ys_.data(), qs_.data());
    } else {
      ys_ = y0_;
      qs_ = q0_;
    }
    evaluate_keeping_warm_start(t, ev_);
    if (!stepped_) {
      start_ = extreme_values(ev_);
      torque_squared_.start = squared_torque(ev_);
      float_gap_.start = float_gap_value(ev_);
      rebound_gap_.start = rebound_gap_value(ev_);
    }
    fold_extremes(t, extreme_values(ev_));
    fold_train(t, ev_);
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
  void observe_step(double t0, double t, RunQuadratures* f_mid) {
    take_up_decisions();
    stepped_ = true;
    step_start_ = t0;
    if (!every_step_ && !f_mid && model_.tracking != Tracking::newton) return;
    const double t_mid = t0 + (t - t0) * 0.5;
    source_->state(t_mid, ys_.data(), nullptr);
    evaluate(model_, ws_, t_mid, ys_.data(), ev_);
    if (f_mid) *f_mid = quadrature_integrand(ev_);
    if (every_step_) {
      mid_ = extreme_values(ev_);
      torque_squared_.mid = squared_torque(ev_);
      float_gap_.mid = float_gap_value(ev_);
      rebound_gap_.mid = rebound_gap_value(ev_);
      fold_extremes(t_mid, mid_);
      fold_train(t_mid, ev_);
    }
    const double in_window = std::max(0.0, t - std::max(t0, t_eval_));  // [s]
    if (ev_.gap > 0.0 && !train_.lash(ev_)) {
      separated_time_ += in_window;
      if (cam_floats()) float_time_ += in_window;
      if (causes_.cam == SeparationCause::rebound) {
        rebound_time_ += in_window;
        if (in_window > 0.0 && std::isnan(rebound_theta_)) rebound_theta_ = ev_.theta;
      }
    }
    train_.fold_step(ev_, in_window);
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
    fold_train(t, at_end);
    StepExtremes::Values s{};
    const std::size_t probes = extremes_.probes(start_, mid_, end, s);
    for (std::size_t i = 0; i < probes; ++i) {
      const double t_probe = step_start_ + (t - step_start_) * s[i];
      fold_extremes(t_probe, extreme_values(probe(t_probe)));
    }
    start_ = end;
    torque_squared_.fold(step_start_, t, t_eval_, squared_torque(at_end));
    float_gap_.fold(step_start_, t, t_eval_, float_gap_value(at_end));
    rebound_gap_.fold(step_start_, t, t_eval_, rebound_gap_value(at_end));
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
      torque_squared_.start = squared_torque(ev_);
      float_gap_.start = float_gap_value(ev_);
      if (t >= t_eval_) flight_gap_ = std::max(flight_gap_, largest_gap);
    }
    separated_time_ += std::max(0.0, t - std::max(t0, t_eval_));
    // A flight is closed-form only without a train (dynamics/free_flight.h): every separation then floats.
    if (cam_floats()) float_time_ += std::max(0.0, t - std::max(t0, t_eval_));
  }

  // Reads the state from `source` from now on.
  void read_from(StateSource& source) { source_ = &source; }

  // The metrics that are not extremes (publish_extremes), once the run
  // reached `t_end` [s]; `separation_integral` is ∫ max(g, 0) dt over the
  // evaluated window [m s], `drive_work` the drive's work over it [J].
  void finish(double t_end, double separation_integral, double drive_work) {
    const double evaluated = t_end - t_eval_;
    m_.separation_fraction = evaluated > 0.0 ? separated_time_ / evaluated : 0.0;
    m_.rms_cam_torque = evaluated > 0.0 ? std::sqrt(torque_squared_.integral / evaluated) : 0.0;
    m_.mean_drive_power = evaluated > 0.0 ? drive_work / evaluated : 0.0;
    m_.energy_residual = energy_scale_ > 0.0 ? energy_max_dev_ / energy_scale_ : 0.0;
    m_.max_pressure_angle_deg = model_.geometry.max_pressure_angle_deg;
    m_.min_radius_of_curvature = model_.geometry.min_radius_of_curvature;
    m_.jump_speed_rpm = model_jump_speed_rpm(model_);
    m_.separation_integral = separation_integral;
    if (model_.take_up.applies) {
      m_.float_fraction = evaluated > 0.0 ? float_time_ / evaluated : 0.0;
      // Without every step's samples the integral is not known (NaN, never a number that looks measured).
      m_.float_integral = every_step_ ? float_gap_.integral : std::numeric_limits<double>::quiet_NaN();
    }
    train_.finish(evaluated);
  }

  // The extremes so far into the metrics (a failed run's too).
  void publish_extremes() {
    take_up_decisions();
    const StepExtremes::Values& best = extremes_.best();
    m_.max_separation_gap = std::max({0.0, best[extreme::gap], flight_gap_});
    m_.peak_contact_force = std::max(0.0, best[extreme::contact_force]);
    const double least = best[extreme::least_contact_force];
    m_.min_contact_force = std::isfinite(least) ? -least : 0.0;
    m_.max_penetration = std::max(0.0, best[extreme::penetration]);
    m_.max_kinematic_error = std::max(0.0, best[extreme::kinematic_error]);
    if (model_.hertz) m_.peak_contact_stress = std::max(0.0, best[extreme::contact_stress]);
    m_.peak_cam_torque = std::max(0.0, best[extreme::cam_torque]);
    if (!model_.follower.circle()) m_.max_face_excursion = std::max(0.0, best[extreme::face_excursion]);
    if (model_.take_up.applies) m_.max_float_gap = std::max({0.0, best[extreme::float_gap], rebound_max_gap_});
    // A rebound that flew separated: its least contact force is 0.
    if (floated_in_rebound_) m_.min_contact_force = std::min(m_.min_contact_force, 0.0);
  }

  Evaluation& ev() { return ev_; }
  // The separation integral quadrature at the last observation [m s].
  double separation_quadrature() const { return qs_[quadrature::separation]; }
  // The drive work quadrature at the last observation [J].
  double drive_work_quadrature() const { return qs_[quadrature::drive_work]; }
  // Energy deviation [J] → energy residual [-].
  double residual(double deviation) const { return energy_scale_ > 0.0 ? deviation / energy_scale_ : 0.0; }

 private:
  // Whether an open cam gap (not lash) floats (dynamics/separation_cause.h).
  bool cam_floats() const { return floats(causes_.cam); }

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
  // While a body rests on its seat the cam's gap is lash: neither a
  // separation nor the least contact force (docs/model.md §12).
  StepExtremes::Values extreme_values(const Evaluation& e) const {
    const LawSample law = model_.law->eval(e.theta);
    const double kinematic_error = std::abs(e.y - law.s);
    constexpr double none = -std::numeric_limits<double>::infinity();
    const double stress = model_.hertz ? contact_pressure(model_, *model_.hertz, e) : none;
    const double torque = std::abs(cam_drive_torque(e));
    const double excursion = model_.follower.circle() ? none : std::abs(e.contact_offset);
    if (train_.lash(e))
      return extremes_of(none, e.normal_force, none, e.delta, kinematic_error, stress, torque, excursion, none);
    // The float gap where a seat makes it differ from the gap (without one
    // every separation floats). With a seat the least contact force is the
    // margin against float: over the law above the take-up windows, never
    // in a bounce (at the take-up and at seating the seat takes the load and
    // the contact force falls to zero by design). A gap open at the root that
    // opens it (or where a body leaves its seat) is not classified yet, and
    // no float either.
    const SeparationCause cause = causes_.cam;
    const bool applies = model_.take_up.applies;
    const bool floating = applies ? cause == SeparationCause::float_gap : cam_floats();
    const bool bounce = cause != SeparationCause::none && !floats(cause);
    const bool margin = !applies || !in_take_up_windows(model_.take_up, law);
    const double float_gap = applies && floating ? e.gap : none;
    const double least = bounce || !margin || (e.gap > 0.0 && !floating) ? none : -e.normal_force;
    return extremes_of(e.gap, e.normal_force, least, e.delta, kinematic_error, stress, torque, excursion, float_gap);
  }

  // T² [N² m²] of the drive torque at `e`.
  static double squared_torque(const Evaluation& e) { return cam_drive_torque(e) * cam_drive_torque(e); }

  // The open cam gap where it floats [m], 0 elsewhere: the float integral's integrand.
  double float_gap_value(const Evaluation& e) const {
    return e.gap > 0.0 && !train_.lash(e) && cam_floats() ? e.gap : 0.0;
  }
  // The open cam gap of a rebound not decided yet [m], 0 elsewhere.
  double rebound_gap_value(const Evaluation& e) const {
    return e.gap > 0.0 && !train_.lash(e) && causes_.cam == SeparationCause::rebound ? e.gap : 0.0;
  }

  // Takes up the rebounds decided since the last sample (dynamics/separation_cause.h):
  // a float's time, gap and integral join the float's; a take-up bounce's are dropped.
  void take_up_decisions() {
    if (causes_.decisions == decisions_seen_) return;
    decisions_seen_ = causes_.decisions;
    if (causes_.decided == SeparationCause::float_gap) {
      float_time_ += rebound_time_;
      float_gap_.integral += rebound_gap_.integral;
      rebound_max_gap_ = std::max(rebound_max_gap_, rebound_gap_max_);
      if (rebound_time_ > 0.0) {
        floated_in_rebound_ = true;
        train_.lets_go_at("cam contact", rebound_theta_);
      }
    }
    rebound_time_ = 0.0;
    rebound_gap_.integral = 0.0;
    rebound_gap_max_ = -std::numeric_limits<double>::infinity();
    rebound_theta_ = std::numeric_limits<double>::quiet_NaN();
  }

  // Folds the extremes' values `x` at t [s] into the window's records.
  void fold_extremes(double t, const StepExtremes::Values& x) {
    if (t < t_eval_) return;
    extremes_.fold(x);
    if (causes_.cam == SeparationCause::rebound) rebound_gap_max_ = std::max(rebound_gap_max_, x[0]);
  }

  // Folds the train at the evaluation `e` at t [s] into its records.
  void fold_train(double t, const Evaluation& e) {
    if (t < t_eval_) return;
    train_.fold(e);
    if (m_.peak_spring_stress) m_.peak_spring_stress = std::max(*m_.peak_spring_stress, spring_stress(model_, e));
  }

  // Folds the energy of `e` with the quadratures qs_ into the balance;
  // returns the deviation E(t) − E(0) [J].
  double fold_energy(const Evaluation& e) {
    const EnergyTerms terms = energy_terms(model_, e);
    const double energy = terms.kinetic + terms.spring + terms.gravity + terms.contact - qs_[quadrature::drive_work] +
                          qs_[quadrature::damper_work] + qs_[quadrature::hysteresis_work] +
                          qs_[quadrature::friction_work] - qs_[quadrature::external_work];
    if (!energy_initialised_) {
      energy0_ = energy;
      energy_initialised_ = true;
    }
    energy_scale_ = std::max(energy_scale_, terms.kinetic + terms.spring + std::abs(qs_[quadrature::drive_work]) +
                                                std::abs(qs_[quadrature::external_work]));
    energy_max_dev_ = std::max(energy_max_dev_, std::abs(energy - energy0_));
    return energy - energy0_;
  }

  const Model& model_;
  Workspace& ws_;
  StateSource* source_;
  const RunState& y0_;
  const RunQuadratures& q0_;
  const double t_eval_;  // start of the evaluated window [s]
  const bool every_step_;
  const SeparationCauses& causes_;  // why the cam's gap is open (dynamics/separation_cause.h)
  Metrics& m_;
  bool stepped_ = false;
  Evaluation ev_, probe_;
  StepExtremes extremes_;
  StepExtremes::Values start_{}, mid_{};  // the extremes' values at the step's start and middle
  double step_start_ = 0.0;               // [s]
  double flight_gap_ = 0.0;               // the largest gap inside the flights in the window [m]
  RunState ys_{};
  RunQuadratures qs_{};
  double energy0_ = 0.0, energy_scale_ = 0.0, energy_max_dev_ = 0.0;  // [J]
  bool energy_initialised_ = false;
  double separated_time_ = 0.0;  // within the evaluated window [s]
  double float_time_ = 0.0;      // of it, in float [s]
  // The drive torque squared at the step's start and middle [N² m²], its integral over the window [N² m² s].
  WindowSimpson torque_squared_;  // the drive torque squared [N² m²], its integral [N² m² s]
  WindowSimpson float_gap_;       // the float gap [m], its integral [m s]
  WindowSimpson rebound_gap_;     // the gap of a rebound not decided yet [m], its integral [m s]
  // The rebound not decided yet: its time in the window [s], its largest gap
  // [m] and its first cam angle there [rad]; the largest gap of those that flew [m].
  double rebound_time_ = 0.0, rebound_gap_max_ = -std::numeric_limits<double>::infinity();
  double rebound_theta_ = std::numeric_limits<double>::quiet_NaN();
  double rebound_max_gap_ = 0.0;
  bool floated_in_rebound_ = false;
  long decisions_seen_ = 0;
  TrainObserver train_;
};

/// One row of a time series from an evaluation at t [s].
void push_row(const Model& model, const Evaluation& ev, TimeSeries& series, double t);

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
      drive_work_at_eval_ = observer_.drive_work_quadrature();
      eval_start_seen_ = true;
    }
  }

  // The energy residual columns, once the run's energy scale is known.
  void finish() {
    for (double de : energy_deviation_) result_.series.energy_residual.push_back(observer_.residual(de));
    for (double de : sample_energy_deviation_) result_.samples.energy_residual.push_back(observer_.residual(de));
  }

  double separation_integral_at_eval() const { return separation_integral_at_eval_; }  // [m s]
  double drive_work_at_eval() const { return drive_work_at_eval_; }                    // [J]

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
  double drive_work_at_eval_ = 0.0;  // [J]
  bool eval_start_seen_;
};

}  // namespace camdyn
