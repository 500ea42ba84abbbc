#include "dynamics/map_sensitivity.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "common/errors.h"
#include "dynamics/contact_events.h"
#include "dynamics/initial_state.h"
#include "dynamics/run_plan.h"
#include "integrate/cvode_integrator.h"

namespace camdyn {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// More roots than this per revolution: impacts accumulating (chatter), where
// the event sequence of neighbouring starts differs and no Jacobian exists.
constexpr long kMaxEventsPerRevolution = 200;
// Step of the central differences of the root functions at an event,
// relative to each state's scale (truncation ~1e-12, rounding ~1e-9 of the
// partials: g is a difference of positions of the base radius's size).
constexpr double kRootStep = 1e-6;
// The step of the differences in an approach speed, relative to it (see
// SensitivityOde::parameter_rate).
constexpr double kApproachStep = 1e-3;
// An event whose crossing speed ∇g·f⁻ + ∂g/∂t is below this fraction of its
// terms' sizes grazes: the event time is not differentiable there.
constexpr double kGrazing = 1e-6;

// The scene's ODE with the forward sensitivities' right-hand side. Besides
// the state the run carries the approach speeds of the damping laws
// (parameter 0: the cam contact's v₀, 1 + r: train root r's), constant
// between events; their sensitivities to x(0) are the rows of
// parameter_rows(), which drive the sensitivities through ∂f/∂v₀.
class SensitivityOde final : public OdeSystem {
 public:
  SensitivityOde(const Model& model, Workspace& ws, int columns)
      : model_(model),
        ws_(ws),
        n_(model.layout.size),
        jacobian_(n_, n_),
        rate_(n_),
        plus_(n_),
        minus_(n_),
        parameter_rows_(MatrixXd::Zero(1 + model.train.roots, columns)) {}

  int size() const override { return n_; }
  int root_count() const override { return model_.root_count(); }
  bool has_jacobian() const override { return true; }
  int rhs(double t, const double* y, double* y_dot) override {
    evaluate(model_, ws_, t, y, ev_);
    if (!ev_.tracking_ok) return 1;  // recoverable: a smaller step
    state_derivative(model_, ev_, y_dot);
    return 0;
  }
  int roots(double t, const double* y, double* g) override {
    evaluate(model_, ws_, t, y, ev_);
    root_functions(model_, ws_, ev_, g);
    return 0;
  }
  int jacobian(double t, const double* y, double* J) override {
    state_jacobian(model_, ws_, t, y, J);
    return 0;
  }
  // ṡ_j = ∂f/∂x s_j + Σ_p ∂f/∂v₀_p W_pj. Allocates nothing.
  int sensitivity_rhs(double t, const double* y, int count, const double* const* s, double* const* s_dot) override {
    state_jacobian(model_, ws_, t, y, jacobian_.data());
    for (int j = 0; j < count; ++j)
      Eigen::Map<VectorXd>(s_dot[j], n_).noalias() = jacobian_ * Eigen::Map<const VectorXd>(s[j], n_);
    for (int p = 0; p < parameter_rows_.rows(); ++p) {
      if (parameter_rows_.row(p).isZero(0.0)) continue;
      if (const int flag = parameter_rate(t, y, p); flag != 0) return flag;
      for (int j = 0; j < count; ++j) Eigen::Map<VectorXd>(s_dot[j], n_) += parameter_rows_(p, j) * rate_;
    }
    return 0;
  }

  // Approach speed p [m/s].
  double& parameter(int p) { return p == 0 ? ws_.v0 : ws_.train.v0[static_cast<std::size_t>(p - 1)]; }
  MatrixXd& parameter_rows() { return parameter_rows_; }
  const Evaluation& evaluated(double t, const double* y) {
    evaluate(model_, ws_, t, y, ev_);
    return ev_;
  }

