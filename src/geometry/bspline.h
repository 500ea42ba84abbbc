// Scalar B-splines for motion laws: basis functions with derivatives
// (Cox–de Boor as in Piegl & Tiller, *The NURBS Book*, 2nd ed., algorithms
// A2.1 and A2.3), clamped splines on a segment, and periodic interpolating
// splines. Evaluation allocates nothing (fixed-size stack arrays, degree ≤
// kMaxSplineDegree), so it can run in the ODE right-hand side.
#pragma once

#include <array>
#include <optional>
#include <vector>

namespace camdyn {

/// Highest supported polynomial degree (sizes the stack arrays of evaluation).
inline constexpr int kMaxSplineDegree = 9;

/// Value and first three derivatives of a scalar function at one point.
using Derivatives3 = std::array<double, 4>;
/// Value and first four derivatives (the fourth is needed by the contour of a
/// flat-faced follower's cam, whose third derivative involves s'''').
using Derivatives4 = std::array<double, 5>;

/// Index i of the knot span with knots[i] ≤ x < knots[i+1], restricted to
/// [p, n − 1] (n control points), so that x outside the domain (or at its right
/// end) uses the first (last) span. NURBS Book A2.1 with a plain binary search.
int find_span(int n, int p, double x, const std::vector<double>& knots);

/// Nonzero basis functions N_{span−p+j, p} (j = 0..p) at x and their derivatives:
/// ders[k][j] = d^k N_{span−p+j, p}/dx^k for k = 0..4 (k > p gives 0). NURBS Book A2.3.
struct BasisDerivatives {
  std::array<std::array<double, kMaxSplineDegree + 1>, 5> ders{};
};
BasisDerivatives basis_derivatives(int span, double x, int p, const std::vector<double>& knots);

/// Clamped (end knots repeated p + 1 times) scalar B-spline s(x) = Σ c_i N_{i,p}(x)
/// on [knots.front(), knots.back()].
class ClampedBSpline {
 public:
  /// Knots: p + 1 copies of a, uniform interior knots, p + 1 copies of b, for n
  /// control points (n ≥ p + 1).
  static std::vector<double> uniform_knots(int degree, int n, double a = 0.0, double b = 1.0);

  /// Requires 1 ≤ degree ≤ kMaxSplineDegree and knots.size() == coefficients.size() + degree + 1.
  ClampedBSpline(int degree, std::vector<double> knots, std::vector<double> coefficients);

  /// Value and x-derivatives; x is clamped to the domain.
  Derivatives3 eval(double x) const;
  /// Value and four x-derivatives.
  Derivatives4 eval4(double x) const;

  int degree() const { return degree_; }
  const std::vector<double>& knots() const { return knots_; }
  const std::vector<double>& coefficients() const { return coefficients_; }

  /// eval4() by the Cox–de Boor recursion, without the polynomial pieces
  /// (the reference the pieces are checked against).
  Derivatives4 eval4_de_boor(double x) const;

 private:
  /// The spline as polynomial pieces, one per knot span: the Taylor
  /// coefficients at the span's left knot, from the derivative splines'
  /// values there (every degree up to kMaxSplineDegree), so that eval4() is a
  /// binary search and a Horner scheme instead of the Cox–de Boor recursion
  /// (which cost half of a spline cam's simulation).
  void build_pieces();

  int degree_;
  std::vector<double> knots_, coefficients_;
  std::vector<double> pieces_;  ///< (n − p) spans × (p + 1) Taylor coefficients; an empty span's are 0
};

/// Periodic scalar B-spline of period T, C^{p−1} everywhere, with m basis
/// functions on m breakpoints per period.
class PeriodicBSpline {
 public:
  /// The spline of degree p through (sites[j], values[j]), j = 0..m−1, with
  /// sites strictly increasing in [sites[0], sites[0] + period) and m ≥ p + 1.
  /// Odd degree: the breakpoints are the sites; even degree: the midpoints
  /// between them (interpolating at the knots of an even-degree spline is
  /// singular for uniform sites, de Boor, *A Practical Guide to Splines*, ch. XIII).
  /// Returns nullopt when the interpolation system is singular (badly spaced sites).
  /// Up to kDenseCollocation sites the system is solved densely (with a
  /// condition estimate); above, as the sparse banded-and-wrapped system it is,
  /// in O(m p²) time and O(m p) memory (measured lift tables of 10⁴–10⁵ rows).
  static std::optional<PeriodicBSpline> interpolate(int degree, const std::vector<double>& sites,
                                                    const std::vector<double>& values, double period);
  static constexpr int kDenseCollocation = 400;

  /// Value and x-derivatives at any real x (reduced modulo the period).
  Derivatives3 eval(double x) const;
  /// Value and four x-derivatives.
  Derivatives4 eval4(double x) const;

  int degree() const { return degree_; }
  double period() const { return period_; }
  /// Breakpoints of one period (the spline is a polynomial between them).
  std::vector<double> breakpoints() const;

 private:
  PeriodicBSpline() = default;
  /// x mapped into the domain [knots_[p], knots_[p] + period).
  double reduce(double x) const;
  /// The collocation row of `site`: basis values row[0..p] of the functions
  /// first, first + 1, … (indices mod m).
  void collocation_row(double site, int& first, std::array<double, kMaxSplineDegree + 1>& row) const;
  /// The coefficients interpolating `values` at `sites` (knots set); null when singular.
  static std::optional<std::vector<double>> solve_dense(const PeriodicBSpline& spline, const std::vector<double>& sites,
                                                        const std::vector<double>& values);
  static std::optional<std::vector<double>> solve_banded(const PeriodicBSpline& spline,
                                                         const std::vector<double>& sites,
                                                         const std::vector<double>& values);

  /// The spline as polynomial pieces (degree ≤ kMaxPieceDegree): per piece,
  /// the Taylor coefficients at its left breakpoint, so that evaluation is a
  /// Horner scheme after a direct index (uniform breakpoints) or a binary
  /// search, instead of the Cox–de Boor recursion.
  void build_pieces();
  static constexpr int kMaxPieceDegree = 5;

  int degree_ = 0;
  double period_ = 1.0;
  int m_ = 0;                         ///< basis functions (= breakpoints) per period
  std::vector<double> pieces_;        ///< m × (p + 1) Taylor coefficients; empty above kMaxPieceDegree
  bool uniform_ = false;              ///< breakpoints equally spaced
  double inverse_spacing_ = 0.0;      ///< 1 / breakpoint spacing when uniform
  std::vector<double> knots_;         ///< unwrapped: m + 2p + 1 knots, domain [knots_[p], knots_[p + m]]
  std::vector<double> coefficients_;  ///< m coefficients; index i is used as i mod m
};

}  // namespace camdyn
