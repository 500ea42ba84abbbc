#include "dynamics/free_flight.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/constants.h"

namespace camdyn {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kNearDeg = 0.5;       // interval near the cam [deg of cam rotation]
constexpr double kFarDeg = 5.0;        // longest interval [deg]
constexpr int kProfileSamples = 1024;  // the bound adds the bulge between samples

// Radius of a circle about the cam centre that holds the whole profile [m]:
// the largest sampled radius plus what the curve can bulge between samples.
double bounding_radius(const PeriodicCurve& profile) {
  double r_max = 0.0, rate_max = 0.0;
  for (int i = 0; i < kProfileSamples; ++i) {
    const CurvePoint p = profile.at(kTwoPi * i / kProfileSamples);
    r_max = std::max(r_max, p.r.norm());
    rate_max = std::max(rate_max, p.dr.norm());
  }
  return r_max + rate_max * kTwoPi / kProfileSamples;
}

// Minimum over s in (0, 1] of the cubic Hermite interpolant with values p0, p1
// and slopes m0, m1 (per unit s); `s_min` is where it is attained. The start
// is left out: it is the open end of a flight interval, or the flight's start.
double hermite_minimum(double p0, double m0, double p1, double m1, double& s_min) {
  auto value = [&](double s) {
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * m0 + (-2 * s3 + 3 * s2) * p1 + (s3 - s2) * m1;
  };
  double best = p1;
  s_min = 1.0;
  // p'(s) = A s² + B s + C.
  const double A = 6 * p0 + 3 * m0 - 6 * p1 + 3 * m1, B = -6 * p0 - 4 * m0 + 6 * p1 - 2 * m1, C = m0;
  std::array<double, 2> roots{-1.0, -1.0};
  if (std::abs(A) < 1e-300) {
    if (std::abs(B) > 1e-300) roots[0] = -C / B;
  } else {
    const double disc = B * B - 4 * A * C;
    if (disc >= 0.0) {
      const double q = -0.5 * (B + std::copysign(std::sqrt(disc), B));
      roots[0] = q / A;
      if (q != 0.0) roots[1] = C / q;
    }
  }
  for (double s : roots) {
    if (s > 0.0 && s < 1.0 && value(s) < best) {
      best = value(s);
      s_min = s;
    }
  }
  return best;
}

// ∫ of the Hermite cubic through (0, g0, ġ0) and (h, g1, ġ1) over [0, h].
double hermite_integral(double h, double g0, double r0, double g1, double r1) {
  return 0.5 * h * (g0 + g1) + h * h * (r0 - r1) / 12.0;
}

}  // namespace

bool flight_has_closed_form(const Model& model) { return flight_has_closed_form(model, follower_linear_parts(model)); }

bool flight_has_closed_form(const Model& model, const std::optional<FollowerLinearParts>& linear) {
  const StateLayout& l = model.layout;
  const int extra = (l.u ? 1 : 0) + (l.spin ? 1 : 0);
  return !model.drive.shaft() && model.pair_form == PairForm::reduced && !l.v && linear &&
         linear->total().stiffness >= 0.0 && model.mass > 0.0 && l.size == 2 + extra && !model.train.present();
}

// ------------------------------------------------------------------ FreeFlight

namespace {

// The sum of the model's follower forces' linear parts; throws without one.
LinearPart flight_forces(const Model& model) {
  const std::optional<FollowerLinearParts> parts = follower_linear_parts(model);
  if (!parts) throw std::invalid_argument(std::string("free flight in closed form: ") + kNoLinearPart);
  return parts->total();
}

}  // namespace

FreeFlight::FreeFlight(const Model& model) : FreeFlight(model, flight_forces(model)) {}

// F₀ = the spring's preload + M g, summed in that order (follower_forces.h).
FreeFlight::FreeFlight(const Model& model, const LinearPart& linear)
    : c_half_(0.5 * linear.damping / model.mass),
      omega2_(linear.stiffness / model.mass),
      b2_(omega2_ - c_half_ * c_half_),
      load_(linear.load / model.mass),
      q_eq_(linear.stiffness > 0.0 ? -linear.load / linear.stiffness : 0.0) {}

void FreeFlight::start(double t0, double q0, double v0) {
  t0_ = t0;
  q0_ = q0;
  v0_ = v0;
}