 private:
  // rate_ = ∂f/∂v₀_p at (t, y). f is affine in 1/v₀ (the damping laws'
  // factor 1 + χ δ̇/v₀, carried linearly to every rate), and for f = a + b/v₀
  // the central difference over ±h is exact once scaled by 1 − (h/v₀)²; so
  // a wide step (h = 1e-3 v₀) keeps the rounding of f out of the
  // sensitivities (a step of 1e-6 v₀ put 1e-10 of f's size into them as
  // noise, and the error test chased it with tiny steps). Only where the
  // force clamp switches within ±h (|1 + χ δ̇/v₀| < 1e-3, where the force is
  // nearly zero) is the difference not exact.
  int parameter_rate(double t, const double* y, int p) {
    double& v0 = parameter(p);
    const double saved = v0, h = kApproachStep * saved;
    v0 = saved + h;
    const int up = rhs(t, y, plus_.data());
    v0 = saved - h;
    const int down = rhs(t, y, minus_.data());
    v0 = saved;
    if (up != 0 || down != 0) return 1;
    rate_ = (plus_ - minus_) * ((1.0 - kApproachStep * kApproachStep) / (2.0 * h));
    return 0;
  }

  const Model& model_;
  Workspace& ws_;
  const int n_;
  Evaluation ev_;
  MatrixXd jacobian_;
  VectorXd rate_, plus_, minus_;
  MatrixXd parameter_rows_;
};

// The root functions at (t, y) and the closing rates that set approach
// speeds, by root: the cam gap's ġ and the train gaps' (none for the clamp switch).
struct RootSample {
  std::array<double, Model::kMaxRoots> g{}, rate{};
};

// The approach speed (SensitivityOde::parameter) a closing gap resets: the
// cam contact's (0) or train root r's (1 + r).
int approach_parameter(const RootSlot& slot) { return slot.role == RootRole::train_gap ? 1 + slot.index : 0; }

// The root functions' partials at an event, by central differences over
// the state (steps kRootStep × each state's scale), the time and the
// approach speeds that have sensitivities.
struct RootPartials {
  VectorXd g_x, rate_x;            // ∇g, ∇ġ of the root that fired
  double g_t = 0.0, rate_t = 0.0;  // ∂g/∂t, ∂ġ/∂t
  VectorXd g_p;                    // ∂g/∂v₀_p
};

// One sensitivity run: the ODE, its integrator, the sensitivities and the
// event bookkeeping (as simulation.cc keeps it, so that impacts count alike).
class SensitivityRun {
 public:
  SensitivityRun(const PoincareMap& map, Workspace& ws, SensitivityOde& ode, CvodeIntegrator& integrator, MatrixXd& s,
                 std::vector<double>& y)
      : model_(map.model()), ws_(ws), ode_(ode), integrator_(integrator), s_(s), y_(y) {
    const int n = model_.layout.size;
    step_scale_.assign(static_cast<std::size_t>(n), 1.0);
    for (std::size_t j = 0; j < map.coordinate_indices().size(); ++j)
      step_scale_[static_cast<std::size_t>(map.coordinate_indices()[j])] = map.scales()[j];
    const Evaluation& ev = ode_.evaluated(0.0, y_.data());
    lash_open_ = ev.gap > 0.0 && model_.train.present() && model_.train.rests_on_seat(ev.train, 0);
    separated_ = ev.gap > 0.0 && !lash_open_;
  }

