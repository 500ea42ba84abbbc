#include "optim/optimize/rigid_design.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/contact_stress.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/held_train_force.h"
#include "dynamics/model.h"
#include "geometry/bspline.h"
#include "geometry/event_spline.h"
#include "geometry/motion_law.h"
#include "optim/linear_program.h"
#include "optim/optimize/jump_bound.h"
#include "optim/optimize/lobe_bound.h"
#include "optim/optimize/rigid_limits.h"
#include "optim/optimize/train_rows.h"

namespace camdyn::optim {

namespace {

constexpr double kBisectionRtol = 1e-4;  // relative width of the bracket on ω
/// On a train, whose every programme is the response of the whole train at
/// ten speeds: 1e−3 (a few rpm).
constexpr double kTrainBisectionRtol = 1e-3;
constexpr int kVerifySamples = 2000;  // per piece, for the margins of built laws

/// s, s', s'', s''' at one sample angle, affine in the control points:
/// value[k] = constant[k] + Σ_j coefficient[j][k] c[first + j].
struct AffineSample {
  double theta = 0.0;  ///< cam angle [rad]
  std::array<double, 4> constant{};
  int first = 0;
  std::vector<std::array<double, 4>> coefficient;
};

std::array<double, 4> derivatives(const LawSample& s) { return {s.s, s.ds, s.d2s, s.d3s}; }

/// Which linear constraints a programme has, and what it optimises.
struct FamilyOptions {
  bool monotone = true;
  bool pressure_angle = true;
  bool jerk = true;
  /// max_margin: maximise t. Otherwise keep t ≥ 0 and minimise the peak of
  /// the rigid contact force P (min_peak_force) or of |s''|
  /// (min_peak_acceleration) at `peak_omega`.
  /// max_lift_area: keep t ≥ 0 and maximise ∫ s dθ over the designed
  /// pieces, with s ≤ the lift cap (docs/optimize.md "Lift area").
  enum class Goal { max_margin, min_peak_force, min_peak_acceleration, max_lift_area } goal = Goal::max_margin;
  double peak_omega = 0.0;  ///< [rad/s]
};

/// The spline family of the design space as the rigid stage sees it: the
/// affine samples of the designed segments, the fixed rest of the law, and
/// the linear constraints.
class SplineFamily {
 public:
  SplineFamily(const DesignSpace& space, const DesignConfig& design, const RigidFollower& follower,
               const FollowerGeometry& geometry, const ConstraintsConfig& constraints, int samples,
               const std::string& file)
      : follower_(follower),
        m_(design.control_points),
        degree_(design.degree),
        monotone_(design.monotone && !space.is_event()),
        first_free_(space.free_offset()),
        spline_size_(space.spline_size()),
        lift_scale_(space.is_event() ? space.event_scale() : 0.0),
        pitch_height_(geometry.y0) {
    const std::optional<double>& max_pressure_angle_deg = constraints.max_pressure_angle_deg;
    // s''' is held at the samples only; between them (a quadratic per knot
    // span of a quintic) it can overshoot by ~1 %, so the LP keeps 2 % clear
    // and the dense check of the dynamic stage and `validate` then holds.
    // With 8 or more samples per knot span (a lift-area event design is
    // sampled that densely) the overshoot is below 0.2 % and 0.5 % is kept.
    const double per_span = static_cast<double>(samples) / std::max(1, space.spline_size() - design.degree);
    max_jerk_ = (per_span >= 8.0 ? 0.995 : 0.98) * constraints.max_peak_jerk.value_or(0.0);
    const std::vector<double> zero(static_cast<std::size_t>(space.control_point_count()), 0.0);
    law0_ = std::make_shared<MotionLaw>(
        build_motion_law(space.scene_with_control_points(zero).mechanism.cam.motion_law, file));
    designed_ = space.designed_segments();
    std::vector<std::size_t> fixed;
    for (std::size_t i = 0; i < law0_->pieces().size(); ++i)
      if (std::find(designed_.begin(), designed_.end(), i) == designed_.end()) fixed.push_back(i);
    fixed_ = std::make_shared<SampledLaw>(*law0_, fixed, kVerifySamples);
    levels_ = space.control_point_levels();
    for (std::size_t k = 0; k < designed_.size(); ++k) sample_segment(k, design.degree, samples);
    if (!geometry.oscillating() && geometry.offset == 0.0) {
      curvature_ = true;
      flat_ = !geometry.circle();
      circle_radius_ = geometry.radius;
      rho_min_ = constraints.min_radius_of_curvature.value_or(0.0);
    }
    if (max_pressure_angle_deg && geometry.circle() && !geometry.oscillating()) {
      tan_max_ = std::tan(*max_pressure_angle_deg * std::numbers::pi / 180.0);
      offset_ = std::abs(geometry.offset);
    }
    set_lobe_limits(space, geometry, constraints);
  }

  /// The lift cap (lift_area), the face-edge rows of a flat face and the
  /// linear radius rows of a flat face without offset.
  void set_lobe_limits(const DesignSpace& space, const FollowerGeometry& geometry,
                       const ConstraintsConfig& constraints) {
    if (constraints.max_lift)
      max_lift_ = *constraints.max_lift;
    else if (space.is_event())
      max_lift_ = space.event_scale();  // the baseline's lift (its lowest s is 0)
    const bool flat_face = !geometry.circle() && !geometry.oscillating();
    if (flat_face && constraints.face_edge_margin && geometry.face_width > 0.0)
      face_limit_ = 0.5 * geometry.face_width - *constraints.face_edge_margin;
    // r_b + s + s'' ≥ ρ_min is linear for a flat face without offset: exact rows.
    flat_radius_rows_ = flat_face && geometry.offset == 0.0 && rho_min_ > 0.0;
  }
  /// The limits of the lift-area certificate: the same as this family's
  /// rows, at their true values (the family keeps a little clear of some).
  LobeLimits lobe_limits(std::vector<double> omegas, const ConstraintsConfig& constraints) const {
    LobeLimits l;
    l.omegas = std::move(omegas);
    l.max_lift = max_lift_;
    l.face_limit = face_limit_;
    l.pitch_height = pitch_height_;
    l.min_radius = flat_radius_rows_ ? rho_min_ : 0.0;
    l.max_jerk = constraints.max_peak_jerk.value_or(0.0);
    return l;
  }
  /// The event's samples' trapezoid weights of ∫ s dθ as costs on c (negated: CLP minimises).
  void add_area_costs(LinearProgram& lp) const {
    // Scaled so the objective is of order 1 (CLP's optimality tolerance is absolute).
    double span = 0.0;
    for (const double w : area_weight_) span += w;
    const double scale = 1.0 / (span * (std::isfinite(max_lift_) ? max_lift_ : 1e-3));
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      const double w = area_weight_[i] * scale;
      if (w == 0.0) continue;
      for (int j = 0; j < m_; ++j) {
        const int col = samples_[i].first + j;
        lp.set_cost(col, lp.costs()[col] - w * samples_[i].coefficient[j][0]);
      }
    }
  }

  int columns() const { return static_cast<int>(levels_.size()) * m_; }
  /// Column index of the margin t in margin_program's programmes.
  int margin_column() const { return columns(); }
  const MotionLaw& law0() const { return *law0_; }
  const std::vector<std::size_t>& designed() const { return designed_; }
  bool has_pressure_rows() const { return tan_max_ > 0.0; }
  bool has_jerk_rows() const { return max_jerk_ > 0.0; }

