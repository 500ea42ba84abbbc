// integrator.method "dop853" (docs/model.md §6): Dormand and Prince's
// order-8 pair against closed forms — its order on a nonlinear problem (one
// step of the Kepler orbit against Kepler's equation), its dense output and
// event location on a harmonic oscillator (its zeros). That a step
// allocates nothing, and the stiff undamped contact of issue 38 against a
// tight BDF reference, are in runge_kutta_order_test.cc.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "common/errors.h"
#include "harmonic_oscillator.h"
#include "integrate/integrator.h"
#include "tolerance.h"

namespace camdyn {
namespace {

// The Kepler problem with μ = 1: q'' = −q / |q|³ (state q_x, q_y, p_x, p_y).
class KeplerOrbit final : public OdeSystem {
 public:
  int size() const override { return 4; }
  int root_count() const override { return 0; }
  int rhs(double /*t*/, const double* y, double* y_dot) override {
    const double r = std::hypot(y[0], y[1]);
    const double r3 = r * r * r;
    y_dot[0] = y[2];
    y_dot[1] = y[3];
    y_dot[2] = -y[0] / r3;
    y_dot[3] = -y[1] / r3;
    return 0;
  }
  int roots(double /*t*/, const double* /*y*/, double* /*g*/) override { return 0; }
};

constexpr double kKeplerEccentricity = 0.1;

// The Kepler orbit's state at time t from the pericentre (semi-major axis 1,
// mean motion 1), by Newton on Kepler's equation M = E − e sin E.
std::array<double, 4> kepler_state(double t) {
  const double e = kKeplerEccentricity, b = std::sqrt(1.0 - e * e);
  double E = t;
  for (int it = 0; it < 50; ++it) E -= (E - e * std::sin(E) - t) / (1.0 - e * std::cos(E));
  const double rate = 1.0 / (1.0 - e * std::cos(E));  // dE/dt
  return {std::cos(E) - e, b * std::sin(E), -std::sin(E) * rate, b * std::cos(E) * rate};
}

// The largest state error of one step of length h from the pericentre, with
// a tolerance that accepts it: the method's local error.
double kepler_step_error(double h) {
  KeplerOrbit ode;
  IntegratorOptions options;
  options.method = IntegrationMethod::dop853;
  options.rtol = 1.0;  // accepts the steps below, and starts with a longer one
  options.atol = 1.0;
  const std::array<double, 4> y0 = kepler_state(0.0);
  const std::unique_ptr<Integrator> integrator = make_integrator(ode, options, 0.0, y0.data());
  EXPECT_EQ(integrator->step(h), Integrator::Result::stop);
  EXPECT_EQ(integrator->counters().steps, 1);
  const std::array<double, 4> exact = kepler_state(h);
  double worst = 0.0;
  for (int i = 0; i < 4; ++i) worst = std::max(worst, std::abs(integrator->state()[i] - exact[i]));
  return worst;
}

// Halving the step divides an order-8 method's local error by 2⁹ = 512; an
// order-7 one (a wrong digit in a weight) by 256, an order-9 one by 1024.
// Two pairs of steps, the errors (3e-9 to 1e-12) well above round-off; on
// the near-circular orbit they are in the asymptotic range (on e = 0.5 from
// the pericentre the ratio is still 400 at h = 0.2).
TEST(Dop853, IsOfOrderEightOnANonlinearProblem) {
  for (const double h : {0.4, 0.34}) {
    const double coarse = kepler_step_error(h), fine = kepler_step_error(0.5 * h);
    EXPECT_GT(fine, 1e-13) << h;
    EXPECT_GT(coarse / fine, 420.0) << h << ": " << coarse << " " << fine;
    EXPECT_LT(coarse / fine, 640.0) << h << ": " << coarse << " " << fine;
  }
}

constexpr double kDopOmega = 2.0 * std::numbers::pi * 1600.0;  // [rad/s], the stiff contact's vibration
constexpr double kDopAmplitude = 1e-6;                         // [m]

std::unique_ptr<Integrator> oscillator_integrator(test::HarmonicOscillator& ode, double rtol) {
  IntegratorOptions options;
  options.method = IntegrationMethod::dop853;
  options.rtol = rtol;
  options.atol = rtol * kDopAmplitude * 1e-2;
  const double y0[2] = {kDopAmplitude, 0.0};
  return make_integrator(ode, options, 0.0, y0);
}

// Over ten periods at rtol 1e-10 the dense output at every step's quarter
// points and the located zeros follow the closed form to the tolerance: the
// interpolant is of order 7, and a root is found to 100 ε in time.
TEST(Dop853, DenseOutputAndRootsFollowTheClosedForm) {
  test::HarmonicOscillator ode(kDopOmega, true);
  const double rtol = 1e-10;
  const std::unique_ptr<Integrator> integrator = oscillator_integrator(ode, rtol);
  const double t_end = 10.0 * 2.0 * std::numbers::pi / kDopOmega;
  double dense_error = 0.0, root_error = 0.0;
  int crossings = 0;
  for (;;) {
    const Integrator::Result result = integrator->step(t_end);
    const double t0 = integrator->last_step_start(), t1 = integrator->time();
    for (const double s : {0.25, 0.5, 0.75}) {
      double y[2];
      const double t = t0 + s * (t1 - t0);
      integrator->dense(t, y);
      dense_error = std::max(dense_error, std::abs(y[0] - kDopAmplitude * std::cos(kDopOmega * t)) / kDopAmplitude);
    }
    if (result == Integrator::Result::root) {
      int direction = 0;
      integrator->root_info(&direction);
      const double expected = (crossings + 0.5) * std::numbers::pi / kDopOmega;
      root_error = std::max(root_error, std::abs(t1 - expected) * kDopOmega);
      EXPECT_EQ(direction, crossings % 2 == 0 ? -1 : +1) << crossings;
      ++crossings;
    }
    if (result == Integrator::Result::stop) break;
  }
  EXPECT_EQ(crossings, 20);
  EXPECT_LT(dense_error, test::integrator_tolerance(rtol, 100.0));
  EXPECT_LT(root_error, test::integrator_tolerance(rtol, 100.0));  // phase [rad]
}

// A restart a hair before the end (an event there): what is left, however
// small, is one step, not a step size fallen to round-off.
TEST(Dop853, TakesARoundOffStepToTheEnd) {
  test::HarmonicOscillator ode(kDopOmega, true);
  const std::unique_ptr<Integrator> integrator = oscillator_integrator(ode, 1e-10);
  const double t_end = 1e-3, y[2] = {kDopAmplitude, 0.0};  // [s], [m, m/s]
  integrator->reinit(std::nextafter(t_end, 0.0), y);
  EXPECT_EQ(integrator->step(t_end), Integrator::Result::stop);
  EXPECT_EQ(integrator->time(), t_end);
  EXPECT_NEAR(integrator->state()[0], kDopAmplitude, 1e-12 * kDopAmplitude);
}

// A right-hand side that fails for good stops the run with the time named.
TEST(Dop853, AnUnrecoverableRightHandSideFailureNamesTheTime) {
  class Failing final : public OdeSystem {
   public:
    int size() const override { return 1; }
    int root_count() const override { return 0; }
    int rhs(double t, const double* /*y*/, double* y_dot) override {
      y_dot[0] = 1.0;
      return t > 0.5 ? -1 : 0;
    }
    int roots(double /*t*/, const double* /*y*/, double* /*g*/) override { return 0; }
  } ode;
  IntegratorOptions options;
  options.method = IntegrationMethod::dop853;
  const double y0[1] = {0.0};
  const std::unique_ptr<Integrator> integrator = make_integrator(ode, options, 0.0, y0);
  try {
    while (integrator->step(1.0) != Integrator::Result::stop) {
    }
    FAIL() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("dop853: the right-hand side failed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace camdyn