  // The event at the integrator's root: the approach speeds it resets, the
  // sensitivities' jump, the restart. Empty, or why the run cannot be trusted.
  std::string handle_event(double t) {
    ++events_;
    std::array<int, Model::kMaxRoots> directions{};
    integrator_.root_info(directions.data());
    int fired = -1;
    for (int r = 0; r < model_.root_count(); ++r) {
      if (directions[static_cast<std::size_t>(r)] == 0) continue;
      if (fired >= 0) return "two events at once";
      fired = r;
    }
    if (fired < 0) return {};
    const int n = model_.layout.size;
    VectorXd f_minus(n), f_plus(n);
    if (ode_.rhs(t, y_.data(), f_minus.data()) != 0) return "the right-hand side failed at an event";
    const RootPartials d = partials(t, fired);
    const double crossing = d.g_x.dot(f_minus) + d.g_t;
    const double size = d.g_x.cwiseProduct(f_minus).cwiseAbs().sum() + std::abs(d.g_t);
    if (!(std::abs(crossing) > kGrazing * size)) return "a grazing event";
    MatrixXd& w = ode_.parameter_rows();
    // dt_e/dx(0): the event time's sensitivity (a row).
    const Eigen::RowVectorXd tau = -(d.g_x.transpose() * s_ + d.g_p.transpose() * w) / crossing;
    const bool closing = directions[static_cast<std::size_t>(fired)] < 0;
    const RootSlot slot = model_.root_slot(fired);
    const Evaluation ev = ode_.evaluated(t, y_.data());
    switch (slot.role) {
      case RootRole::contact_gap:
        if (closing) {
          count_onset(-ev.gap_rate);
          reset_approach(approach_parameter(slot), -ev.gap_rate, model_.contact.reference_velocity, d, f_minus, tau);
        } else {
          lash_open_ = model_.train.present() && model_.train.rests_on_seat(ev.train, 0);
          separated_ = !lash_open_;
        }
        break;
      case RootRole::contact_clamp:  // the force switches on or off: the saltation alone
        break;
      case RootRole::train_gap:
        if (!closing) break;
        if (const TrainElement& e = train_element_of_root(model_.train, slot.index);
            e.law == TrainElement::Law::contact)
          reset_approach(approach_parameter(slot), -ev.train.gap_rate[static_cast<std::size_t>(slot.index)],
                         e.contact.reference_velocity, d, f_minus, tau);
        break;
    }
    if (ode_.rhs(t, y_.data(), f_plus.data()) != 0) return "the right-hand side failed after an event";
    s_ += (f_plus - f_minus) * tau;  // the saltation matrix (H = I: the state is continuous)
    integrator_.reinit(t, y_.data(), s_.data());
    return {};
  }

  long impacts() const { return impacts_; }
  long events() const { return events_; }

 private:
  RootSample sample(double t, const double* y) {
    RootSample out;
    const Evaluation& ev = ode_.evaluated(t, y);
    root_functions(model_, ws_, ev, out.g.data());
    for (int r = 0; r < model_.root_count(); ++r) {
      const RootSlot slot = model_.root_slot(r);
      double& rate = out.rate[static_cast<std::size_t>(r)];
      switch (slot.role) {
        case RootRole::contact_gap:
          rate = ev.gap_rate;
          break;
        case RootRole::contact_clamp:  // no closing rate
          break;
        case RootRole::train_gap:
          rate = ev.train.gap_rate[static_cast<std::size_t>(slot.index)];
          break;
      }
    }
    return out;
  }

  RootPartials partials(double t, int root) {
    const int n = model_.layout.size;
    const std::size_t r = static_cast<std::size_t>(root);
    RootPartials d;
    d.g_x.resize(n);
    d.rate_x.resize(n);
    std::vector<double> y = y_;
    for (int i = 0; i < n; ++i) {
      const std::size_t iu = static_cast<std::size_t>(i);
      const double h = kRootStep * step_scale_[iu];
      y[iu] = y_[iu] + h;
      const RootSample up = sample(t, y.data());
      y[iu] = y_[iu] - h;
      const RootSample down = sample(t, y.data());
      y[iu] = y_[iu];
      d.g_x[i] = (up.g[r] - down.g[r]) / (2.0 * h);
      d.rate_x[i] = (up.rate[r] - down.rate[r]) / (2.0 * h);
    }
    const double h_t = kRootStep / model_.omega;  // [s]
    const RootSample later = sample(t + h_t, y_.data()), earlier = sample(t - h_t, y_.data());
    d.g_t = (later.g[r] - earlier.g[r]) / (2.0 * h_t);
    d.rate_t = (later.rate[r] - earlier.rate[r]) / (2.0 * h_t);
    MatrixXd& w = ode_.parameter_rows();
    d.g_p = VectorXd::Zero(w.rows());
    for (int p = 0; p < w.rows(); ++p) {
      if (w.row(p).isZero(0.0)) continue;
      double& v0 = ode_.parameter(p);  // g, too, is affine in 1/v₀ (the clamp switch)
      const double saved = v0, h = kApproachStep * saved;
      v0 = saved + h;
      const double g_up = sample(t, y_.data()).g[r];
      v0 = saved - h;
      const double g_down = sample(t, y_.data()).g[r];
      v0 = saved;
      d.g_p[p] = (g_up - g_down) * ((1.0 - kApproachStep * kApproachStep) / (2.0 * h));
    }
    return d;
  }

