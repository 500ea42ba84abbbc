// integrator.order (docs/config.md "integrator"): ARKODE's explicit and
// implicit Runge–Kutta tables of each offered order on an undamped harmonic
// oscillator against its closed form, and on the stiff undamped contact of
// issue 38 against a tight BDF reference (docs/performance.md "A stiff
// undamped contact").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>

#include "allocation_counter.h"
#include "dynamics/simulation.h"
#include "harmonic_oscillator.h"
#include "integrate/integrator.h"
#include "tests/dynamics/scenes.h"
#include "tolerance.h"

namespace camdyn {
namespace {

using test::HarmonicOscillator;

constexpr double kFrequency = 1600.0;  // [Hz], the stiff contact's vibration
constexpr double kPeriods = 10.0;
constexpr double kAmplitude = 1e-6;  // [m]

struct OscillatorRun {
  double error = 0.0;  ///< largest |x − x_exact| at the steps, relative to the amplitude
  SolverCounters counters;
};

// x(0) = A, v(0) = 0 for kPeriods periods, one step at a time: x = A cos ωt.
OscillatorRun oscillate(IntegrationMethod method, int order, double rtol) {
  const double omega = 2.0 * std::numbers::pi * kFrequency;
  HarmonicOscillator ode(omega);
  IntegratorOptions options;
  options.method = method;
  options.order = order;
  options.rtol = rtol;
  options.atol = rtol * kAmplitude * 1e-2;  // rtol governs: the state never nears 0 in both components
  const double y0[2] = {kAmplitude, 0.0};
  const std::unique_ptr<Integrator> integrator = make_integrator(ode, options, 0.0, y0);
  const double t_end = kPeriods / kFrequency;
  OscillatorRun r;
  while (integrator->step(t_end) != Integrator::Result::stop) {
    const double t = integrator->time();
    r.error = std::max(r.error, std::abs(integrator->state()[0] - kAmplitude * std::cos(omega * t)) / kAmplitude);
  }
  r.counters = integrator->counters();
  return r;
}

struct MethodOrder {
  IntegrationMethod method;
  int order;
  double error_factor = 100.0;  ///< the global error's bound, in units of rtol
};

std::string name_of(const ::testing::TestParamInfo<MethodOrder>& p) {
  return to_string(p.param.method) + "_order_" + std::to_string(p.param.order);
}

class RungeKuttaOrder : public ::testing::TestWithParam<MethodOrder> {};

// Each table follows the oscillation to its tolerance: the error over 10
// periods stays within a multiple of rtol (local errors of rtol accumulating
// over the steps; measured 0.2–35 rtol over 20 periods, 60 for the order-3
// DIRK), at two tolerances 100× apart, and falls with the tolerance.
TEST_P(RungeKuttaOrder, FollowsAHarmonicOscillatorToItsTolerance) {
  const MethodOrder m = GetParam();
  const double loose = 1e-5, tight = 1e-7;
  const OscillatorRun a = oscillate(m.method, m.order, loose);
  const OscillatorRun b = oscillate(m.method, m.order, tight);
  EXPECT_LT(a.error, test::integrator_tolerance(loose, m.error_factor)) << a.counters.steps << " steps";
  EXPECT_LT(b.error, test::integrator_tolerance(tight, m.error_factor)) << b.counters.steps << " steps";
  EXPECT_LT(b.error, a.error);
  EXPECT_GT(b.counters.steps, a.counters.steps);
}

INSTANTIATE_TEST_SUITE_P(
    Erk, RungeKuttaOrder,
    ::testing::Values(MethodOrder{IntegrationMethod::arkode_erk, 2}, MethodOrder{IntegrationMethod::arkode_erk, 3},
                      MethodOrder{IntegrationMethod::arkode_erk, 4}, MethodOrder{IntegrationMethod::arkode_erk, 5},
                      MethodOrder{IntegrationMethod::arkode_erk, 6}, MethodOrder{IntegrationMethod::arkode_erk, 8}),
    name_of);
INSTANTIATE_TEST_SUITE_P(Dirk, RungeKuttaOrder,
                         ::testing::Values(MethodOrder{IntegrationMethod::arkode_dirk, 2},
                                           MethodOrder{IntegrationMethod::arkode_dirk, 3},
                                           MethodOrder{IntegrationMethod::arkode_dirk, 4},
                                           // ARK548L2SA's DIRK embedding underrates its error on an
                                           // undamped oscillation: measured 190 and 530 rtol at 1e-6, 1e-8.
                                           MethodOrder{IntegrationMethod::arkode_dirk, 5, 1e4}),
                         name_of);

// The order is the table's: at a tight tolerance each higher order takes
// fewer steps (the step grows as rtol^(1/(q+1)) for order q), and the
// default (order 0) is ARKODE's order 4.
TEST(RungeKuttaOrders, HigherExplicitOrdersTakeFewerSteps) {
  const double rtol = 1e-8;
  long previous = oscillate(IntegrationMethod::arkode_erk, 3, rtol).counters.steps;
  for (const int q : {4, 5, 6, 8}) {
    const long steps = oscillate(IntegrationMethod::arkode_erk, q, rtol).counters.steps;
    EXPECT_LT(steps, previous) << "order " << q;
    previous = steps;
  }
  EXPECT_EQ(oscillate(IntegrationMethod::arkode_erk, 0, rtol).counters.steps,
            oscillate(IntegrationMethod::arkode_erk, 4, rtol).counters.steps);
}

// After the first step (where ARKODE makes its stage vectors), steps, dense
// output and root checks of the order-8 pairs, ARKODE's and camdyn's own
// DOP853, make no heap allocation (operator new; docs/performance.md "A
// stiff undamped contact").
TEST(RungeKuttaOrders, ExplicitStepsAllocateNothing) {
  for (const IntegrationMethod method : {IntegrationMethod::arkode_erk, IntegrationMethod::dop853}) {
    HarmonicOscillator ode(2.0 * std::numbers::pi * kFrequency, true);
    IntegratorOptions options;
    options.method = method;
    options.order = method == IntegrationMethod::arkode_erk ? 8 : 0;
    options.rtol = 1e-10;
    options.atol = 1e-18;
    const double y0[2] = {kAmplitude, 0.0};
    const std::unique_ptr<Integrator> integrator = make_integrator(ode, options, 0.0, y0);
    const double t_end = kPeriods / kFrequency;
    ASSERT_NE(integrator->step(t_end), Integrator::Result::stop) << to_string(method);
    double y[2] = {};
    const long before = test::allocation_count();
    for (int i = 0; i < 100; ++i) {
      ASSERT_NE(integrator->step(t_end), Integrator::Result::stop) << to_string(method);
      integrator->dense(0.5 * (integrator->last_step_start() + integrator->time()), y);
    }
    EXPECT_EQ(test::allocation_count() - before, 0) << to_string(method);
  }
}

}  // namespace
}  // namespace camdyn