  /// Whether the cam's radius of curvature has a pointwise form in (s, s', s'')
  /// here (translating follower without offset) and a limit is asked for.
  bool curvature_linearisable() const { return curvature_ && rho_min_ > 0.0; }
  /// A flat face's exact radius rows hold `radius_factor_` × the limit,
  /// 1.002 at first; a design whose dense check (`smallest`, [m]) dips
  /// further between the samples raises it by that dip. (A roller's cuts are
  /// linearised: their error is the linearisation's, which the trust region
  /// closes.)
  void widen_radius_rows(double smallest) {
    if (flat_radius_rows_ && smallest > 0.0 && smallest < rho_min_) radius_factor_ *= 1.001 * rho_min_ / smallest;
  }
  /// Radius of curvature of the cam contour [m] for the lift values x =
  /// (s, s', s''): flat face r_b + s + s''; circle of radius r: the pitch
  /// curve's (r_p² + s'²)^{3/2} / (r_p² + 2 s'² − r_p s'') less r, r_p = y₀ + s
  /// (+inf where the pitch curve is concave: its contour radius only grows).
  double radius_of_curvature(const std::array<double, 4>& x) const {
    const double rp = pitch_height_ + x[0];
    if (flat_) return rp + x[2];
    const double den = rp * rp + 2.0 * x[1] * x[1] - rp * x[2];
    if (den <= 0.0) return kInf;
    return std::pow(rp * rp + x[1] * x[1], 1.5) / den - circle_radius_;
  }
  /// The cam angles of the samples [rad].
  std::vector<double> sample_angles() const {
    std::vector<double> out;
    for (const AffineSample& a : samples_) out.push_back(a.theta);
    return out;
  }
  /// Rows over the control points kept for every later programme (a probe's cuts).
  void add_cuts(const std::vector<LimitCut>& cuts) { cuts_.insert(cuts_.end(), cuts.begin(), cuts.end()); }
  /// The trust region |c − c0| ≤ `step` of the next programmes (replaced on each call).
  void set_trust_region(const std::vector<double>& c0, double step) {
    trust_.clear();
    for (int j = 0; j < columns(); ++j) trust_.push_back({{{j, 1.0}}, c0[j] - step, c0[j] + step});
  }
  /// Adds, at every sample where the radius at c0 is below 1.5 × the limit,
  /// the row "radius linearised at c0 ≥ 1.002 × limit" (kept for every later
  /// programme: cuts).
  void add_curvature_cuts(const std::vector<double>& c0) {
    for (const AffineSample& a : samples_) {
      const std::array<double, 4> x = at(a, c0);
      const double g = radius_of_curvature(x);
      if (g < 1.5 * rho_min_)
        add_cut(
            a, c0, x, g, [this](const std::array<double, 4>& y) { return radius_of_curvature(y); }, 1.002 * rho_min_,
            kLpInfinity);
    }
  }

  /// Holds the rigid-model Hertz pressure p₀ = √(P_n κ E* / (π L)) (P_n the
  /// normal force, κ the curvature sum) at most `limit` [Pa] at every ω of
  /// `omegas`: P_n κ ≤ Q = limit² π L / E*. Translating follower without
  /// offset only (pressure_linearisable()).
  void limit_contact_pressure(const LineContact& contact, double limit, std::vector<double> omegas) {
    pressure_q_ = limit * limit * std::numbers::pi * contact.width / contact.e_star;
    pressure_omegas_ = std::move(omegas);
  }
  bool pressure_linearisable() const { return curvature_ && pressure_q_ > 0.0; }
  /// P_n κ [N/m] of the rigid model at lift values x = (s, s', s'') and cam
  /// speed ω; 0 where the follower is not pressed or the surfaces conform,
  /// +inf where the roller does not fit the pitch curve (an undercut).
  double pressure_load(const std::array<double, 4>& x, double omega) const {
    const double force = follower_.coefficient_s() * x[0] + follower_.coefficient_ds(omega) * x[1] +
                         follower_.coefficient_d2s(omega) * x[2] + follower_.constant() + follower_.min_force;
    if (!(force > 0.0)) return 0.0;
    const double rp = pitch_height_ + x[0];
    if (flat_) {  // the face is normal to the axis: P_n = P, κ = 1 / (r_b + s + s'')
      const double rho = rp + x[2];
      return rho > 0.0 ? force / rho : kInf;
    }
    // Roller: P_n = P / cos φ with tan φ = s' / r_p; κ = 1 / (r (1 − r κ_p)), κ_p the pitch curve's curvature.
    const double q2 = rp * rp + x[1] * x[1];
    const double kappa_p = (rp * rp + 2.0 * x[1] * x[1] - rp * x[2]) / std::pow(q2, 1.5);
    const double reduced = circle_radius_ * (1.0 - circle_radius_ * kappa_p);
    return reduced > 0.0 ? force * std::sqrt(q2) / rp / reduced : kInf;
  }
  /// Adds, at every sample and speed where P_n κ at c0 is above half of Q, the
  /// row "P_n κ linearised at c0 ≤ 0.996 Q" (p₀ ≤ 0.998 × the limit; cuts).
  void add_pressure_cuts(const std::vector<double>& c0) {
    for (const double w : pressure_omegas_) {
      for (const AffineSample& a : samples_) {
        const std::array<double, 4> x = at(a, c0);
        const double load = pressure_load(x, w);
        if (load > 0.5 * pressure_q_)
          add_cut(
              a, c0, x, load, [this, w](const std::array<double, 4>& y) { return pressure_load(y, w); }, -kLpInfinity,
              0.996 * pressure_q_);
      }
    }
  }
  /// Largest p₀ / limit over the designed segments of `law`, densely sampled, at every ω.
  double largest_pressure_ratio(const MotionLaw& law) const {
    double largest = 0.0;
    const SampledLaw sampled(law, designed_, kVerifySamples);
    for (const double w : pressure_omegas_)
      for (const LawSample& s : sampled.samples())
        largest = std::max(largest, pressure_load({s.s, s.ds, s.d2s, s.d3s}, w) / pressure_q_);
    return std::sqrt(largest);
  }
  /// Smallest radius of curvature of the designed segments of `law`, densely sampled [m].
  double smallest_radius(const MotionLaw& law) const {
    double smallest = kInf;
    const SampledLaw sampled(law, designed_, kVerifySamples);  // named: it must outlive the loop
    for (const LawSample& s : sampled.samples())
      smallest = std::min(smallest, radius_of_curvature({s.s, s.ds, s.d2s, s.d3s}));
    return smallest;
  }
  bool monotone() const { return monotone_; }

  /// Worst margin over the pieces that are not designed, at every ω of `omegas` [N].
  /// (A train's rows cover the whole revolution: +inf.)
  double fixed_margin(const std::vector<double>& omegas) const {
    return train_ ? kInf : fixed_->worst_margin(follower_, omegas);
  }

  /// Puts the family on the held train of `model` (optim/optimize/train_rows.h).
  void attach_train(const Model& model, const TrainRowLimits& limits) {
    train_ = std::make_shared<TrainRows>(
        model, *law0_, columns(), [this](double theta, std::vector<LawSample>& out) { column_lift(theta, out); },
        limits);
  }
  TrainRows* train() const { return train_.get(); }