  // An onset resets approach speed p to max(approach, floor) (docs/model.md
  // §6); its sensitivity row is the total derivative of −ġ at the event,
  // −(∇ġ·Φ + (∇ġ·f⁻ + ∂ġ/∂t) dt_e/dx(0)), or zero where the floor holds.
  void reset_approach(int p, double approach, double floor, const RootPartials& d, const VectorXd& f_minus,
                      const Eigen::RowVectorXd& tau) {
    ode_.parameter(p) = std::max(approach, floor);
    MatrixXd& w = ode_.parameter_rows();
    if (approach > floor)
      w.row(p) = -(d.rate_x.transpose() * s_ + (d.rate_x.dot(f_minus) + d.rate_t) * tau);
    else
      w.row(p).setZero();
  }

  void count_onset(double approach) {
    if (lash_open_) {
      lash_open_ = separated_ = false;
      return;
    }
    if (classify_onset(separated_, approach).impact) ++impacts_;
    separated_ = false;
  }

  const Model& model_;
  Workspace& ws_;
  SensitivityOde& ode_;
  CvodeIntegrator& integrator_;
  MatrixXd& s_;
  std::vector<double>& y_;
  std::vector<double> step_scale_;  // per state [its unit]
  bool separated_ = false, lash_open_ = false;
  long impacts_ = 0, events_ = 0;
};

// Φ(0) for the seeds: column c is the start's change for the change
// seeds.col(c) of the coordinates [SI]; the pair parameter u, which the start
// finds from q (f(u, q, θ) = 0), follows it by ∂u/∂q = −f_q/f_u, which is
// ∂u̇/∂q̇ of the state Jacobian (u̇ = (−α f − f_q q̇ − f_θ θ̇)/f_u).
MatrixXd initial_sensitivities(const PoincareMap& map, Workspace& ws, const std::vector<double>& y,
                               const MatrixXd& seeds) {
  const Model& model = map.model();
  const int n = model.layout.size, m = map.dimension();
  MatrixXd s = MatrixXd::Zero(n, seeds.cols());
  for (int j = 0; j < m; ++j) s.row(map.coordinate_indices()[static_cast<std::size_t>(j)]) = seeds.row(j);
  if (model.layout.u) {
    MatrixXd jacobian(n, n);
    state_jacobian(model, ws, 0.0, y.data(), jacobian.data());
    const int u = *model.layout.u;
    s.row(u) = jacobian(u, StateLayout::kQDot) * s.row(StateLayout::kQ);
  }
  return s;
}

// The run itself, its sensitivities started from `seeds` (dimension() × c):
// fills `out` (ok only at its end) with (∂P^k/∂x) seeds.
void run_sensitivities(const PoincareMap& map, const SectionPoint& p, int k, const MatrixXd& seeds, Workspace& ws,
                       MapJacobian& out) {
  const Model& model = map.model();
  const SceneConfig scene = map.scene_for(k);
  const RunPlan plan = plan_run(scene, model);
  const int n = model.layout.size, m = map.dimension();
  prepare_workspace(model, ws);
  std::vector<double> y(static_cast<std::size_t>(n));
  if (const RunFailure f = given_state(model, ws, map.start(p), y.data())) {
    out.reason = f.message;
    return;
  }
  MatrixXd s = initial_sensitivities(map, ws, y, seeds);
  const int c = static_cast<int>(seeds.cols());
  SensitivityOde ode(model, ws, c);
  IntegratorOptions options = integrator_options(scene.integrator, plan);
  options.method = IntegrationMethod::cvode_bdf;
  options.analytic_jacobian = true;
  CvodeIntegrator integrator(ode, options, 0.0, y.data());
  integrator.enable_sensitivities(c, s.data());
  SensitivityRun run(map, ws, ode, integrator, s, y);
  const double drift_tolerance = std::max(1e-9, 10.0 * scene.integrator.rtol);  // [rad], as the simulation's
  double t = 0.0;
  while (t < plan.t_end) {
    const Integrator::Result result = integrator.step(plan.t_end);
    t = integrator.time();
    std::copy(integrator.state(), integrator.state() + n, y.begin());
    if (result == Integrator::Result::root) {
      integrator.sensitivities(s.data());
      if (std::string why = run.handle_event(t); !why.empty()) {
        out.reason = why + " " + where(model, t);
        return;
      }
    }
    if (!(ode.evaluated(t, y.data()).pair_drift <= drift_tolerance)) {
      out.reason = "the contact pair drifted (the run would project it) " + where(model, t);
      return;
    }
    if (run.events() > kMaxEventsPerRevolution * k) {
      out.reason = "events accumulating (chatter) " + where(model, t);
      return;
    }
    if (integrator.counters().steps > scene.integrator.max_steps) {
      out.reason = "step budget exceeded " + where(model, t);
      return;
    }
    if (result == Integrator::Result::stop) break;
  }
  integrator.sensitivities(s.data());
  out.end = map.point(y, ws.v0, ws.motor_phase, k);
  out.jacobian.resize(m, c);
  for (int i = 0; i < m; ++i) out.jacobian.row(i) = s.row(map.coordinate_indices()[static_cast<std::size_t>(i)]);
  out.impacts = run.impacts();
  out.events = run.events();
  out.steps = integrator.counters().steps;
  out.ok = out.jacobian.allFinite();
  if (!out.ok) out.reason = "the sensitivities are not finite";
}

}  // namespace

