// Named tolerance levels for the tests (SUNDIALS style): a tolerance is one of
// these levels, scaled by the size of the values compared, or derived from the
// integrator tolerance or grid of the run under test; never a bare literal.
//
// The round-off levels are relative: multiply them by the size of the values
// compared (a length in metres, a lift, a peak force); for O(1) values, use
// them as they are.
#pragma once

#include <limits>

namespace camdyn::test {

/// Machine epsilon of double (2.2e-16): the unit the round-off levels count in.
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

/// Bound on the lengths of the test cams and followers (radii, lifts, offsets ≲ 0.1 m) [m]: the size
/// that scales the round-off levels for lengths and positions.
inline constexpr double kLengthScale = 0.1;

/// The same arithmetic done two ways, or a result exact but for a couple of roundings: 4 ulps.
inline constexpr double kExact = 4 * kEps;

/// A closed form of a few dozen operations (trig, sqrt, products) against an identity: ≈ 45 ulps.
inline constexpr double kRoundoff = 1e-14;

/// Round-off amplified ~100×: a linear solve, cancellation among large terms, or an iteration run to machine precision.
inline constexpr double kAmplifiedRoundoff = 1e-12;

/// A root or extremum refined by an iteration that stops at its own tolerance (≈ 1e-10 relative), with margin.
inline constexpr double kConverged = 1e-9;

/// A central difference with a step of 1e-6–1e-5 of the scale of x, relative to the derivative:
/// truncation (h/x)² ≈ 1e-10 plus cancellation ε·x/h ≈ 1e-10, with margin.
inline constexpr double kFiniteDifference = 1e-8;

/// A coefficient of order 1 quoted to two decimals (a textbook peak factor): one unit in the last place.
inline constexpr double kQuoted = 0.01;

/// A parameter fitted to noisy synthetic data: 5 % of the true value (a few standard errors of the fits run).
inline constexpr double kStatistical = 0.05;

/// The global error of a run at relative tolerance `rtol`: local errors accumulate over the steps, and a
/// quantity derived from the trajectory (a peak, a crossing) can lose a little more, hence `factor` > 1.
constexpr double integrator_tolerance(double rtol, double factor = 10.0) { return factor * rtol; }

}  // namespace camdyn::test
