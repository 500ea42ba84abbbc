#include "dynamics/run_plan.h"

#include <cmath>
#include <numbers>
#include <sstream>

#include "common/constants.h"

namespace camdyn {

std::string where(const Model& model, double t) {
  std::ostringstream s;
  s << "at t = " << t << " s, cam angle " << std::fmod(model.theta(t) * kRadToDeg, 360.0) << " deg";
  return s.str();
}

RunQuadratures quadrature_integrand(const Evaluation& ev) {
  RunQuadratures f;
  quadrature_derivative(ev, f.data());
  return f;
}

RunPlan plan_run(const SceneConfig& scene, const Model& model) {
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

IntegratorOptions integrator_options(const IntegratorConfig& ic, const RunPlan& p) {
  IntegratorOptions io;
  io.method = ic.method;
  io.order = ic.order.value_or(0);
  io.rtol = ic.rtol;
  io.atol = ic.atol;
  io.max_step = p.max_step;
  io.fixed_step = ic.step.value_or(0.0);
  io.analytic_jacobian = ic.jacobian == JacobianSource::analytic;
  return io;
}

}  // namespace camdyn