void FreeFlight::at(double t, double& q, double& v) const {
  const double tau = t - t0_;
  if (omega2_ == 0.0) {  // no spring: q̈ = −2a q̇ − load
    const double lambda = 2.0 * c_half_;
    if (lambda * tau < 1e-4) {  // series of the exponentials: relative error below 1e-17
      const double z = lambda * tau;
      const double e1 = tau * (1.0 - z / 2.0 + z * z / 6.0 - z * z * z / 24.0);          // (1 − e^{−λτ}) / λ
      const double e2 = tau * tau * (0.5 - z / 6.0 + z * z / 24.0 - z * z * z / 120.0);  // (τ − e1) / λ
      v = v0_ * (1.0 - z + z * z / 2.0 - z * z * z / 6.0) - load_ * e1;
      q = q0_ + v0_ * e1 - load_ * e2;
    } else {
      const double decay = std::exp(-lambda * tau), e1 = -std::expm1(-lambda * tau) / lambda;
      v = v0_ * decay - load_ * e1;
      q = q0_ + v0_ * e1 - load_ * (tau - e1) / lambda;
    }
    return;
  }
  // x = q − q_eq obeys ẍ + 2a ẋ + ω² x = 0: x = e^{−aτ} (x₀ C + (v₀ + a x₀) S)
  // with C = cos bτ, S = sin(bτ)/b, b² = ω² − a² (cosh and sinh when b² < 0).
  const double x0 = q0_ - q_eq_, a = c_half_;
  const double z = b2_ * tau * tau;
  double ec = 0.0, es = 0.0;  // e^{−aτ} C, e^{−aτ} S
  if (std::abs(z) < 1e-6) {
    const double decay = std::exp(-a * tau);
    ec = decay * (1.0 - z / 2.0 + z * z / 24.0);
    es = decay * tau * (1.0 - z / 6.0 + z * z / 120.0);
  } else if (b2_ > 0.0) {
    const double b = std::sqrt(b2_), decay = std::exp(-a * tau);
    ec = decay * std::cos(b * tau);
    es = decay * std::sin(b * tau) / b;
  } else {  // overdamped: both exponents negative, no overflow
    const double beta = std::sqrt(-b2_);
    const double e1 = std::exp((beta - a) * tau), e2 = std::exp(-(beta + a) * tau);
    ec = 0.5 * (e1 + e2);
    es = 0.5 * (e1 - e2) / beta;
  }
  q = q_eq_ + x0 * ec + (v0_ + a * x0) * es;
  v = v0_ * ec - (a * v0_ + omega2_ * x0) * es;
}

double FreeFlight::speed_bound(double q, double v, double h) const {
  // With a spring, V = √(v² + ω² x²) never grows (the rate of V² is −4a v²),
  // so |q̇| ≤ V, and |q̈| ≤ ω |x| + 2a |q̇| ≤ (ω + 2a) V changes q̇ by at most
  // (ω + 2a) V h. Without a spring the load changes it by at most (load + 2a |v|) h.
  if (omega2_ > 0.0) {
    const double amplitude = std::sqrt(v * v + omega2_ * (q - q_eq_) * (q - q_eq_));
    return std::min(amplitude, std::abs(v) + (std::sqrt(omega2_) + 2.0 * c_half_) * amplitude * h);
  }
  return std::abs(v) + (std::abs(load_) + 2.0 * c_half_ * std::abs(v)) * h;
}

// ----------------------------------------------------------------- FlightTrack

FlightTrack::FlightTrack(const Model& model)
    : model_(model), newton_(model), flight_(model), damping_(flight_forces(model).damping) {
  newton_.tracking = Tracking::newton;
  r_max_ = bounding_radius(model.profile());
  const FollowerGeometry& f = model.follower;
  // |∂g/∂q|: 1 for a translating follower; for an arm, the distance from its
  // pivot to any point that can touch the cam.
  lever_ = f.oscillating() ? f.pivot.norm() + r_max_ + f.radius + f.face_width : 1.0;
  const double omega = std::max(model.omega, 1e-300);
  h_near_ = model.omega > 0.0 ? kNearDeg * kDegree / omega : 1e-3;
  h_far_ = model.omega > 0.0 ? kFarDeg * kDegree / omega : 1e-2;
}

void FlightTrack::start(const FlightPoint& p) {
  a_ = p;
  b_ = p;
  flight_.start(p.t, p.q, p.v);
}

bool FlightTrack::point(Workspace& ws, double t, double u_warm, FlightPoint& p) {
  std::array<double, StateLayout::kMax> y{};
  p.t = t;
  flight_.at(t, p.q, p.v);
  y[0] = p.q;
  y[1] = p.v;
  ws.u_warm = u_warm;
  evaluate(newton_, ws, t, y.data(), ev_);
  if (!ev_.tracking_ok) return false;
  p.u = ev_.pair.u;
  p.gap = ev_.gap;
  p.gap_rate = ev_.gap_rate;
  return true;
}