  /// (s, s', s'') of every column's unit lift at cam angle θ [rad] (0 outside its segment).
  void column_lift(double theta, std::vector<LawSample>& out) const {
    out.assign(static_cast<std::size_t>(columns()), LawSample{});
    const std::vector<double> knots = ClampedBSpline::uniform_knots(degree_, spline_size_);
    for (std::size_t k = 0; k < spans_.size(); ++k) {
      const PieceSpan& pc = spans_[k];
      if (theta < pc.start || theta > pc.start + pc.beta) continue;
      const double x = std::clamp((theta - pc.start) / pc.beta, 1e-12, 1.0 - 1e-12);
      const int span = find_span(spline_size_, degree_, x, knots);
      const BasisDerivatives b = basis_derivatives(span, x, degree_, knots);
      for (int r = 0; r <= degree_; ++r) {
        const int j = span - degree_ + r - first_free_;
        if (j < 0 || j >= m_) continue;
        LawSample& o = out[k * static_cast<std::size_t>(m_) + static_cast<std::size_t>(j)];
        o.s = pc.lift * b.ders[0][r];
        o.ds = pc.lift * b.ders[1][r] / pc.beta;
        o.d2s = pc.lift * b.ders[2][r] / (pc.beta * pc.beta);
      }
    }
  }

  /// The programme: maximise t with P − P_min ≥ t at every sample and ω in
  /// `omegas`. Columns: c, then t (the last).
  LinearProgram margin_program(const std::vector<double>& omegas, const FamilyOptions& options) const;

 private:
  /// The lift-area programme's own rows and costs: s ≤ the lift cap at
  /// every sample, the face and radius rows, and −∫ s dθ as the cost.
  void add_lobe_rows(LinearProgram& lp) const {
    std::vector<std::pair<int, double>> terms;
    if (std::isfinite(max_lift_)) {
      for (const AffineSample& a : samples_) {
        terms.clear();
        for (int j = 0; j < m_; ++j) terms.emplace_back(a.first + j, a.coefficient[j][0]);
        lp.add_row(terms, -kLpInfinity, (1.0 - 1e-5) * max_lift_ - a.constant[0]);  // room between samples
      }
    }
    add_face_and_radius_rows(lp);
    add_area_costs(lp);
  }
  /// |s'| ≤ the face limit (flat face with constraints.face_edge_margin) and
  /// r_b + s + s'' ≥ ρ_min (flat face without offset), at every sample.
  void add_face_and_radius_rows(LinearProgram& lp) const {
    std::vector<std::pair<int, double>> terms;
    for (const AffineSample& a : samples_) {
      if (std::isfinite(face_limit_)) {
        terms.clear();
        for (int j = 0; j < m_; ++j) terms.emplace_back(a.first + j, a.coefficient[j][1]);
        lp.add_row(terms, -face_limit_ - a.constant[1], face_limit_ - a.constant[1]);
      }
      if (flat_radius_rows_) {
        terms.clear();
        for (int j = 0; j < m_; ++j) terms.emplace_back(a.first + j, a.coefficient[j][0] + a.coefficient[j][2]);
        lp.add_row(terms, radius_factor_ * rho_min_ - pitch_height_ - a.constant[0] - a.constant[2], kLpInfinity);
      }
    }
  }

  /// A column z (the last, cost 1) and z ≥ P_i(peak_omega), or z ≥ ±s''_i, at every sample.
  void add_peak_rows(LinearProgram& lp, const FamilyOptions& options) const {
    const int z = lp.add_column(-kLpInfinity, kLpInfinity, 1.0);
    const bool force = options.goal == FamilyOptions::Goal::min_peak_force;
    if (force && train_) {
      train_->add_peak_rows(lp, options.peak_omega, z);
      return;
    }
    const double w = options.peak_omega;
    const std::array<double, 3> a = force
                                        ? std::array<double, 3>{follower_.coefficient_s(), follower_.coefficient_ds(w),
                                                                follower_.coefficient_d2s(w)}
                                        : std::array<double, 3>{0.0, 0.0, 1.0};
    const double offset = force ? follower_.constant() + follower_.min_force : 0.0;  // P = Σ a·s + F₀ + M g
    std::vector<std::pair<int, double>> terms;
    for (const AffineSample& s : samples_) {
      for (const double sign : force ? std::vector<double>{1.0} : std::vector<double>{1.0, -1.0}) {
        terms.clear();
        for (int j = 0; j < m_; ++j) {
          const auto& d = s.coefficient[j];
          terms.emplace_back(s.first + j, -sign * (a[0] * d[0] + a[1] * d[1] + a[2] * d[2]));
        }
        terms.emplace_back(z, 1.0);
        const double known = a[0] * s.constant[0] + a[1] * s.constant[1] + a[2] * s.constant[2] + offset;
        lp.add_row(terms, sign * known, kLpInfinity);
      }
    }
  }

  /// The affine samples of designed segment k. The segment's lift is
  /// s = base + h f(ξ), ξ = (θ − start) / β, with f the clamped spline of
  /// degree p on m + 6 uniform-knot control points whose free ones are
  /// coefficients 3 … m + 2 (geometry/motion_law.cc; the boundary ones do not
  /// depend on them), so ∂s⁽ᵏ⁾/∂c_j = h N⁽ᵏ⁾_{3+j}(ξ) / βᵏ exactly.
  void sample_segment(std::size_t k, int p, int samples) {
    const MotionLaw::Piece& pc = law0_->pieces()[designed_[k]];
    const double beta = pc.end - pc.start;
    const double lift = lift_scale_ > 0.0 ? lift_scale_ : pc.lift;  // an event's piece has lift 1 and raw c in h
    spans_.push_back({pc.start, beta, lift});
    const int n = spline_size_;
    const std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
    for (int i = 0; i < samples; ++i) {
      area_weight_.push_back((i == 0 || i + 1 == samples ? 0.5 : 1.0) * beta / (samples - 1));
      const double x = std::clamp(static_cast<double>(i) / (samples - 1), 1e-12, 1.0 - 1e-12);
      AffineSample a;
      a.theta = pc.start + x * beta;
      a.constant = derivatives(law0_->eval(a.theta));
      a.first = static_cast<int>(k) * m_;
      a.coefficient.assign(static_cast<std::size_t>(m_), {0.0, 0.0, 0.0, 0.0});
      const int span = find_span(n, p, x, knots);
      const BasisDerivatives b = basis_derivatives(span, x, p, knots);
      for (int r = 0; r <= p; ++r) {
        const int j = span - p + r - first_free_;  // free control point j is coefficient first_free_ + j
        if (j < 0 || j >= m_) continue;
        a.coefficient[j] = {lift * b.ders[0][r], lift * b.ders[1][r] / beta, lift * b.ders[2][r] / (beta * beta),
                            lift * b.ders[3][r] / (beta * beta * beta)};
      }
      samples_.push_back(std::move(a));
    }
  }

  /// (s, s', s'', s''') of sample `a` at control points c.
  std::array<double, 4> at(const AffineSample& a, const std::vector<double>& c) const {
    std::array<double, 4> x = a.constant;
    for (int j = 0; j < m_; ++j)
      for (int k = 0; k < 4; ++k) x[k] += a.coefficient[j][k] * c[a.first + j];
    return x;
  }
  /// The cut lower ≤ g(x(c0)) + ∇g · (x(c) − x(c0)) ≤ upper for a function g
  /// of (s, s', s'') at sample `a` (value `g0` at c0; gradient by central differences).
  template <class G>
  void add_cut(const AffineSample& a, const std::vector<double>& c0, const std::array<double, 4>& x, double g0,
               const G& g, double lower, double upper) {
    std::array<double, 3> grad{};
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-7 * (std::abs(x[k]) + 1e-3);
      std::array<double, 4> up = x, down = x;
      up[k] += h;
      down[k] -= h;
      grad[k] = (g(up) - g(down)) / (2.0 * h);
    }
    Cut cut;
    double at_c0 = 0.0;
    for (int j = 0; j < m_; ++j) {
      const auto& d = a.coefficient[j];
      const double v = grad[0] * d[0] + grad[1] * d[1] + grad[2] * d[2];
      cut.terms.emplace_back(a.first + j, v);
      at_c0 += v * c0[a.first + j];
    }
    if (!std::isfinite(at_c0) || !std::isfinite(g0)) return;
    cut.lower = std::isfinite(lower) ? lower - g0 + at_c0 : -kLpInfinity;
    cut.upper = std::isfinite(upper) ? upper - g0 + at_c0 : kLpInfinity;
    cuts_.push_back(std::move(cut));
  }

