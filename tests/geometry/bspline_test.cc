// B-spline basis functions and derivatives (NURBS Book A2.1/A2.3), clamped
// and periodic interpolating splines.
#include "geometry/bspline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "finite_difference.h"
#include "tolerance.h"

namespace camdyn {
namespace {

double binomial(int n, int k) {
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

TEST(BSplineBasis, BezierKnotsGiveBernsteinPolynomialsAndTheirDerivatives) {
  // With knots 0^(p+1) 1^(p+1) the basis is B_{i,p}(x) = C(p,i) x^i (1−x)^(p−i):
  // an independent closed form for values and derivatives (by the product rule).
  for (int p = 1; p <= kMaxSplineDegree; ++p) {
    const std::vector<double> knots = ClampedBSpline::uniform_knots(p, p + 1);
    for (double x : {0.0, 0.13, 0.5, 0.77, 1.0}) {
      const int span = find_span(p + 1, p, x, knots);
      EXPECT_EQ(span, p);
      const BasisDerivatives b = basis_derivatives(span, x, p, knots);
      for (int i = 0; i <= p; ++i) {
        // d^k/dx^k [x^i (1−x)^(p−i)] = Σ_j C(k,j) (x^i)^(j) ((1−x)^(p−i))^(k−j).
        auto falling = [](int n, int k) {
          double r = 1.0;
          for (int m = 0; m < k; ++m) r *= n - m;
          return r;
        };
        for (int k = 0; k <= 3; ++k) {
          double d = 0.0;
          for (int j = 0; j <= k; ++j) {
            const int a = i - j, c = p - i - (k - j);
            if (a < 0 || c < 0) continue;
            d += binomial(k, j) * falling(i, j) * std::pow(x, a) * falling(p - i, k - j) * std::pow(1.0 - x, c) *
                 ((k - j) % 2 ? -1.0 : 1.0);
          }
          d *= binomial(p, i);
          // Values are O(1), derivatives up to p³·2^p: relative rounding of a few ulps.
          EXPECT_NEAR(b.ders[k][i], d, test::kAmplifiedRoundoff * std::max(1.0, std::abs(d)))
              << "p=" << p << " i=" << i << " k=" << k << " x=" << x;
        }
      }
    }
  }
}

TEST(BSplineBasis, PartitionOfUnityOnUniformKnots) {
  const int p = 5, n = 11;
  const std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
  for (int i = 0; i <= 100; ++i) {
    const double x = i / 100.0;
    const BasisDerivatives b = basis_derivatives(find_span(n, p, x, knots), x, p, knots);
    double sum[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k)
      for (int j = 0; j <= p; ++j) sum[k] += b.ders[k][j];
    EXPECT_NEAR(sum[0], 1.0, test::kRoundoff);
    for (int k = 1; k < 4; ++k)
      EXPECT_NEAR(sum[k], 0.0, test::kRoundoff * 1e5) << "k=" << k;  // ders up to (p/Δ)³ ≈ 3e4
  }
}

TEST(BSplineBasis, SpanAtAndBeyondTheDomainEnds) {
  const int p = 3, n = 7;
  const std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
  EXPECT_EQ(find_span(n, p, -1.0, knots), p);
  EXPECT_EQ(find_span(n, p, 0.0, knots), p);
  EXPECT_EQ(find_span(n, p, 0.25, knots), p + 1);  // interior knot 1/4 starts span p+1
  EXPECT_EQ(find_span(n, p, 1.0, knots), n - 1);
  EXPECT_EQ(find_span(n, p, 2.0, knots), n - 1);
}

TEST(ClampedBSpline, DerivativesMatchFiniteDifferencesAndEndsInterpolate) {
  const int p = 5;
  const std::vector<double> c = {0.0, 0.1, -0.3, 0.8, 0.5, 1.2, 0.9, 1.0};
  const ClampedBSpline s(p, ClampedBSpline::uniform_knots(p, static_cast<int>(c.size())), c);
  EXPECT_NEAR(s.eval(0.0)[0], c.front(), test::kExact);
  EXPECT_NEAR(s.eval(1.0)[0], c.back(), test::kExact);
  // End slope of a clamped spline: p (c1 − c0) / (knot step).
  EXPECT_NEAR(s.eval(0.0)[1], p * (c[1] - c[0]) / (1.0 / 3.0), test::kAmplifiedRoundoff);
  constexpr double h = 1e-4;
  for (int i = 0; i < 50; ++i) {
    const double x = (i + 0.5) / 50.0;  // ≥ 0.01 from the knots 1/3, 2/3
    const Derivatives3 d = s.eval(x);
    for (int k = 0; k < 3; ++k) {
      const auto fd = test::central_difference([&](double t) { return s.eval(t)[k]; }, x, h);
      EXPECT_NEAR(d[k + 1], fd.value, fd.tolerance) << "order " << k + 1 << " at x = " << x;
    }
  }
}

// The polynomial pieces eval4() evaluates are the spline the Cox–de Boor
// recursion evaluates: every degree, uniform and uneven knots, a repeated
// interior knot (a span of zero length, a kink), at the knots and between,
// to round-off (1e-11 of each derivative's largest size over the samples:
// the Taylor form adds a few ulps per term of degree ≤ 9).
TEST(ClampedBSpline, PolynomialPiecesEqualTheDeBoorRecursion) {
  for (int p = 1; p <= kMaxSplineDegree; ++p) {
    for (int layout = 0; layout < 3; ++layout) {
      const int n = p + 7;
      std::vector<double> knots = ClampedBSpline::uniform_knots(p, n, -0.3, 1.9);
      if (layout >= 1)  // uneven interior knots
        for (int i = p + 1; i < n; ++i) knots[i] += 0.05 * std::sin(3.0 * i);
      if (layout == 2) knots[p + 3] = knots[p + 2];  // a repeated interior knot
      std::vector<double> c(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) c[i] = std::cos(1.3 * i) + 0.1 * i;
      const ClampedBSpline s(p, knots, c);
      std::vector<double> xs;
      for (int i = 0; i <= 400; ++i) xs.push_back(-0.3 + 2.2 * i / 400.0);
      for (int i = p; i <= n; ++i) xs.push_back(knots[i]);
      std::array<double, 5> size{};
      for (double x : xs) {
        const Derivatives4 r = s.eval4_de_boor(x);
        for (int k = 0; k < 5; ++k) size[k] = std::max(size[k], std::abs(r[k]));
      }
      for (double x : xs) {
        const Derivatives4 got = s.eval4(x), want = s.eval4_de_boor(x);
        for (int k = 0; k <= std::min(p, 4); ++k)
          EXPECT_NEAR(got[k], want[k], 1e-11 * size[k])
              << "degree " << p << " layout " << layout << " x " << x << " derivative " << k;
      }
    }
  }
}

TEST(PeriodicBSpline, ReproducesAConstantAndInterpolates) {
  const std::vector<double> sites = {0.0, 0.1, 0.25, 0.4, 0.5, 0.7, 0.85};
  for (int p : {3, 4, 5, 6}) {
    const auto flat = PeriodicBSpline::interpolate(p, sites, std::vector<double>(7, 2.5), 1.0);
    ASSERT_TRUE(flat.has_value());
    for (double x : {-0.3, 0.05, 0.6, 3.99}) {
      EXPECT_NEAR(flat->eval(x)[0], 2.5, test::kRoundoff * 10) << p;
      EXPECT_NEAR(flat->eval(x)[1], 0.0, test::kAmplifiedRoundoff * 10) << p;
    }
    const std::vector<double> values = {1.0, -2.0, 0.5, 3.0, 0.0, 1.5, -1.0};
    const auto s = PeriodicBSpline::interpolate(p, sites, values, 1.0);
    ASSERT_TRUE(s.has_value());
    for (std::size_t j = 0; j < sites.size(); ++j) {
      EXPECT_NEAR(s->eval(sites[j])[0], values[j], test::kAmplifiedRoundoff) << p;
      EXPECT_NEAR(s->eval(sites[j] + 5.0)[0], values[j], test::kAmplifiedRoundoff) << p;  // period 1
    }
    EXPECT_EQ(s->breakpoints().size(), sites.size());
  }
}

TEST(PeriodicBSpline, EvenDegreeUsesMidpointBreakpoints) {
  const auto s = PeriodicBSpline::interpolate(4, {0.0, 0.2, 0.6, 0.8, 0.9}, {0, 1, 2, 1, 0}, 1.0);
  ASSERT_TRUE(s.has_value());
  const std::vector<double> expected = {0.1, 0.4, 0.7, 0.85, 0.95};
  const std::vector<double> got = s->breakpoints();
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t j = 0; j < got.size(); ++j) EXPECT_NEAR(got[j], expected[j], test::kExact);
}

}  // namespace
}  // namespace camdyn