namespace camdyn {
namespace {

// The stiff undamped contact of issue 38 (bench/stiff_contact_bench.cc; a
// quarter revolution here, through most of the rise that excites the
// contact's vibration): the high orders at rtol 1e-10 reach the contact
// forces of a BDF run at rtol 1e-12, atol 1e-16, each in fewer steps than
// the order below, and camdyn's DOP853 in fewer than ARKODE's order 8. The
// undamped vibration carries its phase error through some 400 periods, and
// the reference its own: orders 5, 6 and 8 all give the same peak force to 9
// digits, 1.2e-7 (1200 rtol) below the reference's. DOP853's energy balance
// closes to the tolerance too (its dense output feeds the work quadratures
// at each step's middle; ARKODE's order 8 measured 4e-4 there).
TEST(RungeKuttaOrders, HighOrdersReachTheReferenceForcesOnTheStiffUndampedContact) {
  SceneConfig scene = test::cycloidal_cam_scene(100.0, ContactModel::hertz);
  scene.simulation.cycles = 0.25;
  scene.simulation.discard_cycles = 0;
  SceneConfig tight = scene;
  tight.integrator.rtol = 1e-12;
  tight.integrator.atol = 1e-16;
  const SimulationResult ref = simulate_scene(tight, "reference");
  scene.integrator.rtol = 1e-10;
  scene.integrator.atol = 1e-12;
  long previous_steps = 0;
  for (const MethodOrder m :
       {MethodOrder{IntegrationMethod::arkode_erk, 5}, MethodOrder{IntegrationMethod::arkode_erk, 6},
        MethodOrder{IntegrationMethod::arkode_erk, 8}, MethodOrder{IntegrationMethod::dop853, 0}}) {
    scene.integrator.method = m.method;
    scene.integrator.order = m.order > 0 ? std::optional<int>(m.order) : std::nullopt;
    const std::string what = to_string(m.method) + " order " + std::to_string(m.order);
    const SimulationResult r = simulate_scene(scene, "high order");
    ASSERT_EQ(r.solver.termination, Termination::converged) << what;
    const double tol = test::integrator_tolerance(scene.integrator.rtol, 1e4);
    EXPECT_NEAR(r.metrics.peak_contact_force / ref.metrics.peak_contact_force, 1.0, tol) << what;
    EXPECT_NEAR(r.metrics.min_contact_force / ref.metrics.min_contact_force, 1.0, tol) << what;
    if (previous_steps > 0) {
      EXPECT_LT(r.solver.counters.steps, previous_steps) << what;
    }
    previous_steps = r.solver.counters.steps;
    if (m.method == IntegrationMethod::dop853) {
      EXPECT_LT(std::abs(r.metrics.energy_residual), test::integrator_tolerance(scene.integrator.rtol, 1e3));
    }
  }
}

}  // namespace
}  // namespace camdyn