  RigidFollower follower_;
  int m_ = 0;
  int degree_ = 5;
  /// Each designed piece: start [rad], length β [rad], and the lift a column's unit scales [m].
  struct PieceSpan {
    double start = 0.0, beta = 0.0, lift = 0.0;
  };
  std::vector<PieceSpan> spans_;
  std::shared_ptr<TrainRows> train_;  ///< on a train: its rows replace the rigid force's
  bool monotone_ = true;
  int first_free_ = 3;       ///< index of the first free control point among the spline's coefficients
  int spline_size_ = 0;      ///< all coefficients of a designed spline
  double lift_scale_ = 0.0;  ///< an event's raw control points are in units of this lift [m] (0: a segment's)
  double max_lift_ = kInf, face_limit_ = kInf;  ///< lift_area: s cap [m]; flat face: |s'| cap [m/rad]
  bool flat_radius_rows_ = false;
  std::vector<double> area_weight_;  ///< per sample: its trapezoid weight in ∫ s dθ [rad]
  std::shared_ptr<const MotionLaw> law0_;
  std::vector<std::size_t> designed_;
  std::shared_ptr<const SampledLaw> fixed_;  ///< the pieces that are not designed
  std::vector<std::pair<double, double>> levels_;
  std::vector<AffineSample> samples_;
  double tan_max_ = 0.0, pitch_height_ = 0.0, offset_ = 0.0;  ///< pitch_height_: y₀ of the follower [m]
  double max_jerk_ = 0.0;                                     ///< |s'''| bound [m/rad³] (0: none)
  // Radius of curvature: pointwise form and the limit, and the rows added so far.
  bool curvature_ = false, flat_ = false;
  double circle_radius_ = 0.0, rho_min_ = 0.0;
  double radius_factor_ = 1.002;  ///< a flat face's radius rows' share of the limit (widen_radius_rows)
  // Contact pressure: Q = limit² π L / E* [N/m] (0: no limit) and the speeds it holds at [rad/s].
  double pressure_q_ = 0.0;
  std::vector<double> pressure_omegas_;
  using Cut = LimitCut;
  std::vector<Cut> cuts_, trust_;
};

LinearProgram SplineFamily::margin_program(const std::vector<double>& omegas, const FamilyOptions& options) const {
  LinearProgram lp;
  for (std::size_t k = 0; k < levels_.size(); ++k) {
    const auto [low, high] = levels_[k];
    const double span = std::max(high - low, 1e-3);
    for (int j = 0; j < m_; ++j) {
      if (options.monotone)
        lp.add_column(std::min(low, high), std::max(low, high));
      else
        lp.add_column(low - 0.5 * span, high + 0.5 * span);
    }
  }
  const double force_scale = std::abs(follower_.constant()) + follower_.stiffness * 0.1 + 1.0;
  const bool max_margin = options.goal == FamilyOptions::Goal::max_margin;
  const bool lift_area = options.goal == FamilyOptions::Goal::max_lift_area;
  // A lift-area design is held at the samples only; 1e-3 of the force scale
  // keeps the margin between them (a knot span holds a few samples) ≥ 0.
  // On a train the rows sit on a grid of 1024 angles and a design that keeps
  // its margin at exactly 0 there dips between them: 2e-3 of the train's
  // force scale is kept clear (docs/optimize.md "Trains").
  const double floor_t = train_ ? 2e-3 * train_->force_scale() : (lift_area ? 1e-3 * force_scale : 0.0);
  const int t = lp.add_column(max_margin ? -kLpInfinity : floor_t, std::max(1e3 * force_scale, 10.0 * floor_t),
                              max_margin ? -1.0 : 0.0);
  if (lift_area)
    add_lobe_rows(lp);
  else if (!max_margin)
    add_peak_rows(lp, options);
  if (!lift_area) add_face_and_radius_rows(lp);
  std::vector<std::pair<int, double>> terms;
  if (train_) train_->add_rows(lp, omegas, t);
  for (const double w : train_ ? std::vector<double>{} : omegas) {
    const std::array<double, 3> a = {follower_.coefficient_s(), follower_.coefficient_ds(w),
                                     follower_.coefficient_d2s(w)};
    for (const AffineSample& s : samples_) {
      terms.clear();
      for (int j = 0; j < m_; ++j) {
        const auto& d = s.coefficient[j];
        terms.emplace_back(s.first + j, a[0] * d[0] + a[1] * d[1] + a[2] * d[2]);
      }
      terms.emplace_back(t, -1.0);
      const double known = a[0] * s.constant[0] + a[1] * s.constant[1] + a[2] * s.constant[2] + follower_.constant();
      lp.add_row(terms, -known, kLpInfinity);
    }
  }
  if (options.monotone) {
    for (std::size_t k = 0; k < levels_.size(); ++k) {
      const int first = static_cast<int>(k) * m_;
      for (int j = 0; j + 1 < m_; ++j) lp.add_row({{first + j + 1, 1.0}, {first + j, -1.0}}, 0.0, kLpInfinity);
    }
  }
  for (const std::vector<Cut>* rows : {&cuts_, &trust_})
    for (const Cut& cut : *rows) lp.add_row(cut.terms, cut.lower, cut.upper);
  if (options.jerk && has_jerk_rows()) {
    // −J ≤ s''' ≤ J at every sample.
    for (const AffineSample& s : samples_) {
      terms.clear();
      for (int j = 0; j < m_; ++j) terms.emplace_back(s.first + j, s.coefficient[j][3]);
      lp.add_row(terms, -max_jerk_ - s.constant[3], max_jerk_ - s.constant[3]);
    }
  }
  if (options.pressure_angle && has_pressure_rows()) {
    // ±s' − tan φ s ≤ tan φ y₀ − |e| at every sample.
    const double rhs = tan_max_ * pitch_height_ - offset_;
    for (const AffineSample& s : samples_) {
      for (const double sign : {1.0, -1.0}) {
        terms.clear();
        for (int j = 0; j < m_; ++j)
          terms.emplace_back(s.first + j, sign * s.coefficient[j][1] - tan_max_ * s.coefficient[j][0]);
        lp.add_row(terms, -kLpInfinity, rhs - (sign * s.constant[1] - tan_max_ * s.constant[0]));
      }
    }
  }
  // An event's rows (dense jerk rows, 100 control points) span many decades;
  // the segment designs' programmes are left as they were.
  // A train's rows, too: their coefficients are responses of the whole train.
  if (lift_scale_ > 0.0 || train_) lp.equilibrate_rows();
  return lp;
}

/// Solves a margin programme; returns t* [N] and the control points.
struct MarginSolution {
  double margin = -kInf;
  std::vector<double> c;
};

