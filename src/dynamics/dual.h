// Forward-mode dual numbers with a fixed number of directional derivatives,
// for the exact state Jacobian of the mechanism (dynamics/model.cc evaluates
// one templated right-hand side with double or Dual<N> scalars). Fixed size,
// no heap allocation. Only the operations the model uses are provided.
#pragma once

#include <array>
#include <cmath>

#include "geometry/vec2.h"  // value(double)

namespace camdyn {

template <int N>
struct Dual {
  double v = 0.0;             ///< value
  std::array<double, N> d{};  ///< derivatives with respect to the N seeds

  Dual() = default;
  Dual(double value) : v(value) {}  // NOLINT(google-explicit-constructor): constants mix freely
  /// The seed variable i with value `value`.
  static Dual variable(double value, int i) {
    Dual x(value);
    x.d[i] = 1.0;
    return x;
  }
};

template <int N>
double value(const Dual<N>& x) {
  return x.v;
}

template <int N>
Dual<N> chain(const Dual<N>& x, double f, double df) {  // f(x) with f'(x) = df
  Dual<N> r(f);
  for (int i = 0; i < N; ++i) r.d[i] = df * x.d[i];
  return r;
}

template <int N>
Dual<N> operator-(const Dual<N>& a) {
  return chain(a, -a.v, -1.0);
}
template <int N>
Dual<N> operator+(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.v + b.v);
  for (int i = 0; i < N; ++i) r.d[i] = a.d[i] + b.d[i];
  return r;
}
template <int N>
Dual<N> operator-(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.v - b.v);
  for (int i = 0; i < N; ++i) r.d[i] = a.d[i] - b.d[i];
  return r;
}
template <int N>
Dual<N> operator*(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.v * b.v);
  for (int i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
  return r;
}
template <int N>
Dual<N> operator/(const Dual<N>& a, const Dual<N>& b) {
  Dual<N> r(a.v / b.v);
  const double inv = 1.0 / b.v;
  for (int i = 0; i < N; ++i) r.d[i] = (a.d[i] - r.v * b.d[i]) * inv;
  return r;
}
template <int N>
Dual<N> operator+(const Dual<N>& a, double b) {
  return chain(a, a.v + b, 1.0);
}
template <int N>
Dual<N> operator+(double a, const Dual<N>& b) {
  return chain(b, a + b.v, 1.0);
}
template <int N>
Dual<N> operator-(const Dual<N>& a, double b) {
  return chain(a, a.v - b, 1.0);
}
template <int N>
Dual<N> operator-(double a, const Dual<N>& b) {
  return chain(b, a - b.v, -1.0);
}
template <int N>
Dual<N> operator*(const Dual<N>& a, double b) {
  return chain(a, a.v * b, b);
}
template <int N>
Dual<N> operator*(double a, const Dual<N>& b) {
  return chain(b, a * b.v, a);
}
template <int N>
Dual<N> operator/(const Dual<N>& a, double b) {
  return chain(a, a.v / b, 1.0 / b);
}
template <int N>
Dual<N> operator/(double a, const Dual<N>& b) {
  return chain(b, a / b.v, -a / (b.v * b.v));
}
template <int N>
Dual<N>& operator+=(Dual<N>& a, const Dual<N>& b) {
  return a = a + b;
}
template <int N>
Dual<N>& operator-=(Dual<N>& a, const Dual<N>& b) {
  return a = a - b;
}

template <int N>
Dual<N> sin(const Dual<N>& x) {
  return chain(x, std::sin(x.v), std::cos(x.v));
}
template <int N>
Dual<N> cos(const Dual<N>& x) {
  return chain(x, std::cos(x.v), -std::sin(x.v));
}
template <int N>
Dual<N> tanh(const Dual<N>& x) {
  const double t = std::tanh(x.v);
  return chain(x, t, 1.0 - t * t);
}
/// √x; x > 0 (callers keep away from 0, where the derivative is infinite).
template <int N>
Dual<N> sqrt(const Dual<N>& x) {
  const double r = std::sqrt(x.v);
  return chain(x, r, 0.5 / r);
}
/// x^p for x > 0.
template <int N>
Dual<N> pow(const Dual<N>& x, double p) {
  const double r = std::pow(x.v, p);
  return chain(x, r, p * r / x.v);
}
/// |x|, with the derivative of the side x lies on (0 at x = 0).
template <int N>
Dual<N> abs(const Dual<N>& x) {
  return chain(x, std::abs(x.v), x.v > 0.0 ? 1.0 : (x.v < 0.0 ? -1.0 : 0.0));
}

}  // namespace camdyn
