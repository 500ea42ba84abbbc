// One interface over every integration method camdyn offers (docs/model.md §6):
// CVODES BDF and Adams, ARKODE explicit (adaptive embedded ERK) and implicit
// (DIRK) Runge–Kutta, Dormand and Prince's order-8 pair (DOP853), and a
// fixed-step classical RK4 baseline. All take one
// step at a time, stop at roots of the system's root functions (event
// location), give dense output over the last step, and can be restarted after
// an event.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "integrate/ode_system.h"
#include "scene/scene.h"  // IntegrationMethod

namespace camdyn {

struct IntegratorOptions {
  IntegrationMethod method = IntegrationMethod::cvode_bdf;
  int order = 0;  ///< arkode_erk / arkode_dirk: the Runge–Kutta order (kErkOrders, kDirkOrders), 0: ARKODE's default
  double rtol = 1e-8;
  double atol = 1e-12;            ///< state absolute tolerance
  double max_step = 0.0;          ///< [s], 0: unlimited
  double fixed_step = 0.0;        ///< rk4 step [s]
  bool analytic_jacobian = true;  ///< implicit methods: use OdeSystem::jacobian when available
  long max_steps_per_call = 100000;
};

class Integrator {
 public:
  enum class Result { step, root, stop };
  virtual ~Integrator() = default;

  /// One internal step towards t_stop (never past it). `root` when a root
  /// function changed sign: the integrator then stands at the root.
  virtual Result step(double t_stop) = 0;
  /// Time the integrator stands at [s].
  virtual double time() const = 0;
  /// Start of the interval over which dense output is valid, ending at time().
  virtual double last_step_start() const = 0;
  /// State at time().
  virtual const double* state() const = 0;
  /// Dense output of the state at t in [last_step_start(), time()].
  virtual void dense(double t, double* out) const = 0;
  /// Which roots fired at the last `root` result: +1 rising, −1 falling, 0 none.
  virtual void root_info(int* directions) const = 0;
  /// Restarts at (t, y), e.g. after an event changed the right-hand side.
  virtual void reinit(double t, const double* y) = 0;
  virtual SolverCounters counters() const = 0;
  /// counters().steps alone: the step budget is checked every step, and the
  /// other counters cost several solver queries each.
  virtual long steps() const { return counters().steps; }
};

/// Creates the integrator for options.method. Throws NumericalError when
/// SUNDIALS cannot be set up.
std::unique_ptr<Integrator> make_integrator(OdeSystem& system, const IntegratorOptions& options, double t0,
                                            const double* y0);

}  // namespace camdyn