/// With `feasibility` (a tolerance ≥ 0 [N]), a train's row generation stops
/// as soon as the answer to "is some design's margin ≥ −tolerance" is known:
/// a programme over some rows with t* below it (no design can do better on
/// all rows), or a design that meets every row with t = 0; the margin
/// returned is then only that answer's side of the tolerance.
MarginSolution solve_margin(const SplineFamily& family, const std::vector<double>& omegas, const FamilyOptions& options,
                            int& solves, double feasibility = -1.0) {
  // On a train the rows are generated (optim/optimize/train_rows.h): solve,
  // activate the angles the solution breaks, solve again until none.
  constexpr int kMaxRounds = 40;
  for (int round = 0;; ++round) {
    const LinearProgram lp = family.margin_program(omegas, options);
    const LpSolution sol = solve(lp);
    ++solves;
    if (sol.status == LpStatus::infeasible) return {};  // no design meets the other constraints (e.g. a jerk bound)
    if (sol.status != LpStatus::optimal)
      throw NumericalError(std::string("the rigid-model design programme could not be solved (CLP: ") + sol.message +
                           ")");
    MarginSolution out;
    out.margin = sol.x[family.margin_column()];
    out.c.assign(sol.x.begin(), sol.x.begin() + family.columns());
    TrainRows* train = family.train();
    if (!train) return out;
    const bool deciding = feasibility >= 0.0 && options.goal == FamilyOptions::Goal::max_margin;
    if (deciding && out.margin < -feasibility) return out;
    if (deciding && out.margin >= 0.0 && train->activate_violated(out.c, 0.0, omegas) == 0) return out;
    int added = train->activate_violated(out.c, out.margin, omegas);
    if (options.goal == FamilyOptions::Goal::min_peak_force)
      added += train->activate_peak(out.c, options.peak_omega, sol.x.back());
    if (added == 0) return out;
    if (round + 1 == kMaxRounds)
      throw NumericalError("the train's design programme still breaks rows of the response grid after " +
                           std::to_string(kMaxRounds) + " rounds of row generation");
  }
}

/// The speeds the design programme checks: every operating speed (with the
/// damper's fractions of each).
std::vector<double> operating_omegas(const OptimizeStudyConfig& config, const RigidFollower& f) {
  std::vector<double> out;
  if (f.sampled_speeds > 0) {  // a train: every operating speed, and jump-free up to the top one
    const double top =
        *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end()) * kRadPerSecondPerRpm;
    out = check_speeds(top, f);
    for (const double rpm : config.operating_rpm) out.push_back(rpm * kRadPerSecondPerRpm);
    return out;
  }
  for (const double rpm : config.operating_rpm)
    for (const double w : check_speeds(rpm * kRadPerSecondPerRpm, f)) out.push_back(w);
  return out;
}

/// The speeds at which a lift-area design keeps P ≥ P_min: every speed from
/// 0 to rigid.speed_factor × the top operating speed ω₁. P = M ω² s'' +
/// c ω s' + k s + F₀ + M g is, at each angle, affine in ω² when c = 0, so
/// its least value over [0, ω₁] is at 0 or at ω₁ and those two rows are
/// exact; with a damper it is a parabola in ω whose least value can lie
/// inside, and the rows sample it at every 1/16 of ω₁ (docs/optimize.md).
/// A train's response is no parabola (its resonances lie between): its rows
/// sit at ω₁ k / 10 and at every operating speed, as the other goals'.
std::vector<double> lobe_speeds(const OptimizeStudyConfig& config, const RigidFollower& f) {
  const double top = *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end()) * kRadPerSecondPerRpm *
                     config.rigid.speed_factor;
  if (f.sampled_speeds > 0) {
    std::vector<double> out = check_speeds(top, f);
    for (const double rpm : config.operating_rpm) out.push_back(rpm * kRadPerSecondPerRpm);
    return out;
  }
  std::vector<double> out = {0.0};
  const int steps = f.damping == 0.0 ? 1 : 16;
  for (int k = 1; k <= steps; ++k) out.push_back(top * k / steps);
  return out;
}

/// The family's highest jump-free speed with `options` [rad/s]; `design`
/// (if given) receives the solution at the highest feasible speed tried.
double family_bound(const SplineFamily& family, const RigidFollower& f, const FamilyOptions& options, double hint,
                    int& solves, MarginSolution* design = nullptr, double growth = 2.0) {
  const double tol = 1e-9 * (std::abs(f.constant()) + 1.0);
  double best_w = -1.0;
  auto feasible = [&](double w) {
    const std::vector<double> omegas = check_speeds(w, f);
    if (family.fixed_margin(omegas) < -tol) return false;
    MarginSolution sol = solve_margin(family, omegas, options, solves, tol);
    if (sol.margin < -tol) return false;
    if (design && w > best_w) {
      best_w = w;
      *design = std::move(sol);
    }
    return true;
  };
  return highest_feasible_speed(feasible, hint, 1e3 * hint, f.sampled_speeds > 0 ? kTrainBisectionRtol : kBisectionRtol,
                                growth);
}

/// The jump-free speed of a sampled law [rad/s].
double law_bound(const SampledLaw& sampled, const RigidFollower& f, double hint) {
  auto feasible = [&](double w) { return sampled.worst_margin(f, check_speeds(w, f)) >= 0.0; };
  return highest_feasible_speed(feasible, hint, 1e3 * hint, kBisectionRtol);
}

double as_rpm(double omega) { return std::isfinite(omega) ? omega / kRadPerSecondPerRpm : kInf; }

/// Which of the lift-area bound's limits blocks it: the first whose removal
/// alone makes the programme solvable (its constraint's name), else "the
/// constraints together".
std::string lift_area_blocker(const MotionLaw& law, double from, double to, const RigidFollower& f,
                              const LobeLimits& limits, int grid) {
  struct Relaxed {
    const char* name;
    LobeLimits limits;
  };
  std::vector<Relaxed> tries;
  auto add = [&](const char* name, auto relax) {
    LobeLimits l = limits;
    relax(l);
    tries.push_back({name, std::move(l)});
  };
  if (!limits.omegas.empty())
    add("the contact-force floor P >= P_min up to the top speed (rigid.min_contact_force)",
        [](LobeLimits& l) { l.omegas.clear(); });
  if (std::isfinite(limits.max_lift)) add("constraints.max_lift", [](LobeLimits& l) { l.max_lift = kInf; });
  if (std::isfinite(limits.face_limit)) add("constraints.face_edge_margin", [](LobeLimits& l) { l.face_limit = kInf; });
  if (limits.min_radius > 0.0) add("constraints.min_radius_of_curvature", [](LobeLimits& l) { l.min_radius = 0.0; });
  if (limits.max_jerk > 0.0) add("constraints.max_peak_jerk", [](LobeLimits& l) { l.max_jerk = 0.0; });
  for (const Relaxed& r : tries) {
    try {
      if (lift_area_bound(law, from, to, f, r.limits, grid).solved)
        return std::string("blocked by ") + r.name + ": without it alone a lift exists";
    } catch (const NumericalError&) {  // CLP could not settle this relaxation: no evidence either way
    }
  }
  return "blocked by the constraints together: no one of them removed alone leaves a lift";
}

/// The lift-area certificate of design `d` of an event design space.
void lift_area_part(const SplineFamily& family, const RigidFollower& f, const OptimizeStudyConfig& config,
                    const DesignSpace& space, const RigidDesign& d, const MotionLaw& baseline, Certificate& cert) {
  LiftAreaCertificate& c = cert.lift_area;
  if (!space.is_event()) {
    c.reason = "the lift-area certificate is for an event design (design.event)";
    return;
  }
  const double from = space.event_basis().from, to = space.event_basis().to;
  const std::vector<double> omegas = lobe_speeds(config, f);
  for (const double w : omegas) c.speeds_rpm.push_back(w / kRadPerSecondPerRpm);
  c.baseline = lift_area(baseline, from, to);
  if (d.have) c.design = lift_area(build_motion_law(space.scene(d.x).mechanism.cam.motion_law, ""), from, to);
  if (family.train()) {
    c.reason =
        "not computed on a train: the lift-area bound is a one-mass rigid model's, and every rigid figure of a train "
        "is the held train's (the design itself keeps the held train's forces)";
    return;
  }
  const LobeLimits limits = family.lobe_limits(omegas, config.constraints);
  const LobeBound b = lift_area_bound(family.law0(), from, to, f, limits, config.rigid.certificate_grid);
  c.grid = b.grid;
  if (!b.solved) {
    c.reason = "no lift over the event meets the constraints (the bound's programme is " + b.status + "); " +
               lift_area_blocker(family.law0(), from, to, f, limits, config.rigid.certificate_grid);
    return;
  }
  c.bound = b.area;
  if (!d.have) {
    c.reason = "the spline family has no design under the constraints, although a lift over the event does (" +
               std::to_string(b.area) + " m rad at most): more design.control_points";
    return;
  }
  c.available = true;
}

