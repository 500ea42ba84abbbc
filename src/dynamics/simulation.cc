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
#include <stdexcept>

#include "common/constants.h"
#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/contact_events.h"
#include "dynamics/free_flight.h"
#include "dynamics/initial_state.h"
#include "dynamics/series_columns.h"
#include "dynamics/step_quadrature.h"
#include "dynamics/window_observer.h"
#include "geometry/check_text.h"
#include "integrate/integrator.h"

namespace camdyn {

namespace {

constexpr int kMaxState = StateLayout::kMax;

using State = RunState;
using Quadratures = RunQuadratures;
using Failure = RunFailure;
using Clock = std::chrono::steady_clock;
// Fewest states for which a banded linear solver is tried.
constexpr int kMinBandedStates = 10;
// The directions of the roots the integrator found, by root (Model::root_slot()).
using RootDirections = std::array<int, Model::kMaxRoots>;

// The quadratures a model reports (docs/model.md §7; Quadratures holds all of
// them, by index): the drive's work only where the cam turns or a motor
// drives it, the damper's only with a damper, the contact hysteresis only for
// a dissipative law (the cam contact's, a train seat's or stop's, a damped
// one-sided link's), the friction work only with friction, the separation
// integral always, the external work only with a gas load. A train's spring
// segments and body dampers count as dampers. The others have a
// zero integrand.
bool quadrature_reported(const Model& m, int i) {
  switch (i) {
    case 0:
      return m.drive.works(m.omega);
    case 1:
      return m.forces.damper().present() || m.drive.dissipates() ||
             std::any_of(m.train.elements.begin(), m.train.elements.end(),
                         [](const TrainElement& e) { return e.law == TrainElement::Law::spring && e.damping > 0.0; });
    case 2:
      return force_form(m.contact.model) != ForceForm::elastic ||
             std::any_of(m.train.elements.begin(), m.train.elements.end(), [](const TrainElement& e) {
               return (e.law == TrainElement::Law::one_sided && e.damping > 0.0) ||
                      (e.law == TrainElement::Law::contact && force_form(e.contact.model) != ForceForm::elastic);
             });
    case 3:
      return m.friction.present || m.support.present();
    case 5:
      return m.train.time_dependent();
    default:
      return true;
  }
}

Quadratures integrand(const Evaluation& ev) { return quadrature_integrand(ev); }

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
  // A train long enough for a banded solve to pay (a spring's chain of lumps).
  int bandwidth() const override {
    if (!model_.train.has_coordinates() || model_.layout.size < kMinBandedStates) return -1;
    const int band = train_jacobian_bandwidth(model_.train, model_.layout.core_size);
    return 4 * band + 2 < model_.layout.size ? band : -1;
  }
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
      q[quadrature::damper_work] = p.damper_work;
      q[quadrature::separation] = p.separation;
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
  bool lash_open = false;      // the cam's gap is open while the follower rests on a seat (docs/model.md §12)
  SeparationCauses causes;     // why each open gap opened (dynamics/separation_cause.h)
  double last_progress = 0.0;  // wall time of the last progress report [s]
  IntegratorSource* integrator_source = nullptr;
  FlightSource* flight_source = nullptr;
  FlightTrack* flight = nullptr;         // null: flights are integrated
  StepQuadrature* quadrature = nullptr;  // null: no quadratures
  const Model* newton_model = nullptr;   // the model with Newton tracking, for the drift projection
  bool last_flight_short = false;        // the last flight landed at once: integrate the next one
  bool ended_in_flight = false;          // the run's end came in a flight
};

// Whether the train has rested on a seat since the law last rose to the
// take-up height: a gap that opens below it afterwards is a seat bounce.
void follow_seating(const Model& model, const Evaluation& ev, SeparationCauses& causes) {
  if (!model.take_up.applies) return;
  const double lift = model.law->eval(ev.theta).s - model.take_up.base;  // [m | rad]
  if (lift >= model.take_up.take_up)
    causes.seated_since_take_up = false;
  else if (model.train.rests_on_seat(ev.train, 0))
    causes.seated_since_take_up = true;
}

// Decides the rebound in flight as `cause` (take_up or float_gap): its
// separation's event, a take-up bounce counted where it opened in the window;
// the observer takes the decision up at its next sample.
void decide_rebound(const RunContext& run, LoopState& loop, SeparationCause cause) {
  SeparationCauses& causes = loop.causes;
  ContactEvent& opened = run.result.events[causes.rebound_event];
  opened.cause = cause;
  if (cause == SeparationCause::take_up && opened.time >= run.plan.t_eval && run.result.metrics.train)
    ++run.result.metrics.train->take_up_bounces;
  causes.cam = cause;
  causes.decided = cause;
  ++causes.decisions;
}

// A contact onset at t (docs/model.md §6; dynamics/contact_events.h): an
// impact, or a graze or re-entry recorded but not counted; the episode's
// approach speed v₀ from the gap's closing rate. It carries the cause of
// the separation it ends (dynamics/separation_cause.h).
void record_onset(const RunContext& run, const Evaluation& ev, double t, LoopState& loop) {
  SimulationResult& result = run.result;
  const double approach = -ev.gap_rate;
  run.ws.v0 = std::max(approach, run.model.contact.reference_velocity);
  SeparationCauses& causes = loop.causes;
  SeparationCause cause = causes.cam;
  if (cause == SeparationCause::rebound) {  // a rebound lands: about as it left, or it flew
    const double bound = std::max(causes.chain_speed, kReboundLandingFactor * causes.rebound_speed);  // [m/s]
    cause = approach <= bound ? SeparationCause::take_up : SeparationCause::float_gap;
    decide_rebound(run, loop, cause);
  }
  causes.cam = SeparationCause::none;
  if (loop.lash_open) {  // the cam takes up the lash (docs/model.md §12)
    causes.chain_speed = approach;
    result.events.push_back({t, ev.theta * kRadToDeg, true, approach, false, ev.v, false, true});
    loop.lash_open = loop.separated = false;
    return;
  }
  causes.chain_speed = cause == SeparationCause::take_up ? approach : 0.0;
  const OnsetClass onset = classify_onset(loop.separated, approach);
  if (onset.impact && t >= run.plan.t_eval) {
    ++result.metrics.impact_count;
    result.metrics.max_impact_velocity = std::max(result.metrics.max_impact_velocity, approach);
  }
  result.events.push_back({t, ev.theta * kRadToDeg, true, approach, onset.impact, ev.v, onset.grazing, false, cause});
  loop.separated = false;
}

// A gap opening at t, the cam contact's (body −1) or body `body`'s link, off
// every seat: its cause (dynamics/separation_cause.h), a take-up bounce in
// the window counted.
SeparationCause classify_opening(const RunContext& run, const Evaluation& ev, double t, const LoopState& loop) {
  const Model& model = run.model;
  const SeparationCause cause =
      opening_cause(model.take_up, model.law->eval(ev.theta), loop.causes.seated_since_take_up);
  if (cause == SeparationCause::take_up && t >= run.plan.t_eval && run.result.metrics.train)
    ++run.result.metrics.train->take_up_bounces;
  return cause;
}

// A link opening at t off every seat: classified as the cam's gap, but
// above the take-up window, in a cam contact episode that began with the
// take-up's impact, where the law still accelerates the train onto the cam
// (s'' > 0: the held train's link force there is the spring's preload plus
// the body's inertia, which no spring loses), it is that impact's ringing:
// a take-up bounce, not float (docs/valvetrain.md).
SeparationCause classify_link_opening(const RunContext& run, const Evaluation& ev, double t, const LoopState& loop) {
  const Model& model = run.model;
  const bool ringing = loop.causes.chain_speed > 0.0 && model.law->eval(ev.theta).d2s > 0.0;
  if (!ringing) return classify_opening(run, ev, t, loop);
  const SeparationCause cause =
      opening_cause(model.take_up, model.law->eval(ev.theta), loop.causes.seated_since_take_up);
  if (cause != SeparationCause::float_gap) return classify_opening(run, ev, t, loop);
  if (t >= run.plan.t_eval && run.result.metrics.train) ++run.result.metrics.train->take_up_bounces;
  return SeparationCause::take_up;
}

// The cam contact's gap opening at t: a separation, or lash where the
// follower rests on a seat (docs/model.md §12); above the take-up window, a
// rebound of the take-up's impacts is decided where it lands.
void record_separation(const RunContext& run, const Evaluation& ev, double t, LoopState& loop) {
  const Model& model = run.model;
  SeparationCauses& causes = loop.causes;
  loop.lash_open = model.train.present() && model.train.rests_on_seat(ev.train, 0);
  loop.separated = !loop.lash_open;
  causes.cam = loop.separated ? classify_opening(run, ev, t, loop) : SeparationCause::none;
  // A rebound of the take-up's impacts: where the law accelerates the train
  // onto the cam (no spring can lose it there), or separating fast.
  if (causes.cam == SeparationCause::float_gap && causes.chain_speed > 0.0 &&
      (model.law->eval(ev.theta).d2s > 0.0 || ev.gap_rate >= kReboundSpeedShare * causes.chain_speed)) {
    causes.cam = SeparationCause::rebound;
    causes.rebound_event = run.result.events.size();
    causes.rebound_speed = ev.gap_rate;
  }
  run.result.events.push_back(
      {t, ev.theta * kRadToDeg, false, ev.gap_rate, false, ev.v, false, loop.lash_open, causes.cam});
}

// A train gap closing at t (docs/model.md §12): a seat's or stop's approach
// speed becomes its v₀; seat onsets and coil clashes in the window are counted.
void record_train_onset(const RunContext& run, const Evaluation& ev, double t, int root, LoopState& loop) {
  const FollowerTrain& train = run.model.train;
  const double approach = -ev.train.gap_rate[static_cast<std::size_t>(root)];
  const TrainElement& e = train_element_of_root(train, root);
  if (e.law == TrainElement::Law::contact) record_train_onset(train, run.ws.train, root, approach);
  const auto body = static_cast<std::size_t>(e.body);
  if (e.role == TrainRole::seat) loop.causes.seat_bouncing[body] = false;
  if (e.role == TrainRole::link) loop.causes.link[body] = SeparationCause::none;
  if (t < run.plan.t_eval || !(approach > 0.0) || !run.result.metrics.train) return;
  TrainMetrics& m = *run.result.metrics.train;
  if (e.role == TrainRole::seat) {
    ++m.seat_impacts;
    m.max_seating_velocity = std::max(m.max_seating_velocity, approach);
  } else if (e.role == TrainRole::clash) {
    ++m.coil_clashes;
  }
}

// A train gap opening at t: a body leaving its seat (a seat bounce where the
// law does not lift it) or a link opening off every seat (its cause). The
// gaps below a body that leaves its seat were lash and are separations now,
// of the seat bounce's cause or of the take-up window's.
void record_train_opening(const RunContext& run, const Evaluation& ev, double t, int root, LoopState& loop) {
  const Model& model = run.model;
  const TrainElement& e = train_element_of_root(model.train, root);
  const auto body = static_cast<std::size_t>(e.body);
  SeparationCauses& causes = loop.causes;
  if (e.role == TrainRole::link) {
    causes.link[body] =
        model.train.rests_on_seat(ev.train, e.body) ? SeparationCause::none : classify_link_opening(run, ev, t, loop);
    return;
  }
  if (e.role != TrainRole::seat) return;
  const bool bounce = leaves_seat_as_bounce(model.take_up, e.body, model.law->eval(ev.theta).s);
  if (bounce) {
    causes.seat_bouncing[body] = true;
    if (t >= run.plan.t_eval && run.result.metrics.train) ++run.result.metrics.train->seat_bounces;
  }
  const FollowerTrain& train = model.train;
  const auto open_as_lash = [&](std::size_t i) {  // link i open, its cause not set (it opened as lash)
    const int link_root = train.elements[static_cast<std::size_t>(train.bodies[i].link)].root;
    return causes.link[i] == SeparationCause::none && link_root >= 0 &&
           ev.train.gap[static_cast<std::size_t>(link_root)] > 0.0;
  };
  const bool cam_lash_ends = loop.lash_open && !train.rests_on_seat(ev.train, 0);
  bool links_lash = false;
  for (std::size_t i = 1; i <= body; ++i) links_lash = links_lash || open_as_lash(i);
  if (!cam_lash_ends && !links_lash) return;
  const SeparationCause below = bounce ? SeparationCause::seat_bounce : classify_opening(run, ev, t, loop);
  for (std::size_t i = 1; i <= body; ++i)
    if (open_as_lash(i)) causes.link[i] = below;
  if (!cam_lash_ends) return;
  // The cam's gap, open as lash, is a separation from here (events.csv says so).
  causes.cam = below;
  loop.lash_open = false;
  loop.separated = true;
  run.result.events.push_back({t, ev.theta * kRadToDeg, false, ev.gap_rate, false, ev.v, false, false, below});
}

// The roots the integrator stopped at (docs/model.md §6), in the model's
// order, each by its role: the cam contact's gap records a contact onset (an
// impact when the follower was separated) or a separation, and the train's
// gaps theirs. Returns whether the right-hand side changed, so that the
// integrator must restart.
bool handle_root(const RunContext& run, const Integrator& integrator, const Evaluation& ev, double t,
                 RootDirections& root_dirs, LoopState& loop) {
  const Model& model = run.model;
  bool restart = false;
  integrator.root_info(root_dirs.data());
  ++run.result.solver.events;
  for (int r = 0; r < model.root_count(); ++r) {
    const int dir = root_dirs[static_cast<std::size_t>(r)];
    if (dir == 0) continue;
    const RootSlot slot = model.root_slot(r);
    switch (slot.role) {
      case RootRole::contact_gap:
        if (dir < 0)  // gap closing: contact onset
          record_onset(run, ev, t, loop);
        else  // gap opening: separation (lash while the follower rests on a seat)
          record_separation(run, ev, t, loop);
        restart = true;
        break;
      case RootRole::contact_clamp:  // the force clamp switches
        if (ev.delta > 0.0) restart = true;
        break;
      case RootRole::train_gap:  // a force switches on or off (its damping term jumps)
        if (dir < 0)
          record_train_onset(run, ev, t, slot.index, loop);
        else
          record_train_opening(run, ev, t, slot.index, loop);
        restart = true;
        break;
    }
  }
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
  if (integrator.steps() > ic.max_steps)
    return {Termination::step_budget, "step budget of " + std::to_string(ic.max_steps) +
                                          " steps (integrator.max_steps) exceeded " + where(run.model, t)};
  const Clock::time_point now = Clock::now();
  const double wall = std::chrono::duration<double>(now - run.wall_start).count();  // [s]
  if (wall > ic.max_wall_time_s)
    return {Termination::wall_time_budget, "wall-time budget of " + std::to_string(ic.max_wall_time_s) +
                                               " s (integrator.max_wall_time_s) exceeded " + where(run.model, t)};
  if (study_budget_exhausted(now))
    return {Termination::wall_time_budget, study_budget_text() + " " + where(run.model, t)};
  if (wall - last_progress > 0.25) {
    last_progress = wall;
    if (run.options.progress) run.options.progress(t / run.plan.t_end);
    poll_interrupt();  // Ctrl-C in the Python module (common/study_budget.h)
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
  start.damper_work = loop.q[quadrature::damper_work];
  start.separation = loop.q[quadrature::separation];
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
  loop.q[quadrature::damper_work] = end.damper_work;
  loop.q[quadrature::separation] = end.separation;
  run.ws.u_warm = end.u;
  observer.read_from(*loop.integrator_source);
  loop.last_flight_short = landed && end.t - t_start < 1e-9 * (run.plan.max_step + end.t);
  loop.ended_in_flight = !landed;
  if (landed) {
    ++run.result.solver.events;
    record_onset(run, ode.evaluated(end.t, loop.y.data()), end.t, loop);
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
  loop.lash_open = ev.gap > 0.0 && model.train.present() && model.train.rests_on_seat(ev.train, 0);
  loop.separated = ev.gap > 0.0 && !loop.lash_open;
  follow_seating(model, ev, loop.causes);
  if (loop.separated) loop.causes.cam = opening_cause(model.take_up, model.law->eval(ev.theta), true);
  RootDirections root_dirs{};
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
    follow_seating(model, ev, loop.causes);
    if (result_kind == Integrator::Result::root) restart = handle_root(run, integrator, ev, t, root_dirs, loop);
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
  result.metrics.mean_drive_power = kUnknown;
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
                          loop.causes, run.result.metrics);
  SeriesRecorder recorder(model, run.plan, run.options, observer, run.result);
  Failure failure;
  try {
    failure = integrate(run, ode, integrator, loop, observer, recorder);
    // Still in flight at the end: a rebound not decided is taken as float (never hide flight).
    if (loop.causes.cam == SeparationCause::rebound) decide_rebound(run, loop, SeparationCause::float_gap);
    observer.publish_extremes();
    if (!failure) {
      observer.finish(run.plan.t_end, loop.q[quadrature::separation] - recorder.separation_integral_at_eval(),
                      loop.q[quadrature::drive_work] - recorder.drive_work_at_eval());
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
  static constexpr const char* kNames[] = {"drive_work",    "damper_work", "hysteresis_work",
                                           "friction_work", nullptr,       "external_work"};
  std::vector<std::string> names;
  for (int i = 0; i < Model::kQuadratures; ++i)
    if (kNames[i] && quadrature_reported(model, i)) names.emplace_back(kNames[i]);
  return names;
}

void throw_if_failed(const SimulationResult& result) {
  if (!result.solver.converged()) throw NumericalError(result.solver.message);
}

std::vector<std::string> TimeSeries::column_names() {
  std::vector<std::string> names;
  for (const SeriesColumn& c : kSeriesColumns) names.emplace_back(c.name);
  return names;
}

std::vector<const std::vector<double>*> TimeSeries::columns() const {
  return {&time, &cam_angle_deg, &follower_position, &follower_velocity, &follower_acceleration, &kinematic_position,
          &gap,  &contact_force, &friction_force,    &energy_residual,   &contact_offset,        &cam_speed_rpm};
}

std::vector<std::string> TimeSeries::all_names() const {
  std::vector<std::string> names = column_names();
  names.insert(names.end(), train_names.begin(), train_names.end());
  return names;
}

std::vector<const std::vector<double>*> TimeSeries::all_columns() const {
  std::vector<const std::vector<double>*> all = columns();
  for (const std::vector<double>& column : train) all.push_back(&column);
  return all;
}

SimulationResult simulate(const SceneConfig& scene, const Model& model, Workspace& ws,
                          const SimulationOptions& options) {
  const Clock::time_point wall_start = Clock::now();
  const RunPlan p = plan_run(scene, model);
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

SimulationResult simulate_scene(const SceneConfig& scene, const std::string& file, const SimulationOptions& options) {
  return simulate_scene(*build_cam_geometry(scene, file), scene, file, options);
}

SimulationResult simulate_scene(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file,
                                const SimulationOptions& options) {
  return simulate_scene(build_model(geometry, scene, file), scene, options);
}

SimulationResult simulate_scene(const Model& model, const SceneConfig& scene, const SimulationOptions& options) {
  Workspace ws;
  SimulationResult result = simulate(scene, model, ws, options);
  estimate_error(scene, model, result);
  return result;
}

}  // namespace camdyn
