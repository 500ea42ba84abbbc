// A planar vector over any scalar type S (double, or the dual numbers of
// dynamics/dual.h), for kinematics written once and evaluated both for the
// right-hand side and for its exact Jacobian. J v is v turned by +90°.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace camdyn {

template <class S>
struct Vec2 {
  S x{}, y{};
  Vec2() = default;
  Vec2(const S& x_, const S& y_) : x(x_), y(y_) {}
  /// Lifts a double vector (constant) into S.
  explicit Vec2(const Eigen::Vector2d& v) : x(v.x()), y(v.y()) {}
};

template <class S>
Vec2<S> operator+(const Vec2<S>& a, const Vec2<S>& b) {
  return {a.x + b.x, a.y + b.y};
}
template <class S>
Vec2<S> operator-(const Vec2<S>& a, const Vec2<S>& b) {
  return {a.x - b.x, a.y - b.y};
}
template <class S>
Vec2<S> operator-(const Vec2<S>& a) {
  return {-a.x, -a.y};
}
template <class S, class K>
Vec2<S> operator*(const K& k, const Vec2<S>& a) {
  return {k * a.x, k * a.y};
}
template <class S>
S dot(const Vec2<S>& a, const Vec2<S>& b) {
  return a.x * b.x + a.y * b.y;
}
/// a × b (z-component).
template <class S>
S cross(const Vec2<S>& a, const Vec2<S>& b) {
  return a.x * b.y - a.y * b.x;
}
/// J a: a turned by +90°.
template <class S>
Vec2<S> perp(const Vec2<S>& a) {
  return {-a.y, a.x};
}
/// R(angle) a with c = cos(angle), s = sin(angle).
template <class S, class C>
Vec2<S> rotate(const Vec2<S>& a, const C& c, const C& s) {
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}
/// J v for a double vector: v turned by +90°.
inline Eigen::Vector2d perp(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }
/// a × b (z-component) of double vectors.
inline double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }
/// v turned by `angle` [rad].
inline Eigen::Vector2d rotate(const Eigen::Vector2d& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
}
/// The value of a scalar (dual numbers overload it in their namespace).
inline double value(double x) { return x; }
template <class S>
Eigen::Vector2d to_eigen(const Vec2<S>& a) {
  return {value(a.x), value(a.y)};
}

}  // namespace camdyn