/// (a): the any-law bound of the designed pieces and the fixed rest's own bound.
void any_law_part(const SplineFamily& family, const RigidFollower& f, double hint, int grid, Certificate& cert) {
  const std::vector<SegmentJumpBound> bounds = any_law_jump_bounds(family.law0(), f, family.designed(), hint, grid);
  double best = kInf;
  for (const SegmentJumpBound& b : bounds) {
    if (b.omega < best) {
      best = b.omega;
      cert.any_law_binding = "segments[" + std::to_string(b.piece) + "]";
    }
  }
  auto fixed_ok = [&](double w) { return family.fixed_margin(check_speeds(w, f)) >= 0.0; };
  const double fixed = highest_feasible_speed(fixed_ok, hint, 1e3 * hint, kBisectionRtol);
  if (fixed < best) {
    best = fixed;
    cert.any_law_binding = fixed == 0.0 ? "the spring cannot hold the follower at rest with the required force"
                                        : "the segments that are not designed";
  }
  cert.any_law_rpm = best >= 1e3 * hint ? kInf : as_rpm(best);
}

/// (b); `fastest` receives the family's fastest design.
double family_part(const SplineFamily& family, const RigidFollower& f, double hint, Certificate& cert, int& solves,
                   MarginSolution& fastest) {
  const FamilyOptions all{family.monotone(), true};
  const double bound = family_bound(family, f, all, hint, solves, &fastest);
  cert.family_rpm = as_rpm(bound);
  return bound;
}

/// What holds (b) down: two more bisections, each without one kind of constraint.
void family_binding(const SplineFamily& family, const RigidFollower& f, double hint, double bound, Certificate& cert,
                    int& solves) {
  const FamilyOptions all{family.monotone(), true};
  if (family.has_pressure_rows() &&
      family_bound(family, f, FamilyOptions{all.monotone, false, true}, hint, solves) > 1.005 * bound)
    cert.family_binding.push_back("max_pressure_angle_deg");
  if (family.has_jerk_rows() &&
      family_bound(family, f, FamilyOptions{all.monotone, true, false}, hint, solves) > 1.005 * bound)
    cert.family_binding.push_back("max_peak_jerk");
  if (family.monotone() && family_bound(family, f, FamilyOptions{false, true, true}, hint, solves) > 1.005 * bound)
    cert.family_binding.push_back("monotone");
  if (std::isfinite(cert.any_law_rpm) && cert.family_rpm >= 0.99 * cert.any_law_rpm)
    cert.family_binding.push_back("spring and mass (no law does better)");
  else if (cert.family_binding.empty())
    cert.family_binding.push_back("spline family (degree and control points)");
}

/// The least held quantity − its floor of `signal` on `train` at ω [N].
double held_least_margin(const HeldTrain& train, const GridSignal& signal, double omega, const TrainRowLimits& limits) {
  const std::vector<Eigen::VectorXd> v = held_train_values(train, signal, omega);
  double least = kInf;
  for (std::size_t k = 0; k < train.quantities.size(); ++k) {
    const HeldQuantity& q = train.quantities[k];
    if (q.held())
      least = std::min(
          least, v[k].minCoeff() - (q.kind == HeldQuantity::Kind::contact ? limits.contact_floor : limits.link_floor));
  }
  return least;
}

/// A programme on a train whose speeds are generated as its angles are: the
/// held train's forces dip in resonance bands narrower than the spacing of
/// the sampled speeds (a surging spring's, about 80 rpm wide on the DOHC
/// lash train), so after each programme the design's first failing speed up
/// to `omega_top` (held_train_jump_speed: equal steps and the resonances of
/// its harmonics) and the worst speed of the band above it join the list,
/// until the design holds up to `omega_top`, no design holds at the new
/// speeds (the last design is kept; its dense check says where it fails),
/// or kSpeedRounds rounds. One programme off a train.
MarginSolution solve_over_speeds(const SplineFamily& family, const DesignSpace& space, std::vector<double> omegas,
                                 double omega_top, const FamilyOptions& options, int& solves) {
  constexpr int kSpeedRounds = 16;
  constexpr int kBandSteps = 16;      // the band above a failing speed, scanned for its worst
  constexpr double kBandWidth = 0.1;  // of the failing speed
  MarginSolution out = solve_margin(family, omegas, options, solves);
  const TrainRows* train = family.train();
  for (int round = 0; train && !out.c.empty() && round < kSpeedRounds; ++round) {
    const MotionLaw law =
        build_motion_law(space.scene(space.design_from_control_points(out.c)).mechanism.cam.motion_law, "");
    const GridSignal signal = grid_signal([&](double theta) { return law.eval(theta); }, TrainRows::kAngles);
    const TrainRowLimits& limits = train->limits();
    const double fail =
        held_train_jump_speed(train->held(), signal, omega_top, limits.contact_floor, limits.link_floor, 1e-4);
    if (!(fail > 0.0 && fail < omega_top)) break;  // holds up to the top, or not even at rest
    const double band_end = std::min(omega_top, (1.0 + kBandWidth) * fail);
    double worst = fail, least = kInf;
    for (int j = 0; j <= kBandSteps; ++j) {
      const double w = fail + (band_end - fail) * j / kBandSteps;
      const double m = held_least_margin(train->held(), signal, w, limits);
      if (m < least) {
        least = m;
        worst = w;
      }
    }
    omegas.push_back(fail);
    omegas.push_back(worst);
    MarginSolution next = solve_margin(family, omegas, options, solves);
    if (next.c.empty()) break;
    out = std::move(next);
  }
  return out;
}

/// The stage's design. Jump-free up to rigid.speed_factor × the top
/// operating speed where the family allows it, and then, as the study's
/// objective asks, with the lowest peak contact force or acceleration at the
/// top speed; otherwise (or when the family cannot reach that speed) the
/// family's fastest design.
RigidDesign make_design(const SplineFamily& family, const RigidFollower& f, const OptimizeStudyConfig& config,
                        const DesignSpace& space, double bound, const MarginSolution& fastest, int& solves) {
  const double top = *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end()) * kRadPerSecondPerRpm;
  const double wanted = config.rigid.speed_factor * top;
  FamilyOptions options{family.monotone(), true};
  if (config.objective.peak_contact_force > 0.0)
    options.goal = FamilyOptions::Goal::min_peak_force;
  else if (config.objective.peak_acceleration > 0.0)
    options.goal = FamilyOptions::Goal::min_peak_acceleration;
  options.peak_omega = top;
  MarginSolution chosen = fastest;
  if (config.objective.lift_area > 0.0) {
    options.goal = FamilyOptions::Goal::max_lift_area;
    MarginSolution most = solve_over_speeds(family, space, lobe_speeds(config, f), wanted, options, solves);
    if (!most.c.empty()) chosen = std::move(most);  // else no law keeps contact there: the fastest
  } else if (options.goal != FamilyOptions::Goal::max_margin && bound >= wanted) {
    std::vector<double> omegas = check_speeds(wanted, f);
    for (const double w : operating_omegas(config, f)) omegas.push_back(w);
    chosen = solve_over_speeds(family, space, omegas, wanted, options, solves);
  }
  RigidDesign d;
  d.have = !chosen.c.empty();
  if (!d.have) return d;
  d.control_points = chosen.c;
  d.x = space.design_from_control_points(chosen.c);
  d.lp_margin = chosen.margin;
  return d;
}

