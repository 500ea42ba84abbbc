#include "geometry/event_spline.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <utility>

#include "common/constants.h"
#include "geometry/bspline.h"

namespace camdyn {

namespace {

/// The event's lift: the clamped spline on x ∈ [0, 1]; returns s itself (the
/// piece has base 0 and lift 1).
class EventShape final : public NormalisedRise {
 public:
  explicit EventShape(ClampedBSpline spline) : spline_(std::move(spline)) {}
  LawSample eval(double x) const override {
    const Derivatives4 d = spline_.eval4(x);
    return {d[0], d[1], d[2], d[3], d[4]};
  }

 private:
  ClampedBSpline spline_;
};

/// Piece `pc` of a law at θ, with MotionLaw::eval's arithmetic.
LawSample piece_sample(const MotionLaw::Piece& pc, double theta) {
  if (!pc.shape) return {pc.base, 0.0, 0.0, 0.0, 0.0};
  const double len = pc.shape_length();
  const LawSample f = pc.shape->eval((theta - pc.shape_origin()) / len);
  const double k1 = pc.lift / len, k2 = k1 / len, k3 = k2 / len;
  return {pc.base + pc.lift * f.s, k1 * f.ds, k2 * f.d2s, k3 * f.d3s, 0.0};
}

/// `pc` restricted to [a, b) ⊆ [pc.start, pc.end), evaluating as before.
MotionLaw::Piece clipped(const MotionLaw::Piece& pc, double a, double b) {
  MotionLaw::Piece out = pc;
  out.origin = pc.shape_origin();
  out.length = pc.shape_length();
  out.start = a;
  out.end = b;
  return out;
}

}  // namespace

int event_join_order(int degree) { return degree >= 4 ? 3 : 2; }

std::array<double, 4> join_values(const MotionLaw& law, double theta, bool from_left) {
  const std::vector<MotionLaw::Piece>& pieces = law.pieces();
  const MotionLaw::Piece* pc = &pieces.front();
  double t = theta;
  if (from_left) {
    if (t <= 0.0) t = kTwoPi;  // the left of 0 is the end of the cycle
    for (const MotionLaw::Piece& p : pieces)
      if (p.start < t) pc = &p;
  } else {
    if (t >= kTwoPi) t = 0.0;
    for (const MotionLaw::Piece& p : pieces)
      if (p.start <= t) pc = &p;
  }
  const LawSample s = piece_sample(*pc, t);
  return {s.s, s.ds, s.d2s, s.d3s};
}

std::vector<double> EventSplineBasis::coefficients(const std::vector<double>& free_points) const {
  assert(static_cast<int>(free_points.size()) == free);
  const int n = count();
  std::vector<double> c(static_cast<std::size_t>(n), 0.0);
  for (int k = 0; k <= order; ++k) {
    c[k] = head[k];
    c[n - 1 - k] = tail[k];
  }
  std::copy(free_points.begin(), free_points.end(), c.begin() + first_free());
  return c;
}

EventSplineBasis event_spline_basis(const MotionLaw& law, double from, double to, int degree, int free) {
  EventSplineBasis b;
  b.degree = degree;
  b.order = event_join_order(degree);
  b.free = free;
  b.from = from;
  b.to = to;
  const int n = b.count(), p = degree;
  b.knots = ClampedBSpline::uniform_knots(p, n);
  const double beta = to - from;
  // The joins' derivatives in x = (θ − from) / β: s⁽ᵏ⁾ βᵏ.
  const std::array<double, 4> v0 = join_values(law, from, true), v1 = join_values(law, to, false);
  // At a clamped end only the first k + 1 basis functions have a nonzero k-th
  // derivative, so each join is a triangular solve.
  const BasisDerivatives b0 = basis_derivatives(p, 0.0, p, b.knots);
  const BasisDerivatives b1 = basis_derivatives(n - 1, 1.0, p, b.knots);
  const std::size_t joined = static_cast<std::size_t>(b.order) + 1;  // s, s', ..., up to the join's order
  b.head.assign(joined, 0.0);
  b.tail.assign(joined, 0.0);
  double scale = 1.0;
  for (int k = 0; k <= b.order; ++k) {
    double r0 = v0[k] * scale, r1 = v1[k] * scale;
    for (int i = 0; i < k; ++i) {
      r0 -= b0.ders[k][i] * b.head[i];
      r1 -= b1.ders[k][p - i] * b.tail[i];
    }
    b.head[k] = r0 / b0.ders[k][k];
    b.tail[k] = r1 / b1.ders[k][p - k];
    scale *= beta;
  }
  return b;
}

MotionLaw splice_event(const MotionLaw& law, const EventSplineBasis& basis, const std::vector<double>& free_points) {
  std::vector<MotionLaw::Piece> pieces;
  for (const MotionLaw::Piece& pc : law.pieces())
    if (pc.start < basis.from) pieces.push_back(clipped(pc, pc.start, std::min(pc.end, basis.from)));
  MotionLaw::Piece event;
  event.start = basis.from;
  event.end = basis.to;
  event.base = 0.0;
  event.lift = 1.0;
  event.shape =
      std::make_shared<EventShape>(ClampedBSpline(basis.degree, basis.knots, basis.coefficients(free_points)));
  pieces.push_back(event);
  for (const MotionLaw::Piece& pc : law.pieces())
    if (pc.end > basis.to) pieces.push_back(clipped(pc, std::max(pc.start, basis.to), pc.end));
  return MotionLaw(std::move(pieces));
}

std::size_t event_piece_index(const MotionLaw& spliced, const EventSplineBasis& basis) {
  const std::vector<MotionLaw::Piece>& pieces = spliced.pieces();
  for (std::size_t i = 0; i < pieces.size(); ++i)
    if (pieces[i].start == basis.from && pieces[i].end == basis.to) return i;
  assert(false);
  return 0;
}

}  // namespace camdyn
