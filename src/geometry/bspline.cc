#include "geometry/bspline.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <utility>

namespace camdyn {

int find_span(int n, int p, double x, const std::vector<double>& knots) {
  assert(static_cast<int>(knots.size()) >= n + 1 && n > p);
  // Last span i with knots[i] ≤ x among i ∈ [p, n − 1]; repeated knots give
  // empty spans that upper_bound skips.
  const auto first = knots.begin() + p;
  const auto last = knots.begin() + n;  // knots[n] closes the domain
  const auto it = std::upper_bound(first, last, x);
  const int span = static_cast<int>(it - knots.begin()) - 1;
  return std::clamp(span, p, n - 1);
}

BasisDerivatives basis_derivatives(int span, double x, int p, const std::vector<double>& knots) {
  assert(p >= 0 && p <= kMaxSplineDegree);
  constexpr int kN = kMaxSplineDegree + 1;
  const int nd = std::min(4, p);  // derivatives above p vanish
  // ndu: basis functions (upper triangle) and knot differences (lower triangle).
  double ndu[kN][kN];
  double left[kN], right[kN];
  ndu[0][0] = 1.0;
  for (int j = 1; j <= p; ++j) {
    left[j] = x - knots[span + 1 - j];
    right[j] = knots[span + j] - x;
    double saved = 0.0;
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];
      const double temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  BasisDerivatives out;
  auto& ders = out.ders;
  for (int j = 0; j <= p; ++j) ders[0][j] = ndu[j][p];
  double a[2][kN];
  for (int r = 0; r <= p; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = 1.0;
    for (int k = 1; k <= nd; ++k) {
      double d = 0.0;
      const int rk = r - k, pk = p - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = r - 1 <= pk ? k - 1 : p - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  double factor = p;
  for (int k = 1; k <= nd; ++k) {
    for (int j = 0; j <= p; ++j) ders[k][j] *= factor;
    factor *= p - k;
  }
  return out;
}

// ---------------------------------------------------------------- clamped

std::vector<double> ClampedBSpline::uniform_knots(int degree, int n, double a, double b) {
  assert(n >= degree + 1);
  std::vector<double> knots(n + degree + 1);
  const int spans = n - degree;
  for (int i = 0; i <= degree; ++i) {
    knots[i] = a;
    knots[n + i] = b;
  }
  for (int j = 1; j < spans; ++j) knots[degree + j] = a + (b - a) * j / spans;
  return knots;
}

ClampedBSpline::ClampedBSpline(int degree, std::vector<double> knots, std::vector<double> coefficients)
    : degree_(degree), knots_(std::move(knots)), coefficients_(std::move(coefficients)) {
  assert(degree_ >= 1 && degree_ <= kMaxSplineDegree);
  assert(knots_.size() == coefficients_.size() + degree_ + 1);
  build_pieces();
}

void ClampedBSpline::build_pieces() {
  const int p = degree_, n = static_cast<int>(coefficients_.size());
  if (p < 1 || p > kMaxSplineDegree || static_cast<int>(knots_.size()) != n + p + 1) return;
  // derivative[k]: the coefficients of the k-th derivative, a spline of
  // degree p − k on the knots knots_[k .. n + p − k] (a span of zero length
  // contributes nothing): c'_i = (p − k + 1) (c_{i+1} − c_i) / (u_{i+p+1} − u_{i+k}).
  std::vector<std::vector<double>> derivative(static_cast<std::size_t>(p) + 1);
  derivative[0] = coefficients_;
  for (int k = 1; k <= p; ++k) {
    const std::vector<double>& c = derivative[static_cast<std::size_t>(k) - 1];
    std::vector<double>& d = derivative[static_cast<std::size_t>(k)];
    d.assign(static_cast<std::size_t>(n - k), 0.0);
    const int q = p - k + 1;  // degree of the spline differentiated
    for (int i = 0; i < n - k; ++i) {
      const double width = knots_[i + p + 1] - knots_[i + k];
      if (width > 0.0) d[i] = q * (c[i + 1] - c[i]) / width;
    }
  }
  const int spans = n - p;
  pieces_.assign(static_cast<std::size_t>(spans) * static_cast<std::size_t>(p + 1), 0.0);
  double factorial = 1.0;
  for (int k = 0; k <= p; ++k) {
    if (k > 0) factorial *= k;
    // The k-th derivative at each span's left knot x0: its spline of degree
    // p − k has the knot vector knots_ less k knots at each end, where the
    // span's index is span − k.
    const int degree = p - k;
    const std::vector<double> knots(knots_.begin() + k, knots_.end() - k);
    const std::vector<double>& d = derivative[static_cast<std::size_t>(k)];
    for (int span = p; span < n; ++span) {
      const double x0 = knots_[span];
      if (!(knots_[span + 1] > x0)) continue;
      double value = d[span - p];  // degree 0: the span's constant
      if (degree > 0) {
        const BasisDerivatives b = basis_derivatives(span - k, x0, degree, knots);
        value = 0.0;
        for (int j = 0; j <= degree; ++j) value += b.ders[0][j] * d[span - p + j];
      }
      pieces_[static_cast<std::size_t>(span - p) * static_cast<std::size_t>(p + 1) + static_cast<std::size_t>(k)] =
          value / factorial;
    }
  }
}

namespace {

/// Value and four derivatives at x0 + t of the polynomial with Taylor
/// coefficients a[0..p] at x0, by repeated synthetic division (Horner).
Derivatives4 taylor_derivatives(std::array<double, kMaxSplineDegree + 1> a, int p, double t) {
  Derivatives4 out{};
  double factorial = 1.0;
  for (int d = 0; d <= std::min(p, 4); ++d) {
    for (int k = p - 1; k >= d; --k) a[k] += t * a[k + 1];
    if (d > 0) factorial *= d;
    out[d] = a[d] * factorial;
  }
  return out;
}

}  // namespace

Derivatives4 ClampedBSpline::eval4(double x) const {
  if (pieces_.empty()) return eval4_de_boor(x);
  const int n = static_cast<int>(coefficients_.size()), p = degree_;
  x = std::clamp(x, knots_.front(), knots_.back());
  const int span = find_span(n, p, x, knots_);
  std::array<double, kMaxSplineDegree + 1> a{};
  const double* c = &pieces_[static_cast<std::size_t>(span - p) * static_cast<std::size_t>(p + 1)];
  std::copy(c, c + p + 1, a.begin());
  return taylor_derivatives(a, p, x - knots_[span]);
}

Derivatives4 ClampedBSpline::eval4_de_boor(double x) const {
  const int n = static_cast<int>(coefficients_.size());
  x = std::clamp(x, knots_.front(), knots_.back());
  const int span = find_span(n, degree_, x, knots_);
  const BasisDerivatives b = basis_derivatives(span, x, degree_, knots_);
  Derivatives4 out{};
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j <= degree_; ++j) out[k] += b.ders[k][j] * coefficients_[span - degree_ + j];
  return out;
}

Derivatives3 ClampedBSpline::eval(double x) const {
  const Derivatives4 d = eval4(x);
  return {d[0], d[1], d[2], d[3]};
}

// ---------------------------------------------------------------- periodic

std::optional<PeriodicBSpline> PeriodicBSpline::interpolate(int degree, const std::vector<double>& sites,
                                                            const std::vector<double>& values, double period) {
  const int m = static_cast<int>(sites.size());
  const int p = degree;
  assert(p >= 1 && p <= kMaxSplineDegree && m >= p + 1 && values.size() == sites.size());
  if (m <= 0 || p < 1 || p > kMaxSplineDegree || m < p + 1 || values.size() != sites.size()) return std::nullopt;
  PeriodicBSpline spline;
  spline.degree_ = p;
  spline.period_ = period;
  spline.m_ = m;

  std::vector<double> breaks(sites);
  if (p % 2 == 0) {
    for (int j = 0; j < m; ++j) breaks[j] = 0.5 * (sites[j] + (j + 1 < m ? sites[j + 1] : sites[0] + period));
  }
  // Unwrapped knots: U[k] = breaks[(k − p) mod m] + period · floor((k − p) / m).
  spline.knots_.resize(m + 2 * p + 1);
  for (int k = 0; k < m + 2 * p + 1; ++k) {
    const int q = k - p;
    const int wraps = q >= 0 ? q / m : -((-q + m - 1) / m);
    spline.knots_[k] = breaks[q - wraps * m] + period * wraps;
  }

  std::optional<std::vector<double>> c =
      m <= kDenseCollocation ? solve_dense(spline, sites, values) : solve_banded(spline, sites, values);
  if (!c) return std::nullopt;
  spline.coefficients_ = std::move(*c);
  spline.build_pieces();
  return spline;
}

void PeriodicBSpline::build_pieces() {
  const int p = degree_, w = p + 1;
  if (p > kMaxPieceDegree) return;
  pieces_.assign(static_cast<std::size_t>(m_) * static_cast<std::size_t>(w), 0.0);
  auto derivative = [&](const BasisDerivatives& b, int span, int k) {
    double sum = 0.0;
    for (int j = 0; j <= p; ++j) sum += b.ders[k][j] * coefficients_[(span - p + j) % m_];
    return sum;
  };
  for (int i = 0; i < m_; ++i) {
    const int span = p + i;
    const double x0 = knots_[span], x1 = knots_[span + 1];
    const BasisDerivatives left = basis_derivatives(span, x0, p, knots_);
    std::array<double, kMaxPieceDegree + 1> d{};
    for (int k = 0; k <= std::min(p, 4); ++k) d[k] = derivative(left, span, k);
    if (p == 5) {  // the fifth derivative is constant on the piece: the slope of the fourth
      const BasisDerivatives right = basis_derivatives(span, x1, p, knots_);
      d[5] = (derivative(right, span, 4) - d[4]) / (x1 - x0);
    }
    double factorial = 1.0;
    for (int k = 0; k <= p; ++k) {
      if (k > 0) factorial *= k;
      pieces_[static_cast<std::size_t>(i) * static_cast<std::size_t>(w) + static_cast<std::size_t>(k)] =
          d[k] / factorial;
    }
  }
  const double spacing = period_ / m_;
  uniform_ = true;
  for (int i = 0; i <= m_ && uniform_; ++i)
    uniform_ = std::abs(knots_[p + i] - (knots_[p] + i * spacing)) <= 1e-12 * period_;
  inverse_spacing_ = 1.0 / spacing;
}

void PeriodicBSpline::collocation_row(double site, int& first, std::array<double, kMaxSplineDegree + 1>& row) const {
  const double x = reduce(site);
  const int span = find_span(m_ + degree_, degree_, x, knots_);
  const BasisDerivatives b = basis_derivatives(span, x, degree_, knots_);
  first = span - degree_;
  for (int r = 0; r <= degree_; ++r) row[r] = b.ders[0][r];
}

std::optional<std::vector<double>> PeriodicBSpline::solve_dense(const PeriodicBSpline& spline,
                                                                const std::vector<double>& sites,
                                                                const std::vector<double>& values) {
  const int m = spline.m_, p = spline.degree_;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  Eigen::VectorXd rhs(m);
  std::array<double, kMaxSplineDegree + 1> row{};
  for (int j = 0; j < m; ++j) {
    int first = 0;
    spline.collocation_row(sites[j], first, row);
    for (int r = 0; r <= p; ++r) a(j, (first + r) % m) += row[r];
    rhs(j) = values[j];
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
  // B-spline collocation matrices of reasonable site spacing have rcond ~ 1e-2;
  // far below that the sites are (nearly) coincident or misplaced.
  if (!(lu.rcond() > 1e-10)) return std::nullopt;
  const Eigen::VectorXd c = lu.solve(rhs);
  return std::vector<double>(c.data(), c.data() + m);
}

std::optional<std::vector<double>> PeriodicBSpline::solve_banded(const PeriodicBSpline& spline,
                                                                 const std::vector<double>& sites,
                                                                 const std::vector<double>& values) {
  const int m = spline.m_, p = spline.degree_;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<std::size_t>(m) * static_cast<std::size_t>(p + 1));
  std::array<double, kMaxSplineDegree + 1> row{};
  Eigen::VectorXd rhs(m);
  for (int j = 0; j < m; ++j) {
    int first = 0;
    spline.collocation_row(sites[j], first, row);
    for (int r = 0; r <= p; ++r) entries.emplace_back(j, (first + r) % m, row[r]);
    rhs(j) = values[j];
  }
  Eigen::SparseMatrix<double> a(m, m);
  a.setFromTriplets(entries.begin(), entries.end());  // sums the entries of a wrapped column, as the dense path does
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  lu.compute(a);
  if (lu.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd c = lu.solve(rhs);
  if (lu.info() != Eigen::Success || !c.allFinite()) return std::nullopt;
  // No condition estimate here: a nearly singular system shows as a residual
  // that is not at round-off or as coefficients far larger than the data
  // (interpolating B-spline coefficients stay within a small multiple of it).
  const double scale = rhs.cwiseAbs().maxCoeff() + std::numeric_limits<double>::min();
  if ((a * c - rhs).cwiseAbs().maxCoeff() > 1e-9 * scale || c.cwiseAbs().maxCoeff() > 1e6 * scale) return std::nullopt;
  return std::vector<double>(c.data(), c.data() + m);
}

double PeriodicBSpline::reduce(double x) const {
  const double start = knots_[degree_];
  double y = x - period_ * std::floor((x - start) / period_);
  // Rounding can land y an ulp outside [start, start + period).
  if (y >= start + period_) y -= period_;
  if (y < start) y = start;
  return y;
}

Derivatives4 PeriodicBSpline::eval4(double x) const {
  const int p = degree_;
  const double y = reduce(x);
  if (!pieces_.empty()) {
    int i = 0;
    if (uniform_) {
      i = std::clamp(static_cast<int>((y - knots_[p]) * inverse_spacing_), 0, m_ - 1);
      if (y < knots_[p + i] && i > 0) --i;  // rounding of the index near a breakpoint
      if (y >= knots_[p + i + 1] && i < m_ - 1) ++i;
    } else {
      i = find_span(m_ + p, p, y, knots_) - p;
    }
    // Taylor coefficients at y by repeated synthetic division (Horner).
    std::array<double, kMaxSplineDegree + 1> a{};
    const double* c = &pieces_[static_cast<std::size_t>(i) * static_cast<std::size_t>(p + 1)];
    std::copy(c, c + p + 1, a.begin());
    return taylor_derivatives(a, p, y - knots_[p + i]);
  }
  const int span = find_span(m_ + p, p, y, knots_);
  const BasisDerivatives b = basis_derivatives(span, y, p, knots_);
  Derivatives4 out{};
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j <= p; ++j) out[k] += b.ders[k][j] * coefficients_[(span - p + j) % m_];
  return out;
}

Derivatives3 PeriodicBSpline::eval(double x) const {
  const Derivatives4 d = eval4(x);
  return {d[0], d[1], d[2], d[3]};
}

std::vector<double> PeriodicBSpline::breakpoints() const {
  return {knots_.begin() + degree_, knots_.begin() + degree_ + m_};
}

}  // namespace camdyn