/// The limits that are not linear (radius of curvature, contact pressure,
/// an arm's pressure angle): while the design (densely sampled) breaks one,
/// linearise it at the design's samples (pointwise forms in the family, the
/// rest through `probe`), add the cuts and a trust region, and design again
/// (at most 8 rounds; the dynamic stage holds the limits in any case).
RigidDesign tighten_nonlinear(SplineFamily& family, const RigidLimitProbe* probe, const RigidFollower& f,
                              const OptimizeStudyConfig& config, const DesignSpace& space, double hint, RigidDesign d,
                              int& solves) {
  double step = 0.2;  // trust region in normalised lift
  for (int round = 0; round < 8 && d.have; ++round) {
    const MotionLaw law = build_motion_law(space.scene(d.x).mechanism.cam.motion_law, "");
    const double smallest = family.curvature_linearisable() ? family.smallest_radius(law) : kInf;  // [m]
    const bool curvature_short = smallest < config.constraints.min_radius_of_curvature.value_or(0.0);
    const bool pressure_over = family.pressure_linearisable() && family.largest_pressure_ratio(law) > 1.0;
    const bool probed_broken = probe && probe->broken(d.control_points);
    if (!curvature_short && !pressure_over && !probed_broken) break;
    family.set_trust_region(d.control_points, step);
    if (curvature_short) {
      family.widen_radius_rows(smallest);
      family.add_curvature_cuts(d.control_points);
    }
    if (pressure_over) family.add_pressure_cuts(d.control_points);
    if (probed_broken) family.add_cuts(probe->cuts(d.control_points));
    MarginSolution fastest;
    // A lift-area design does not need the family's fastest (make_design).
    const double bound = config.objective.lift_area > 0.0
                             ? 0.0
                             : family_bound(family, f, FamilyOptions{family.monotone(), true}, hint, solves, &fastest);
    const RigidDesign next = make_design(family, f, config, space, bound, fastest, solves);
    if (!next.have) break;  // the cuts leave nothing: keep the last design
    d = next;
    step *= 0.7;
  }
  return d;
}

/// The probe for the limits the family has no linear or pointwise form of:
/// an arm's pressure angle, and the radius of curvature and contact pressure
/// of offset followers and arms. None when there are none.
std::optional<RigidLimitProbe> limit_probe(const SceneConfig& baseline, const Model& model, const RigidFollower& f,
                                           const OptimizeStudyConfig& config, const DesignSpace& space,
                                           const SplineFamily& family) {
  const ConstraintsConfig& c = config.constraints;
  const FollowerGeometry& g = model.follower;
  const bool pointwise = !g.oscillating() && g.offset == 0.0;  // the family's own forms
  // On a train the pressure's force is the held train's, which no pointwise
  // form in (s, s', s'') has (docs/model.md §12): the probe holds it.
  const bool held = rigid_figures_held(model);
  ProbedLimits limits;
  if (g.oscillating()) limits.max_pressure_angle_deg = c.max_pressure_angle_deg;
  if (!pointwise) limits.min_radius_of_curvature = c.min_radius_of_curvature;
  if (!pointwise || held) {
    limits.contact = line_contact(baseline.mechanism.contact);
    if (limits.contact) limits.max_contact_stress = c.max_contact_stress;
    if (held) limits.held = &model;
  }
  if (!limits.any()) return std::nullopt;
  limits.omegas = operating_omegas(config, f);
  return RigidLimitProbe(space, g, model.direction, f, std::move(limits), family.sample_angles());
}

/// The limits of the train's rows: P_min at the contact (the held train's
/// contact quantity is the normal force, also for an arm) and at every link,
/// and the spring and seating limits of the constraints.
TrainRowLimits train_limits(const Certificate& cert, const ConstraintsConfig& c) {
  TrainRowLimits l;
  l.contact_floor = cert.min_contact_force;
  l.link_floor = cert.min_contact_force;
  l.max_spring_force = c.max_spring_force;
  l.max_seating_velocity = c.max_seating_velocity;
  return l;
}

/// Scans a held train's jump-free speed up to this many times the top operating speed.
constexpr double kTrainScanFactor = 10.0;

/// (a) on a train: no closed form and no per-segment split (the response
/// couples the segments), so the bound is the family bound of a rich cubic
/// spline with no other constraint — 16 free control points per designed
/// segment, control points free — a lower estimate of ANY law's bound that
/// rises to it as the spline is refined; the 8-point figure is reported
/// beside it as the evidence of convergence.
void any_law_on_train(const SceneConfig& baseline, const OptimizeStudyConfig& config, const Model& model,
                      const RigidFollower& f, double hint, const std::string& file, Certificate& cert, int& solves) {
  for (const int points : {8, 16}) {
    DesignConfig rich = config.design;
    rich.control_points = points;
    rich.degree = 3;
    rich.monotone = false;
    rich.spring = false;
    rich.end_deg_range = {};
    const DesignSpace space(baseline, rich, file);
    ConstraintsConfig none;
    none.max_pressure_angle_deg.reset();
    SplineFamily family(space, rich, f, model.follower, none, config.rigid.samples, file);
    family.attach_train(model, train_limits(cert, none));
    // The finer spline starts its bracket from the coarser one's figure.
    const bool coarse = points == 8;
    const double start = coarse || !std::isfinite(cert.any_law_coarse_rpm) || cert.any_law_coarse_rpm <= 0.0
                             ? hint
                             : cert.any_law_coarse_rpm * kRadPerSecondPerRpm;
    const double w =
        family_bound(family, f, FamilyOptions{false, false, false}, start, solves, nullptr, coarse ? 2.0 : 1.05);
    (coarse ? cert.any_law_coarse_rpm : cert.any_law_rpm) = w >= 1e3 * start ? kInf : as_rpm(w);
  }
  cert.any_law_binding = "the designed segments together on the held train (cubic spline, 16 control points each)";
}

/// The jump-free speed of `law` at P_min on the stage's model [rpm]: the
/// held train's (dense grid) on a train, the rigid one-mass model's (the law
/// sampled densely) otherwise; `hint` the top operating speed [rad/s].
double law_jump_free_rpm(const Model& model, const MotionLaw& law, const RigidFollower& f, const TrainRowLimits& limits,
                         double hint) {
  if (model.train.has_coordinates()) return as_rpm(held_jump_free_speed(model, law, limits, kTrainScanFactor * hint));
  return as_rpm(law_bound(SampledLaw(law, kVerifySamples), f, hint));
}

/// The top operating speed [rad/s]: the brackets' hint.
double top_omega(const OptimizeStudyConfig& config) {
  return *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end()) * kRadPerSecondPerRpm;
}

/// The stage's train limits: P_min at the cam and at every link, and the constraints' rows.
TrainRowLimits stage_train_limits(const OptimizeStudyConfig& config) {
  Certificate floor;
  floor.min_contact_force = rigid_min_contact_force(config);
  return train_limits(floor, config.constraints);
}

/// The rigid follower of a model whose stage ran (run_rigid_stage refuses
/// one without a linear part); throws InputError for one without.
RigidFollower stage_follower(const Model& model, double min_force) {
  const std::optional<RigidFollower> f = rigid_follower(model, min_force);
  if (!f) throw InputError("", "mechanism.follower", std::string("the rigid-model stage: ") + kNoLinearPart);
  return *f;
}