double FlightTrack::damper_work(double ta, double tb) const {
  if (damping_ == 0.0 || tb <= ta) return 0.0;
  // Four-point Gauss–Legendre on c q̇²: q̇ is smooth over an interval of a few degrees.
  constexpr std::array<double, 4> x{-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  constexpr std::array<double, 4> w{0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  const double mid = 0.5 * (ta + tb), half = 0.5 * (tb - ta);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    double q = 0.0, v = 0.0;
    flight_.at(mid + half * x[i], q, v);
    sum += w[i] * v * v;
  }
  return damping_ * half * sum;
}

// The longest interval from p over which the gap provably stays above half
// its value: the closing speed is at most |∂g/∂q| |q̇| + |∂g/∂θ| ω, and
// |∂g/∂θ| ≤ R, the bounding radius. (A circle centre C against the profile
// point P: ∂g/∂θ = n · (−σ C⊥), and n ∥ C − P leaves n · P⊥; a face with
// normal m: ∂g/∂θ = −σ m⊥ · P.)
double FlightTrack::safe_interval(const FlightPoint& p) const {
  const double half_gap = 0.5 * p.gap;
  const double closing = lever_ * flight_.speed_bound(p.q, p.v, h_far_) + r_max_ * model_.omega;
  return closing > 0.0 ? half_gap / closing : h_far_;
}

bool FlightTrack::advance(Workspace& ws, double t_stop, bool& ok) {
  ok = true;
  a_ = b_;
  const double safe = safe_interval(a_);
  const bool checked = safe < h_near_;  // too close to rule contact out: the Hermite check decides
  const double h = std::min(std::max(safe, h_near_), h_far_);
  const double t_b = std::min(a_.t + h, t_stop);
  // Warm start: the pair parameter extrapolated along the last interval.
  if (!point(ws, t_b, b_.u, b_)) return ok = false;
  ++intervals_;
  b_.damper_work = a_.damper_work + damper_work(a_.t, b_.t);
  b_.separation = a_.separation + hermite_integral(b_.t - a_.t, a_.gap, a_.gap_rate, b_.gap, b_.gap_rate);
  if (b_.gap > 0.0 && !checked) return false;
  FlightPoint hi = b_;
  if (hi.gap > 0.0) {
    // A dip of the gap inside the interval that the end points do not show.
    const double dt = b_.t - a_.t;
    double s = 0.0;
    if (hermite_minimum(a_.gap, a_.gap_rate * dt, b_.gap, b_.gap_rate * dt, s) > 0.0) return false;
    FlightPoint mid;
    if (!point(ws, a_.t + s * dt, a_.u, mid)) return ok = false;
    if (mid.gap > 0.0) return false;  // the cubic was wrong, the gap stays open
    hi = mid;
  }
  FlightPoint landing;
  if (!refine_landing(ws, a_, hi, landing)) return ok = false;
  landing.damper_work = a_.damper_work + damper_work(a_.t, landing.t);
  landing.separation = a_.separation + hermite_integral(landing.t - a_.t, a_.gap, a_.gap_rate, 0.0, landing.gap_rate);
  b_ = landing;
  return true;
}

// Illinois (modified regula falsi) on the gap between lo (open) and hi (closed),
// down to adjacent times: the landing is the closed end.
bool FlightTrack::refine_landing(Workspace& ws, FlightPoint lo, FlightPoint hi, FlightPoint& landing) {
  int side = 0;
  double g_lo = lo.gap, g_hi = hi.gap;
  for (int it = 0; it < 200; ++it) {
    const double width = hi.t - lo.t;
    if (width <= 4.0 * std::numeric_limits<double>::epsilon() * std::abs(hi.t) || hi.gap == 0.0) break;
    double t = hi.t - g_hi * width / (g_hi - g_lo);
    if (!(t > lo.t && t < hi.t)) t = lo.t + 0.5 * width;
    FlightPoint m;
    if (!point(ws, t, lo.u, m)) return false;
    if (m.gap > 0.0) {
      lo = m;
      g_lo = m.gap;
      if (side == -1) g_hi *= 0.5;
      side = -1;
    } else {
      hi = m;
      g_hi = m.gap;
      if (side == +1) g_lo *= 0.5;
      side = +1;
    }
  }
  landing = hi;
  return true;
}

double FlightTrack::largest_gap() const {
  const double dt = b_.t - a_.t;
  double s = 0.0;
  return -hermite_minimum(-a_.gap, -a_.gap_rate * dt, -b_.gap, -b_.gap_rate * dt, s);
}

bool FlightTrack::at(Workspace& ws, double t, FlightPoint& p) {
  if (t == b_.t) {  // the interval's end, solved already
    p = b_;
    return true;
  }
  if (!point(ws, t, a_.u, p)) return false;
  p.damper_work = a_.damper_work + damper_work(a_.t, t);
  p.separation = a_.separation + hermite_integral(t - a_.t, a_.gap, a_.gap_rate, p.gap, p.gap_rate);
  return true;
}

}  // namespace camdyn