std::string sensitivity_unsupported(const PoincareMap& map) {
  const Model& m = map.model();
  if (!m.exact_jacobian() || m.layout.v) return "the general pair form has no exact state Jacobian";
  if (m.tracking != Tracking::differential) return "Newton tracking is not covered";
  if (m.friction.present || m.support.present()) return "friction can stick";
  if (m.drive.shaft()) return "a shaft drive is not covered";
  return {};
}

namespace {

// One run from `seeds`, or why none can be trusted.
MapJacobian seeded_run(const PoincareMap& map, const SectionPoint& p, int k, const MatrixXd& seeds, Workspace& ws) {
  MapJacobian out;
  out.reason = sensitivity_unsupported(map);
  if (!out.reason.empty()) return out;
  try {
    run_sensitivities(map, p, k, seeds, ws, out);
  } catch (const NumericalError& e) {  // CVODES gave up
    out.ok = false;
    out.reason = e.what();
  }
  return out;
}

}  // namespace

MapJacobian sensitivity_jacobian(const PoincareMap& map, const SectionPoint& p, int k, Workspace& ws) {
  // Column j seeded with scale_j (the sensitivities of the state's size, as
  // the error control weighs them), then divided by it.
  const VectorXd scales = Eigen::Map<const VectorXd>(map.scales().data(), map.dimension());
  MapJacobian out = seeded_run(map, p, k, MatrixXd(scales.asDiagonal()), ws);
  if (out.ok) out.jacobian.array().rowwise() /= scales.transpose().array();
  return out;
}

MapJacobian sensitivity_product(const PoincareMap& map, const SectionPoint& p, int k, const MatrixXd& directions,
                                Workspace& ws) {
  return seeded_run(map, p, k, directions, ws);
}

}  // namespace camdyn