/// The one jump-free figure of `model`'s law at P_min on the stage's model [rpm].
double model_jump_free_rpm(const Model& model, const OptimizeStudyConfig& config) {
  const RigidFollower f = stage_follower(model, rigid_min_contact_force(config));
  return law_jump_free_rpm(model, *model.law, f, stage_train_limits(config), top_omega(config));
}

/// The stage's figures of its design (`scene`): the margin at each operating
/// speed, on the design's own held train's dense grid on a train, else the
/// law sampled densely with the stage's one-mass model `f`; and its one
/// jump-free figure (stage_jump_free_rpm).
void verify_design(const SceneConfig& scene, const OptimizeStudyConfig& config, const std::string& file,
                   const Model& baseline, const RigidFollower& f, RigidDesign& d) {
  std::optional<Model> own;
  try {
    own.emplace(build_model(scene, file));
  } catch (const InputError&) {
    // A design whose cam the geometry refuses (a flat face's cusp without a
    // curvature limit): its law on the baseline's model; it only starts the search.
  }
  const Model& model = own ? *own : baseline;
  const MotionLaw built = build_motion_law(scene.mechanism.cam.motion_law, file);
  const MotionLaw& law = own ? *own->law : built;
  const TrainRowLimits limits = stage_train_limits(config);
  if (model.train.has_coordinates()) {
    for (const double rpm : config.operating_rpm)
      d.verified_margin.push_back(check_held_train(model, law, rpm * kRadPerSecondPerRpm, limits).margin);
  } else {
    const SampledLaw sampled(law, kVerifySamples);
    for (const double rpm : config.operating_rpm)
      d.verified_margin.push_back(sampled.worst_margin(f, rpm * kRadPerSecondPerRpm));
  }
  const RigidFollower own_f = stage_follower(model, rigid_min_contact_force(config));
  d.jump_free_rpm = law_jump_free_rpm(model, law, own_f, limits, top_omega(config));
}

}  // namespace

bool design_holds(const RigidDesign& d, std::size_t i) {
  return d.have && i < d.verified_margin.size() && d.verified_margin[i] >= 0.0;
}

double stage_jump_free_rpm(const SceneConfig& scene, const OptimizeStudyConfig& config, const std::string& file) {
  return model_jump_free_rpm(build_model(scene, file), config);
}

bool Certificate::all_feasible() const {
  return available && std::all_of(speeds.begin(), speeds.end(), [](const SpeedCertificate& s) { return s.feasible; });
}

std::vector<double> rigid_margin_curve(const SceneConfig& scene, double rpm, double min_force,
                                       const std::vector<double>& angles_deg) {
  SceneConfig at = scene;
  at.mechanism.cam.rpm = rpm;
  const Model model = build_model(at, "");
  const RigidFollower f = stage_follower(model, min_force);
  std::vector<double> out;
  for (const double deg : angles_deg)
    out.push_back(
        f.margin(rpm * kRadPerSecondPerRpm, model.law->eval(std::min(deg, 360.0 - 1e-9) * std::numbers::pi / 180.0)));
  return out;
}

std::string Certificate::binding_text() const {
  std::string text;
  for (const std::string& b : family_binding) text += (text.empty() ? "" : ", ") + b;
  return text;
}

double rigid_min_contact_force(const OptimizeStudyConfig& config) {
  return config.rigid.min_contact_force.value_or(config.constraints.min_contact_force.value_or(0.0));
}

RigidStageResult run_rigid_stage(const SceneConfig& baseline, const OptimizeStudyConfig& config,
                                 const DesignSpace& space, const std::string& file) {
  const auto t0 = std::chrono::steady_clock::now();
  RigidStageResult out;
  Certificate& cert = out.certificate;
  cert.min_contact_force = rigid_min_contact_force(config);
  const Model model = build_model(baseline, file);
  const std::optional<RigidFollower> linear = rigid_follower(model, cert.min_contact_force);
  if (!linear) {  // the stage's programmes are linear in the forces: none without a linear part
    cert.reason = kNoLinearPart;
    return out;
  }
  RigidFollower f = *linear;
  cert.margin_unit = coordinate_units(model).force;  // a torque about the pivot for an arm
  const bool on_train = model.train.has_coordinates();
  if (on_train) f.sampled_speeds = TrainRows::kSampledSpeeds;
  const TrainRowLimits limits = train_limits(cert, config.constraints);
  SplineFamily family(space, config.design, f, model.follower, config.constraints, config.rigid.samples, file);
  if (on_train) {
    cert.model = "held train";
    family.attach_train(model, limits);
  }
  // The pointwise pressure rows are the one-mass force's; a train's go through the probe (limit_probe).
  if (const std::optional<LineContact> contact = line_contact(baseline.mechanism.contact);
      contact && config.constraints.max_contact_stress && !on_train)
    family.limit_contact_pressure(*contact, *config.constraints.max_contact_stress, operating_omegas(config, f));
  const double hint = top_omega(config);
  cert.available = true;
  cert.baseline_rpm = law_jump_free_rpm(model, *model.law, f, limits, hint);
  if (space.is_event()) {
    // The any-law bound bisects each rise and return between its end
    // levels; an event that rises and returns has its own (lift_area_part).
    cert.any_law_rpm = cert.any_law_coarse_rpm = std::numeric_limits<double>::quiet_NaN();
    cert.any_law_unavailable =
        "not computed for an event design (design.event): the any-law bound is per rise and per return, between "
        "their end levels";
  } else if (on_train) {
    any_law_on_train(baseline, config, model, f, hint, file, cert, out.lp_solves);
  } else {
    any_law_part(family, f, hint, config.rigid.certificate_grid, cert);
  }
  MarginSolution fastest;
  // A lift-area design is not the family's fastest; its certificate is the
  // area bound (lift_area_part), so (b) is left out: a dozen programmes of
  // the dense sampling such a design needs.
  const bool lift_area_goal = config.objective.lift_area > 0.0;
  const double bound = lift_area_goal ? 0.0 : family_part(family, f, hint, cert, out.lp_solves, fastest);
  if (lift_area_goal) {
    cert.family_rpm = std::numeric_limits<double>::quiet_NaN();
    cert.family_binding = {"not computed for a lift-area design"};
  }
  const FamilyOptions all{family.monotone(), true};
  for (const double rpm : config.operating_rpm) {
    const std::vector<double> omegas = check_speeds(rpm * kRadPerSecondPerRpm, f);
    const double m = std::min(solve_margin(family, omegas, all, out.lp_solves).margin, family.fixed_margin(omegas));
    cert.speeds.push_back({rpm, m >= -1e-9 * (std::abs(f.constant()) + 1.0), m});
  }
  if (!lift_area_goal && (config.rigid.explain_bound || !cert.all_feasible()))
    family_binding(family, f, hint, bound, cert, out.lp_solves);

  out.design = make_design(family, f, config, space, bound, fastest, out.lp_solves);
  const std::optional<RigidLimitProbe> probe = limit_probe(baseline, model, f, config, space, family);
  if (family.curvature_linearisable() || family.pressure_linearisable() || probe)
    out.design =
        tighten_nonlinear(family, probe ? &*probe : nullptr, f, config, space, hint, out.design, out.lp_solves);
  RigidDesign& d = out.design;
  // Before the design's figures: a stage without a design explains its lift-area bound too.
  if (config.objective.lift_area > 0.0) lift_area_part(family, f, config, space, d, *model.law, cert);
  if (d.have) verify_design(space.scene(d.x), config, file, model, f, d);
  if (on_train) {
    cert.train_harmonics = family.train()->harmonics();
    cert.train_truncation = family.train()->truncation();
  }
  out.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace camdyn::optim
