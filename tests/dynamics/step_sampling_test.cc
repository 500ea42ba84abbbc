// What the run follows over each integrator step from the model evaluated at
// the step's start, middle and end: the work quadratures (Simpson's rule,
// StepQuadrature) and the window's extremes (StepExtremes), against closed
// forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "dynamics/step_extremes.h"
#include "dynamics/step_quadrature.h"

namespace camdyn {
namespace {

using Values = StepQuadrature::Values;

Values all(double x) {
  Values v;
  v.fill(x);
  return v;
}

// A cubic integrand: Simpson's rule integrates it exactly, and inside the
// step the quadratic through the three samples integrates a quadratic
// exactly.
TEST(StepQuadrature, SimpsonIsExactForACubicAndTheInteriorForAQuadratic) {
  const auto cubic = [](double t) { return 1.0 + 2.0 * t + 3.0 * t * t + 4.0 * t * t * t; };
  const auto cubic_integral = [](double t) { return t + t * t + t * t * t + t * t * t * t; };
  StepQuadrature q;
  q.start(0.3, all(cubic_integral(0.3)), all(cubic(0.3)));
  q.step(0.7, all(cubic(0.5)), all(cubic(0.7)));
  Values at_end{};
  q.at(0.7, at_end.data());
  for (double v : at_end) EXPECT_NEAR(v, cubic_integral(0.7), 1e-14);

  const auto quadratic = [](double t) { return 2.0 - t + 5.0 * t * t; };
  const auto quadratic_integral = [](double t) { return 2.0 * t - 0.5 * t * t + 5.0 / 3.0 * t * t * t; };
  StepQuadrature r;
  r.start(1.0, all(quadratic_integral(1.0)), all(quadratic(1.0)));
  r.step(1.5, all(quadratic(1.25)), all(quadratic(1.5)));
  for (double t : {1.0, 1.1, 1.3, 1.4999, 1.5}) {
    Values at{};
    r.at(t, at.data());
    EXPECT_NEAR(at[0], quadratic_integral(t), 1e-14) << t;
  }
  // The end is the value the next step starts from, to the bit.
  Values end{};
  r.at(1.5, end.data());
  r.step(2.0, all(quadratic(1.75)), all(quadratic(2.0)));
  Values next_start{};
  r.at(1.5, next_start.data());
  EXPECT_EQ(next_start, end);
}

// Over many steps the error falls as h⁴ (Simpson's order): ∫₀^π sin = 2.
TEST(StepQuadrature, ConvergesAtFourthOrder) {
  const auto error_with = [](int steps) {
    const double h = std::numbers::pi / steps;
    StepQuadrature q;
    q.start(0.0, all(0.0), all(std::sin(0.0)));
    for (int i = 1; i <= steps; ++i) q.step(i * h, all(std::sin((i - 0.5) * h)), all(std::sin(i * h)));
    Values at_end{};
    q.at(steps * h, at_end.data());
    return std::abs(at_end[0] - 2.0);
  };
  const double coarse = error_with(10), fine = error_with(20);
  EXPECT_NEAR(coarse / fine, 16.0, 0.5);
  // Composite Simpson: |error| ≤ (b − a) h⁴ max|f⁗| / 2880, h the step, max|f⁗| = 1.
  EXPECT_LT(coarse, std::numbers::pi * std::pow(std::numbers::pi / 10, 4) / 2880.0);
}

StepExtremes::Values extremes_of(double x) {
  StepExtremes::Values v;
  v.fill(x);
  return v;
}

// A peak between the samples: the vertex of the parabola through them is
// where to look; a monotone step, a trough or a peak that cannot beat the
// record asks for nothing.
TEST(StepExtremes, AskForTheVertexOnlyWhereAPeakCanBeatTheRecord) {
  // cos over [−0.2, 0.3]: the peak at t = 0, the fraction 0.4 of the step.
  const double t0 = -0.2, t1 = 0.3;
  const auto x = [&](double s) { return extremes_of(std::cos(t0 + (t1 - t0) * s)); };
  StepExtremes e;
  e.fold(x(0.0));
  e.fold(x(0.5));
  e.fold(x(1.0));
  StepExtremes::Values s{};
  ASSERT_EQ(e.probes(x(0.0), x(0.5), x(1.0), s), 1u);  // the five quantities agree: one probe
  const double t_peak = t0 + (t1 - t0) * s[0];
  EXPECT_NEAR(t_peak, 0.0, 0.02);
  e.fold(extremes_of(std::cos(t_peak)));
  EXPECT_NEAR(e.best()[0], 1.0, 1e-3);  // the samples alone: cos(0.05) = 0.9988

  StepExtremes::Values none{};
  EXPECT_EQ(e.probes(extremes_of(0.1), extremes_of(0.2), extremes_of(0.3), none), 0u);  // monotone
  EXPECT_EQ(e.probes(extremes_of(0.3), extremes_of(0.1), extremes_of(0.3), none), 0u);  // a trough
  EXPECT_EQ(e.probes(extremes_of(0.1), extremes_of(0.3), extremes_of(0.2), none), 0u);  // below the record 1
  StepExtremes fresh;
  EXPECT_EQ(fresh.probes(extremes_of(0.1), extremes_of(0.3), extremes_of(0.2), none), 1u);  // no record yet
}

}  // namespace
}  // namespace camdyn
