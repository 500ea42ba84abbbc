#include "geometry/motion_law.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numbers>
#include <utility>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/bspline.h"
#include "geometry/event_spline.h"

namespace camdyn {

namespace {

double deg_to_rad(double deg) { return deg * (kPi / 180.0); }

std::string num10(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string indexed(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// ---------------------------------------------------------------- classic rises

/// Cycloidal: f = x − sin(2πx)/2π; zero velocity and acceleration at both ends.
class Cycloidal final : public NormalisedRise {
 public:
  LawSample eval(double x) const override {
    const double w = kTwoPi * x;
    return {x - std::sin(w) / kTwoPi, 1.0 - std::cos(w), kTwoPi * std::sin(w), kTwoPi * kTwoPi * std::cos(w),
            -kTwoPi * kTwoPi * kTwoPi * std::sin(w)};
  }
};

/// Simple harmonic: f = (1 − cos πx)/2; zero velocity but ±π²/2 acceleration at the ends.
class Harmonic final : public NormalisedRise {
 public:
  LawSample eval(double x) const override {
    const double w = kPi * x;
    return {0.5 * (1.0 - std::cos(w)), 0.5 * kPi * std::sin(w), 0.5 * kPi * kPi * std::cos(w),
            -0.5 * kPi * kPi * kPi * std::sin(w), -0.5 * kPi * kPi * kPi * kPi * std::cos(w)};
  }
};

/// Polynomial f = Σ c_i x^i.
class Polynomial final : public NormalisedRise {
 public:
  explicit Polynomial(std::array<double, 8> c) : c_(c) {}
  LawSample eval(double x) const override {
    double d[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
    // Horner on each derivative: d^k/dx^k Σ c_i x^i = Σ_{i ≥ k} c_i i!/(i − k)! x^{i − k}.
    for (int k = 0; k < 5; ++k) {
      for (int i = 7; i >= k; --i) {
        double falling = 1.0;
        for (int j = 0; j < k; ++j) falling *= i - j;
        d[k] = d[k] * x + c_[i] * falling;
      }
    }
    return {d[0], d[1], d[2], d[3], d[4]};
  }

 private:
  std::array<double, 8> c_;
};

/// A rise whose acceleration is piecewise c0 + c1·sin(ω(x − x0) + ψ), integrated
/// exactly from f(0) = f'(0) = 0 and scaled so that f(1) = 1. This gives the
/// modified sine and modified trapezoid laws without rounded textbook
/// coefficients.
class PiecewiseSinusoidRise final : public NormalisedRise {
 public:
  struct Span {
    double x0;                  ///< start of the span (spans are contiguous, the first at 0)
    double c0, c1;              ///< constant and sinusoid amplitude of the unscaled acceleration
    double omega;               ///< angular frequency in x (any nonzero value when c1 = 0)
    double psi;                 ///< phase at x0
    double v0 = 0.0, f0 = 0.0;  ///< unscaled f' and f at x0 (filled by the constructor)
  };

  explicit PiecewiseSinusoidRise(std::vector<Span> spans) : spans_(std::move(spans)) {
    double v = 0.0, f = 0.0;
    for (std::size_t i = 0; i < spans_.size(); ++i) {
      spans_[i].v0 = v;
      spans_[i].f0 = f;
      const double x1 = i + 1 < spans_.size() ? spans_[i + 1].x0 : 1.0;
      const LawSample end = unscaled(spans_[i], x1 - spans_[i].x0);
      v = end.ds;
      f = end.s;
    }
    // The shapes are antisymmetric in acceleration, so the velocity returns to 0.
    assert(std::abs(v) < 1e-12);
    scale_ = 1.0 / f;
  }

  LawSample eval(double x) const override {
    std::size_t i = spans_.size() - 1;
    while (i > 0 && x < spans_[i].x0) --i;
    const LawSample u = unscaled(spans_[i], x - spans_[i].x0);
    return {scale_ * u.s, scale_ * u.ds, scale_ * u.d2s, scale_ * u.d3s, scale_ * u.d4s};
  }

 private:
  static LawSample unscaled(const Span& sp, double t) {
    const double w = sp.omega, phase = sp.omega * t + sp.psi;
    const double k = sp.c1 / w;
    return {
        sp.f0 + sp.v0 * t + 0.5 * sp.c0 * t * t - k * ((std::sin(phase) - std::sin(sp.psi)) / w - t * std::cos(sp.psi)),
        sp.v0 + sp.c0 * t - k * (std::cos(phase) - std::cos(sp.psi)), sp.c0 + sp.c1 * std::sin(phase),
        sp.c1 * w * std::cos(phase), -sp.c1 * w * w * std::sin(phase)};
  }

  std::vector<Span> spans_;
  double scale_ = 1.0;
};

std::shared_ptr<const NormalisedRise> modified_sine() {
  // a ∝ sin 4πx on [0, 1/8], cos((4π/3)(x − 1/8)) on [1/8, 7/8], sin 4πx on [7/8, 1].
  constexpr double w = 4.0 * kPi;
  return std::make_shared<PiecewiseSinusoidRise>(std::vector<PiecewiseSinusoidRise::Span>{
      {0.0, 0.0, 1.0, w, 0.0},
      {0.125, 0.0, 1.0, w / 3.0, 0.5 * kPi},
      {0.875, 0.0, 1.0, w, 1.5 * kPi},
  });
}

std::shared_ptr<const NormalisedRise> modified_trapezoid() {
  // a ∝ sin 4πx, 1, sin(4πx − π), −1, sin 4πx on the eighths 1, 2, 2, 2, 1.
  constexpr double w = 4.0 * kPi;
  return std::make_shared<PiecewiseSinusoidRise>(std::vector<PiecewiseSinusoidRise::Span>{
      {0.0, 0.0, 1.0, w, 0.0},
      {0.125, 1.0, 0.0, 1.0, 0.0},
      {0.375, 0.0, 1.0, w, 0.5 * kPi},
      {0.625, -1.0, 0.0, 1.0, 0.0},
      {0.875, 0.0, 1.0, w, 1.5 * kPi},
  });
}

// ---------------------------------------------------------------- spline shapes

/// A spline segment's normalised rise: clamped B-spline on x ∈ [0, 1].
class SplineRise final : public NormalisedRise {
 public:
  explicit SplineRise(ClampedBSpline spline) : spline_(std::move(spline)) {}
  LawSample eval(double x) const override {
    const Derivatives4 d = spline_.eval4(x);
    return {d[0], d[1], d[2], d[3], d[4]};
  }

 private:
  ClampedBSpline spline_;
};

/// A whole-cycle periodic spline with parameter x = θ/2π; returns s itself [m].
class PeriodicShape final : public NormalisedRise {
 public:
  explicit PeriodicShape(PeriodicBSpline spline) : spline_(std::move(spline)) {}
  LawSample eval(double x) const override {
    const Derivatives4 d = spline_.eval4(x);
    return {d[0], d[1], d[2], d[3], d[4]};
  }

 private:
  PeriodicBSpline spline_;
};

// ---------------------------------------------------------------- segments

/// A validated segment.
struct Segment {
  double start = 0.0, end = 0.0;  ///< [rad]
  double lift = 0.0;              ///< signed [m or rad]; 0 for a dwell
  bool spline = false;
  std::shared_ptr<const NormalisedRise> shape;  ///< classic law; spline: built later
};

/// s' and s'' [per rad] at the start (x = 0) or end (x = 1) of a segment, as a
/// spline neighbour sees them. A dwell has none, and a neighbouring spline
/// segment is taken to have zero velocity and acceleration at the shared
/// boundary: its own boundary points are built from this same assumption, so
/// both sides agree without solving the two splines together.
std::pair<double, double> boundary_rates(const Segment& seg, double x) {
  if (!seg.shape || seg.spline) return {0.0, 0.0};
  const double len = seg.end - seg.start;
  const LawSample f = seg.shape->eval(x);
  return {seg.lift * f.ds / len, seg.lift * f.d2s / (len * len)};
}

/// Builds the clamped spline of a spline segment: p + 1 ≤ n = free + 6 control
/// points, uniform interior knots, and the 3 control points at each end chosen
/// so that f, f', f'' match (f(0), f'(0), f''(0)) = (0, d0[0], d0[1]) and
/// (f(1), f'(1), f''(1)) = (1, d1[0], d1[1]), in the normalised variable.
std::shared_ptr<const NormalisedRise> spline_segment_shape(int p, const std::vector<double>& free,
                                                           std::array<double, 2> d0, std::array<double, 2> d1) {
  const int n = static_cast<int>(free.size()) + 6;
  std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
  std::vector<double> c(n, 0.0);
  std::copy(free.begin(), free.end(), c.begin() + 3);

  // At a clamped end only the first k + 1 basis functions have a nonzero k-th
  // derivative, so the boundary conditions form a triangular system.
  const std::array<double, 3> start_values = {0.0, d0[0], d0[1]};
  const BasisDerivatives b0 = basis_derivatives(p, 0.0, p, knots);  // N_0..N_p
  for (int k = 0; k < 3; ++k) {
    double r = start_values[k];
    for (int i = 0; i < k; ++i) r -= b0.ders[k][i] * c[i];
    c[k] = r / b0.ders[k][k];
  }
  const std::array<double, 3> end_values = {1.0, d1[0], d1[1]};
  const BasisDerivatives b1 = basis_derivatives(n - 1, 1.0, p, knots);  // N_{n−1−p}..N_{n−1}
  for (int k = 0; k < 3; ++k) {
    double r = end_values[k];
    for (int i = 0; i < k; ++i) r -= b1.ders[k][p - i] * c[n - 1 - i];
    c[n - 1 - k] = r / b1.ders[k][p - k];
  }
  return std::make_shared<SplineRise>(ClampedBSpline(p, std::move(knots), std::move(c)));
}

/// Units and totals of the rise / return lifts, gathered while reading the segments.
struct LiftTotals {
  double rise = 0.0, ret = 0.0;  ///< sums of the rise and return lifts [m or rad]
  double since_return = 0.0;     ///< rises since the last return [m or rad]: what a return without a lift takes
  int in_deg = -1;               ///< unit of the first rise/return: 0 metres, 1 degrees
};

/// Checks the end angle of segment `sc` (at `at`) and sets seg.start / seg.end [rad];
/// prev_end_deg [deg] moves on to this segment's end.
/// The shortest segment [deg].
constexpr double kMinSegmentSpanDeg = 1e-6;

void read_segment_span(const SegmentConfig& sc, bool last, const std::string& file, const std::string& at,
                       double& prev_end_deg, Segment& seg) {
  if (!std::isfinite(sc.end_deg) || sc.end_deg <= prev_end_deg)
    throw InputError(
        file, at + ".end_deg",
        num10(sc.end_deg) + " must be greater than where the segment starts (" + num10(prev_end_deg) + "°)");
  if (sc.end_deg > 360.0) throw InputError(file, at + ".end_deg", num10(sc.end_deg) + " is beyond 360°");
  // A span too short to turn through: its law's derivatives (1/span^k) overflow,
  // and a denormal span vanishes in radians.
  if (sc.end_deg - prev_end_deg < kMinSegmentSpanDeg)
    throw InputError(file, at + ".end_deg",
                     "the segment spans " + num10(sc.end_deg - prev_end_deg) + "° (from " + num10(prev_end_deg) +
                         "° to " + num10(sc.end_deg) + "°): at least " + num10(kMinSegmentSpanDeg) + "° is needed");
  seg.start = deg_to_rad(prev_end_deg);
  seg.end = last ? kTwoPi : deg_to_rad(sc.end_deg);
  prev_end_deg = sc.end_deg;
}

/// Checks the lift of a rise / return segment, sets seg.lift (signed [m or rad])
/// and adds it to the totals. A return without a lift goes back down by the
/// rises since the last return, to the level the follower rose from.
void read_segment_lift(const SegmentConfig& sc, const std::string& file, const std::string& at, LiftTotals& totals,
                       Segment& seg) {
  if (sc.type == SegmentType::return_ && !sc.lift && !sc.lift_deg) {
    if (totals.since_return <= 0.0)
      throw InputError(file, at + ".lift",
                       "missing: there is no rise since the last return to go back down from (give 'lift' [m] or "
                       "'lift_deg')");
    totals.ret += totals.since_return;
    seg.lift = -totals.since_return;
    totals.since_return = 0.0;
    return;
  }
  if (sc.lift.has_value() == sc.lift_deg.has_value())
    throw InputError(file, at,
                     "give exactly one of lift [m] (translating follower) or lift_deg "
                     "(oscillating follower)");
  const int in_deg = sc.lift_deg ? 1 : 0;
  const std::string lift_path = at + (in_deg ? ".lift_deg" : ".lift");
  if (totals.in_deg >= 0 && totals.in_deg != in_deg)
    throw InputError(file, lift_path, "mixes lift and lift_deg segments in one law");
  totals.in_deg = in_deg;
  const double given = in_deg ? *sc.lift_deg : *sc.lift;
  if (!std::isfinite(given) || given <= 0.0) throw InputError(file, lift_path, num10(given) + " must be > 0");
  const double lift = in_deg ? deg_to_rad(given) : given;
  const bool rise = sc.type == SegmentType::rise;
  (rise ? totals.rise : totals.ret) += lift;
  totals.since_return = rise ? totals.since_return + lift : 0.0;
  seg.lift = rise ? lift : -lift;
}

/// Checks the law of a rise / return segment: a spline's degree and control
/// points, or a classic law, whose shape it sets (a spline's is built later).
void read_segment_law(const SegmentConfig& sc, const std::string& file, const std::string& at, Segment& seg) {
  if (sc.law == SegmentLaw::spline) {
    seg.spline = true;
    if (sc.degree < 3 || sc.degree > kMaxSplineDegree)
      throw InputError(file, at + ".degree",
                       std::to_string(sc.degree) + " must be in [3, " + std::to_string(kMaxSplineDegree) + "]");
    const std::size_t total = sc.control_points.size() + 6;
    if (total < static_cast<std::size_t>(sc.degree) + 1)
      throw InputError(
          file, at + ".control_points",
          "a degree-" + std::to_string(sc.degree) + " spline needs at least " + std::to_string(sc.degree + 1) +
              " control points: 6 boundary ones (added by the program) plus at "
              "least " +
              std::to_string(sc.degree - 5) + " free ones, " + std::to_string(sc.control_points.size()) + " given");
    for (std::size_t j = 0; j < sc.control_points.size(); ++j)
      if (!std::isfinite(sc.control_points[j]))
        throw InputError(file, indexed(at + ".control_points", j), "must be finite");
  } else {
    if (!sc.control_points.empty())
      throw InputError(file, at + ".control_points", "only a spline segment has control points");
    seg.shape = classic_rise(sc.law);
    if (!seg.shape) {
      std::string names;
      for (const SegmentLaw law : classic_rise_laws()) names += to_string(law) + ", ";
      throw InputError(file, at + ".law", "unknown law '" + to_string(sc.law) + "' (use " + names + "spline)");
    }
  }
}

/// The validated segments of `configs` (spline shapes not built yet). Throws
/// InputError naming segs_path when the segments do not cover the turn or
/// the rises and returns do not add up to the same lift.
std::vector<Segment> read_segments(const std::vector<SegmentConfig>& configs, const std::string& file,
                                   const std::string& segs_path) {
  std::vector<Segment> segs(configs.size());
  double prev_end_deg = 0.0;
  LiftTotals totals;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const SegmentConfig& sc = configs[i];
    const std::string at = indexed(segs_path, i);
    Segment& seg = segs[i];
    read_segment_span(sc, i + 1 == configs.size(), file, at, prev_end_deg, seg);
    if (sc.type == SegmentType::dwell) {
      if (sc.lift || sc.lift_deg) throw InputError(file, at, "a dwell has no lift");
      if (sc.law != SegmentLaw::none) throw InputError(file, at + ".law", "a dwell has no law");
      continue;
    }
    if (sc.type != SegmentType::rise && sc.type != SegmentType::return_)
      throw InputError(file, at + ".type",
                       "unknown segment type '" + to_string(sc.type) + "' (use rise, dwell or return)");
    read_segment_lift(sc, file, at, totals, seg);
    read_segment_law(sc, file, at, seg);
  }
  if (configs.empty()) throw InputError(file, segs_path, "no segments");
  if (prev_end_deg != 360.0)
    throw InputError(file, indexed(segs_path, configs.size() - 1) + ".end_deg",
                     "the last segment ends at " + num10(prev_end_deg) +
                         "°: segments must cover the whole turn, ending at exactly 360");
  if (std::abs(totals.rise - totals.ret) > 1e-12 * std::max(totals.rise, totals.ret)) {
    const double unit = totals.in_deg == 1 ? kPi / 180.0 : 1.0;  // report in the given unit
    throw InputError(file, segs_path,
                     "lift mismatch: the rises add up to " + num10(totals.rise / unit) + " but the returns to " +
                         num10(totals.ret / unit) + (totals.in_deg == 1 ? "°" : " m") +
                         "; the law must close over a turn");
  }
  return segs;
}

/// Closes the cycle exactly: the last rise/return takes up the rounding-level
/// difference the lift-mismatch tolerance allowed.
void close_cycle(std::vector<Segment>& segs) {
  for (std::size_t i = segs.size(); i-- > 0;) {
    if (segs[i].lift == 0.0) continue;
    double others = 0.0;
    for (std::size_t j = 0; j < segs.size(); ++j)
      if (j != i) others += segs[j].lift;
    segs[i].lift = -others;
    break;
  }
}

/// Builds the shape of every spline segment from its control points and the
/// rates of its neighbours at the shared boundaries.
void build_spline_shapes(const std::vector<SegmentConfig>& configs, std::vector<Segment>& segs) {
  const std::size_t count = segs.size();
  for (std::size_t i = 0; i < count; ++i) {
    if (!segs[i].spline) continue;
    // Neighbours wrap around: the law is periodic.
    const Segment& prev = segs[(i + count - 1) % count];
    const Segment& next = segs[(i + 1) % count];
    const auto [v_in, a_in] = boundary_rates(prev, 1.0);
    const auto [v_out, a_out] = boundary_rates(next, 0.0);
    // θ-rates to the normalised variable x = (θ − start)/L of s = base + lift·f(x).
    const double len = segs[i].end - segs[i].start, lift = segs[i].lift;
    segs[i].shape =
        spline_segment_shape(configs[i].degree, configs[i].control_points, {v_in * len / lift, a_in * len * len / lift},
                             {v_out * len / lift, a_out * len * len / lift});
  }
}

/// The law of the built segments, each piece starting at the level the ones
/// before it reached, shifted so that its lowest s is 0.
MotionLaw law_of_segments(const std::vector<Segment>& segs) {
  std::vector<MotionLaw::Piece> pieces;
  double level = 0.0;
  for (const Segment& seg : segs) {
    pieces.push_back({seg.start, seg.end, level, seg.lift, seg.shape});
    level += seg.lift;
  }
  // Lowest s is 0 (a law may start with a return, a spline may undershoot).
  const double low = MotionLaw(pieces).min_s();
  for (auto& piece : pieces) piece.base -= low;
  return MotionLaw(std::move(pieces));
}

/// The segmented law of `configs` (at config path `path`); throws InputError.
MotionLaw law_from_segments(const std::vector<SegmentConfig>& configs, const std::string& file,
                            const std::string& path) {
  std::vector<Segment> segs = read_segments(configs, file, path + ".segments");
  close_cycle(segs);
  build_spline_shapes(configs, segs);
  return law_of_segments(segs);
}

// ---------------------------------------------------------------- periodic spline

/// Builds the InputError for knot j (j < 0: the whole list); field is "knots" or "lift".
using KnotError = std::function<InputError(const std::string& field, int j, const std::string& reason)>;

MotionLaw periodic_law(int degree, const std::vector<double>& knots_deg, const std::vector<double>& lift,
                       const KnotError& error) {
  const int m = static_cast<int>(knots_deg.size());
  if (lift.size() != knots_deg.size())
    throw error("lift", -1, std::to_string(lift.size()) + " lift values for " + std::to_string(m) + " knots");
  if (m < degree + 1)
    throw error("knots", -1,
                std::to_string(m) + " knots; a degree-" + std::to_string(degree) + " periodic spline needs at least " +
                    std::to_string(degree + 1));
  for (int j = 0; j < m; ++j) {
    const double k = knots_deg[j];
    if (!std::isfinite(k) || k < 0.0 || k >= 360.0) throw error("knots", j, num10(k) + "° is outside [0, 360)");
    if (j > 0 && k <= knots_deg[j - 1])
      throw error("knots", j, num10(k) + "° must be greater than the previous knot (" + num10(knots_deg[j - 1]) + "°)");
    if (!std::isfinite(lift[j])) throw error("lift", j, "must be finite");
  }
  std::vector<double> sites(m);
  for (int j = 0; j < m; ++j) sites[j] = knots_deg[j] / 360.0;  // x = θ/2π
  std::optional<PeriodicBSpline> spline = PeriodicBSpline::interpolate(degree, sites, lift, 1.0);
  if (!spline)
    throw error("knots", -1,
                "the periodic interpolation system is singular: knots too unevenly spaced for "
                "degree " +
                    std::to_string(degree));
  std::vector<MotionLaw::Piece> pieces{{0.0, kTwoPi, 0.0, 1.0, std::make_shared<PeriodicShape>(std::move(*spline))}};
  return MotionLaw(std::move(pieces));
}

void check_degree(int degree, const std::string& file, const std::string& at) {
  if (degree < 3 || degree > kMaxSplineDegree)
    throw InputError(file, at, std::to_string(degree) + " must be in [3, " + std::to_string(kMaxSplineDegree) + "]");
}

MotionLaw law_from_spline(const PeriodicSplineConfig& sc, const std::string& file, const std::string& path) {
  const std::string at = path + ".spline";
  check_degree(sc.degree, file, at + ".degree");
  return periodic_law(sc.degree, sc.knots_deg, sc.lift,
                      [&](const std::string& field, int j, const std::string& reason) {
                        std::string p = at + (field == "knots" ? ".knots_deg" : ".lift");
                        if (j >= 0) p = indexed(p, static_cast<std::size_t>(j));
                        return InputError(file, p, reason);
                      });
}

MotionLaw law_from_table(const TableConfig& tc, const std::string& file, const std::string& path) {
  const std::string at = path + ".table";
  check_degree(tc.degree, file, at + ".degree");
  if (tc.file.empty()) throw InputError(file, at + ".file", "no file given");
  if (tc.lines.size() != tc.angle_deg.size() || tc.lift.size() != tc.angle_deg.size())
    throw InputError(file, at + ".file", "the table's rows were not read (io/config.h load_table_rows)");
  std::vector<double> angles = tc.angle_deg, lifts = tc.lift;
  // A closing row at 360° that repeats the 0° row is redundant for a periodic law.
  if (angles.size() > 1 && angles.back() == 360.0 && angles.front() == 0.0) {
    const double scale = std::max(std::abs(lifts.front()), std::abs(lifts.back()));
    if (std::abs(lifts.back() - lifts.front()) > 1e-12 * scale)
      throw InputError(tc.file, "line " + std::to_string(tc.lines.back()),
                       "the row at 360° must repeat the row at 0° (" + tc.lift_column + " " + num10(lifts.back()) +
                           " ≠ " + num10(lifts.front()) + ")");
    angles.pop_back();
    lifts.pop_back();
  }
  return periodic_law(tc.degree, angles, lifts, [&](const std::string& field, int j, const std::string& reason) {
    if (j >= 0) return InputError(tc.file, "line " + std::to_string(tc.lines[j]), reason);
    return InputError(tc.file, "column " + (field == "knots" ? tc.angle_column : tc.lift_column), reason);
  });
}

// ---------------------------------------------------------------- event

/// `law` with the event of `ec` (at config path `at`) spliced in.
MotionLaw law_with_event(const MotionLaw& law, const EventSplineConfig& ec, const std::string& file,
                         const std::string& at) {
  check_degree(ec.degree, file, at + ".degree");
  if (!(ec.from_deg >= 0.0 && ec.to_deg > ec.from_deg && ec.to_deg <= 360.0))
    throw InputError(file, at,
                     "needs 0 <= from_deg < to_deg <= 360, got " + num10(ec.from_deg) + " and " + num10(ec.to_deg));
  const int free = static_cast<int>(ec.control_points.size());
  const int order = event_join_order(ec.degree);
  if (free + 2 * (order + 1) < ec.degree + 1 || free < 1)
    throw InputError(file, at + ".control_points",
                     std::to_string(free) + " control points; a degree-" + std::to_string(ec.degree) +
                         " event needs at least " + std::to_string(std::max(1, ec.degree - 1 - 2 * order)));
  for (std::size_t j = 0; j < ec.control_points.size(); ++j)
    if (!std::isfinite(ec.control_points[j]))
      throw InputError(file, indexed(at + ".control_points", j), "must be finite");
  const EventSplineBasis basis = event_spline_basis(
      law, deg_to_rad(ec.from_deg), ec.to_deg == 360.0 ? kTwoPi : deg_to_rad(ec.to_deg), ec.degree, free);
  return splice_event(law, basis, ec.control_points);
}

}  // namespace

// ---------------------------------------------------------------- public

const std::vector<SegmentLaw>& classic_rise_laws() {
  static const std::vector<SegmentLaw> laws = {SegmentLaw::cycloidal,          SegmentLaw::polynomial_345,
                                               SegmentLaw::polynomial_4567,    SegmentLaw::harmonic,
                                               SegmentLaw::modified_trapezoid, SegmentLaw::modified_sine};
  return laws;
}

std::shared_ptr<const NormalisedRise> classic_rise(SegmentLaw law) {
  switch (law) {
    case SegmentLaw::cycloidal:
      return std::make_shared<Cycloidal>();
    case SegmentLaw::polynomial_345:  // 10x³ − 15x⁴ + 6x⁵
      return std::make_shared<Polynomial>(std::array<double, 8>{0, 0, 0, 10, -15, 6, 0, 0});
    case SegmentLaw::polynomial_4567:  // 35x⁴ − 84x⁵ + 70x⁶ − 20x⁷
      return std::make_shared<Polynomial>(std::array<double, 8>{0, 0, 0, 0, 35, -84, 70, -20});
    case SegmentLaw::harmonic:
      return std::make_shared<Harmonic>();
    case SegmentLaw::modified_trapezoid:
      return modified_trapezoid();
    case SegmentLaw::modified_sine:
      return modified_sine();
    case SegmentLaw::none:
    case SegmentLaw::spline:
      break;
  }
  return nullptr;
}

MotionLaw::MotionLaw(std::vector<Piece> pieces) : pieces_(std::move(pieces)) {
  assert(!pieces_.empty() && pieces_.front().start == 0.0 && pieces_.back().end == kTwoPi);
  min_s_ = std::numeric_limits<double>::infinity();
  max_s_ = -min_s_;
  for (std::size_t i = 0; i < pieces_.size(); ++i) {
    const Piece& pc = pieces_[i];
    assert(pc.end > pc.start && (i == 0 || pc.start == pieces_[i - 1].end));
    // Classic laws are monotone (extremes at piece ends); splines may overshoot
    // between knots, so sample densely (~4096 points per turn, ≥ 64 per piece).
    const int n = 64 + static_cast<int>(std::ceil(4096.0 * (pc.end - pc.start) / kTwoPi));
    const double x0 = pc.x_begin(), x1 = pc.x_end();
    for (int k = 0; k <= n; ++k) {
      const double x = x0 + (x1 - x0) * static_cast<double>(k) / n;
      const double s = pc.shape ? pc.base + pc.lift * pc.shape->eval(x).s : pc.base;
      min_s_ = std::min(min_s_, s);
      max_s_ = std::max(max_s_, s);
    }
  }
}

LawSample MotionLaw::eval(double theta) const {
  // fmod is exact, so the reduction is as good as 2π's double representation;
  // a tiny negative θ can round to t = 2π after the shift.
  double t = std::fmod(theta, kTwoPi);
  if (t < 0.0) t += kTwoPi;
  if (t >= kTwoPi) t = 0.0;
  const auto it =
      std::upper_bound(pieces_.begin(), pieces_.end(), t, [](double v, const Piece& pc) { return v < pc.start; });
  const Piece& pc = it == pieces_.begin() ? pieces_.front() : *(it - 1);
  if (!pc.shape) return {pc.base, 0.0, 0.0, 0.0, 0.0};
  const double len = pc.shape_length();
  const LawSample f = pc.shape->eval((t - pc.shape_origin()) / len);
  const double k1 = pc.lift / len, k2 = k1 / len, k3 = k2 / len, k4 = k3 / len;
  return {pc.base + pc.lift * f.s, k1 * f.ds, k2 * f.d2s, k3 * f.d3s, k4 * f.d4s};
}

MotionLaw build_motion_law(const MotionLawConfig& config, const std::string& file, const std::string& path) {
  const int given = (config.segments.empty() ? 0 : 1) + (config.spline ? 1 : 0) + (config.table ? 1 : 0);
  if (given != 1)
    throw InputError(
        file, path,
        given == 0 ? "give one of segments, spline or table" : "give only one of segments, spline or table");
  if (config.event) {
    MotionLawConfig base = config;
    base.event.reset();
    return law_with_event(build_motion_law(base, file, path), *config.event, file, path + ".event");
  }
  if (config.spline) return law_from_spline(*config.spline, file, path);
  if (config.table) return law_from_table(*config.table, file, path);
  return law_from_segments(config.segments, file, path);
}

ShapePeaks shape_peaks(const NormalisedRise& shape, int samples, double x0, double x1) {
  ShapePeaks p;
  for (int j = 0; j <= samples; ++j) {
    const LawSample f = shape.eval(x0 + (x1 - x0) * static_cast<double>(j) / samples);
    p.d1 = std::max(p.d1, std::abs(f.ds));
    p.d2 = std::max(p.d2, std::abs(f.d2s));
    p.d3 = std::max(p.d3, std::abs(f.d3s));
  }
  return p;
}

LawPeaks law_peaks(const MotionLaw& law, int samples) {
  LawPeaks k;
  for (const MotionLaw::Piece& pc : law.pieces()) {
    if (!pc.shape) continue;  // a dwell
    const double beta = pc.shape_length();
    const ShapePeaks f = shape_peaks(*pc.shape, samples, pc.x_begin(), pc.x_end());
    const double h = std::abs(pc.lift);
    k.velocity = std::max(k.velocity, h * f.d1 / beta);
    k.acceleration = std::max(k.acceleration, h * f.d2 / (beta * beta));
    k.jerk = std::max(k.jerk, h * f.d3 / (beta * beta * beta));
  }
  return k;
}

}  // namespace camdyn
