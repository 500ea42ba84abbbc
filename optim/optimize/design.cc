#include "optim/optimize/design.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/bspline.h"
#include "geometry/event_spline.h"
#include "geometry/motion_law.h"
#include "io/json_archive.h"

namespace camdyn::optim {

namespace {

constexpr int kFitSamples = 401;  // per designed segment: a few per knot span of any spline we allow

std::string segment_path(std::size_t i) { return "mechanism.cam.motion_law.segments[" + std::to_string(i) + "]"; }

/// Coefficients of the clamped spline of `shape` (n control points, degree p,
/// uniform knots) at both ends: c_0..c_2 from f, f', f'' at x = 0 and
/// c_{n−3}..c_{n−1} from those at x = 1. At a clamped end only the first k + 1
/// basis functions have a nonzero k-th derivative, so each is a triangular
/// solve; this is the inverse of how the geometry code sets the boundary
/// control points, so it recovers them exactly.
std::pair<std::array<double, 3>, std::array<double, 3>> end_coefficients(const NormalisedRise& shape, int p, int n) {
  const std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
  const LawSample f0 = shape.eval(0.0), f1 = shape.eval(1.0);
  const std::array<double, 3> v0 = {f0.s, f0.ds, f0.d2s}, v1 = {f1.s, f1.ds, f1.d2s};
  std::array<double, 3> head{}, tail{};
  const BasisDerivatives b0 = basis_derivatives(p, 0.0, p, knots);
  for (int k = 0; k < 3; ++k) {
    double r = v0[k];
    for (int i = 0; i < k; ++i) r -= b0.ders[k][i] * head[i];
    head[k] = r / b0.ders[k][k];
  }
  const BasisDerivatives b1 = basis_derivatives(n - 1, 1.0, p, knots);
  for (int k = 0; k < 3; ++k) {
    double r = v1[k];
    for (int i = 0; i < k; ++i) r -= b1.ders[k][p - i] * tail[i];
    tail[k] = r / b1.ders[k][p - k];  // tail[k] = c_{n−1−k}
  }
  return {head, tail};
}

/// Whether segments of `type` are designed.
bool is_designed(const DesignConfig& config, SegmentType type) {
  return std::find(config.segments.begin(), config.segments.end(), type) != config.segments.end();
}

/// Least-squares coefficients c_j of the m free control points of a spline of
/// degree p (n = m + 6 control points, uniform knots) so that f0 + Σ c_j N_{3+j}
/// ≈ target in value, slope and curvature, each derivative order weighted by
/// the inverse of its peak so all count. f0 is the spline with the free
/// control points at 0.
std::vector<double> fit_control_points(const NormalisedRise& target, const NormalisedRise& f0, int p, int m) {
  const int n = m + 6;
  const std::vector<double> knots = ClampedBSpline::uniform_knots(p, n);
  std::array<double, 3> peak{1e-300, 1e-300, 1e-300};
  std::vector<LawSample> t(kFitSamples), z(kFitSamples);
  for (int i = 0; i < kFitSamples; ++i) {
    const double xi = static_cast<double>(i) / (kFitSamples - 1);
    t[i] = target.eval(xi);
    z[i] = f0.eval(xi);
    peak[0] = std::max(peak[0], std::abs(t[i].s));
    peak[1] = std::max(peak[1], std::abs(t[i].ds));
    peak[2] = std::max(peak[2], std::abs(t[i].d2s));
  }
  constexpr Eigen::Index kRows = 3 * Eigen::Index{kFitSamples};
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(kRows, m);
  Eigen::VectorXd b(kRows);
  for (int i = 0; i < kFitSamples; ++i) {
    const double xi = static_cast<double>(i) / (kFitSamples - 1);
    const int s = find_span(n, p, xi, knots);
    const BasisDerivatives bd = basis_derivatives(s, xi, p, knots);
    const std::array<double, 3> tv = {t[i].s, t[i].ds, t[i].d2s}, zv = {z[i].s, z[i].ds, z[i].d2s};
    for (int order = 0; order < 3; ++order) {
      const int row = 3 * i + order;
      const double w = 1.0 / peak[order];
      b(row) = w * (tv[order] - zv[order]);
      for (int r = 0; r <= p; ++r) {
        const int j = s - p + r - 3;  // free control point j is coefficient 3 + j
        if (j >= 0 && j < m) a(row, j) = w * bd.ders[order][r];
      }
    }
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  return {c.data(), c.data() + c.size()};
}

/// How well the fitted law reproduces the baseline law on the designed
/// segments: largest lift error and largest acceleration error relative to
/// the segment's peak acceleration.
BaselineFit measure_fit(const MotionLaw& base_law, const MotionLaw& fitted, const std::vector<std::size_t>& segments) {
  BaselineFit fit;
  for (const std::size_t index : segments) {
    const NormalisedRise& target = *base_law.pieces()[index].shape;
    const NormalisedRise& got = *fitted.pieces()[index].shape;
    double peak_acc = 1e-300, err_s = 0.0, err_a = 0.0;
    for (int i = 0; i < kFitSamples; ++i) {
      const double xi = static_cast<double>(i) / (kFitSamples - 1);
      const LawSample ft = target.eval(xi), fg = got.eval(xi);
      peak_acc = std::max(peak_acc, std::abs(ft.d2s));
      err_s = std::max(err_s, std::abs(fg.s - ft.s));
      err_a = std::max(err_a, std::abs(fg.d2s - ft.d2s));
    }
    fit.max_lift_error = std::max(fit.max_lift_error, err_s);
    fit.max_acceleration_error = std::max(fit.max_acceleration_error, err_a / peak_acc);
  }
  return fit;
}

}  // namespace

struct DesignSpace::Event {
  MotionLawConfig base_config;  ///< the baseline's law, without an event of the same span
  EventSplineBasis basis;
  double scale = 1.0;     ///< the baseline's lift h: variables are control points / h [m]
  std::size_t piece = 0;  ///< the event's piece in the built law
};

DesignSpace::DesignSpace(const SceneConfig& baseline, const DesignConfig& config, const std::string& file)
    : baseline_(baseline), config_(config), file_(file) {
  if (config.event) {
    make_event(baseline);
    return;
  }
  const std::vector<SegmentConfig>& segs = baseline.mechanism.cam.motion_law.segments;
  if (segs.empty())
    throw InputError(file, "mechanism.cam.motion_law",
                     "an optimize study designs spline segments of a segmented law: give the baseline motion law as "
                     "'segments' (rise / dwell / return)");
  const MotionLaw base_law = build_motion_law(baseline.mechanism.cam.motion_law, file);
  select_segments(segs);
  read_end_ranges(segs);
  check_end_ranges(segs);
  number_variables();
  levels_vary_ = levels_move_with_angles(segs);

  // Baseline end angles as normalised variables.
  std::vector<double> x(variables_.size(), 0.0);
  for (const Designed& d : designed_)
    if (d.angle_variable >= 0) x[d.angle_variable] = (segs[d.index].end_deg - d.end_lo) / (d.end_hi - d.end_lo);

  const SceneConfig base_skeleton = skeleton(x);
  const std::vector<Levels> lv = levels(base_skeleton);
  if (!levels_vary_) fixed_levels_ = lv;
  const MotionLaw skeleton_law = build_motion_law(base_skeleton.mechanism.cam.motion_law, file);
  for (std::size_t k = 0; k < designed_.size(); ++k) {
    const Designed& d = designed_[k];
    set_bounds(d, lv[k]);
    const std::vector<double> c = fit_control_points(
        *base_law.pieces()[d.index].shape, *skeleton_law.pieces()[d.index].shape, config.degree, config.control_points);
    set_initial_control_points(d, lv[k], c, x);
  }
  initial_ = x;

  // How well the fit reproduces the baseline, measured on the built law.
  fit_ = measure_fit(base_law, build_motion_law(scene(initial_).mechanism.cam.motion_law, file), designed_segments());
}

void DesignSpace::select_segments(const std::vector<SegmentConfig>& segs) {
  for (const SegmentType type : config_.segments) {
    if (std::none_of(segs.begin(), segs.end(), [&](const SegmentConfig& s) { return s.type == type; }))
      throw InputError(file_, "design.segments",
                       "the baseline motion law has no '" + to_string(type) + "' segment to design");
  }
  for (std::size_t i = 0; i < segs.size(); ++i) {
    if (is_designed(config_, segs[i].type)) designed_.push_back({i, 0, -1, 0.0, 0.0});
  }
}

void DesignSpace::read_end_ranges(const std::vector<SegmentConfig>& segs) {
  const std::array<std::pair<SegmentType, const std::optional<std::vector<double>>*>, 2> ranges = {
      std::pair{SegmentType::rise, &config_.end_deg_range.rise},
      std::pair{SegmentType::return_, &config_.end_deg_range.ret}};
  for (const auto& [type, range] : ranges) {
    if (!*range) continue;
    const std::string at = "design.end_deg_range." + to_string(type);
    if (!is_designed(config_, type)) throw InputError(file_, at, "'" + to_string(type) + "' is not in design.segments");
    const long count =
        std::count_if(segs.begin(), segs.end(), [&wanted = type](const SegmentConfig& s) { return s.type == wanted; });
    if (count != 1)
      throw InputError(file_, at,
                       "the baseline has " + std::to_string(count) + " '" + to_string(type) +
                           "' segments; an end-angle range needs exactly one");
    for (Designed& d : designed_) {
      if (segs[d.index].type != type) continue;
      if (d.index + 1 == segs.size())
        throw InputError(file_, at, "the last segment ends at 360 deg; its end angle cannot vary");
      d.end_lo = (**range)[0];
      d.end_hi = (**range)[1];
      d.angle_variable = 0;  // numbered by number_variables
      if (segs[d.index].end_deg < d.end_lo || segs[d.index].end_deg > d.end_hi)
        throw InputError(file_, at,
                         "the baseline end angle " + format_shortest(segs[d.index].end_deg) + " deg is outside [" +
                             format_shortest(d.end_lo) + ", " + format_shortest(d.end_hi) + "]");
    }
  }
}

void DesignSpace::check_end_ranges(const std::vector<SegmentConfig>& segs) const {
  auto end_range = [&](std::size_t i) -> std::pair<double, double> {  // reach of segment i's end [deg]
    if (i >= segs.size()) return {360.0, 360.0};
    for (const Designed& d : designed_)
      if (d.index == i && d.angle_variable >= 0) return {d.end_lo, d.end_hi};
    return {segs[i].end_deg, segs[i].end_deg};
  };
  for (const Designed& d : designed_) {
    if (d.angle_variable < 0) continue;
    const std::string at = "design.end_deg_range." + to_string(segs[d.index].type);
    const double start_max = d.index == 0 ? 0.0 : end_range(d.index - 1).second;
    const double next_min = end_range(d.index + 1).first;
    if (d.end_lo <= start_max || d.end_hi >= next_min)
      throw InputError(file_, at,
                       "must lie strictly between where the segment can start (" + format_shortest(start_max) +
                           " deg) and where the next segment can end (" + format_shortest(next_min) + " deg)");
  }
}

void DesignSpace::number_variables() {
  const int m = config_.control_points;
  for (Designed& d : designed_) {
    d.first_variable = static_cast<int>(variables_.size());
    for (int j = 0; j < m; ++j)
      variables_.push_back({"segments[" + std::to_string(d.index) + "].control_points[" + std::to_string(j) + "]"});
    if (d.angle_variable >= 0) {
      d.angle_variable = static_cast<int>(variables_.size());
      variables_.push_back({"segments[" + std::to_string(d.index) + "].end_deg", 0.0, 1.0});
    }
  }
}

bool DesignSpace::levels_move_with_angles(const std::vector<SegmentConfig>& segs) const {
  for (const Designed& d : designed_) {
    if (d.angle_variable < 0) continue;
    for (std::size_t nb : {(d.index + segs.size() - 1) % segs.size(), (d.index + 1) % segs.size()}) {
      if (segs[nb].type != SegmentType::dwell && !is_designed(config_, segs[nb].type)) return true;
    }
  }
  return false;
}

void DesignSpace::set_bounds(const Designed& d, const Levels& lv) {
  if (config_.monotone && lv.high < lv.low)
    throw InputError(file_, segment_path(d.index),
                     "cannot keep this segment monotone: its neighbours' rates put the boundary control points out "
                     "of order (set design.monotone to false)");
  const double span = std::max(lv.high - lv.low, 1e-3);
  for (int j = 0; j < config_.control_points; ++j) {
    DesignVariable& v = variables_[d.first_variable + j];
    if (config_.monotone) {
      v.lower = 0.0;
      v.upper = 1.0;
    } else {
      v.lower = lv.low - 0.5 * span;
      v.upper = lv.high + 0.5 * span;
    }
  }
}

void DesignSpace::set_initial_control_points(const Designed& d, const Levels& lv, const std::vector<double>& c,
                                             std::vector<double>& x) const {
  double prev = lv.low;
  for (int j = 0; j < config_.control_points; ++j) {
    const DesignVariable& v = variables_[d.first_variable + j];
    double value = c[j];
    if (config_.monotone) {
      const double room = lv.high - prev;
      value = room > 1e-12 ? std::clamp((c[j] - prev) / room, 0.0, 1.0) : 0.0;
      prev += value * room;
    }
    x[d.first_variable + j] = std::clamp(value, v.lower, v.upper);
  }
}

std::vector<double> DesignSpace::lower() const {
  std::vector<double> v;
  for (const DesignVariable& d : variables_) v.push_back(d.lower);
  return v;
}

std::vector<double> DesignSpace::upper() const {
  std::vector<double> v;
  for (const DesignVariable& d : variables_) v.push_back(d.upper);
  return v;
}

std::vector<std::size_t> DesignSpace::designed_segments() const {
  if (event_) return {event_->piece};
  std::vector<std::size_t> v;
  for (const Designed& d : designed_) v.push_back(d.index);
  return v;
}

SceneConfig DesignSpace::skeleton(const std::vector<double>& x) const {
  SceneConfig scene = baseline_;
  std::vector<SegmentConfig>& segs = scene.mechanism.cam.motion_law.segments;
  scene.mechanism.cam.motion_law.source.clear();  // no longer the profile file it came from
  for (const Designed& d : designed_) {
    SegmentConfig& s = segs[d.index];
    s.law = SegmentLaw::spline;
    s.degree = config_.degree;
    s.control_points.assign(static_cast<std::size_t>(config_.control_points), 0.0);
    if (d.angle_variable >= 0) s.end_deg = d.end_lo + x[d.angle_variable] * (d.end_hi - d.end_lo);
  }
  return scene;
}

std::vector<DesignSpace::Levels> DesignSpace::levels(const SceneConfig& skel) const {
  const MotionLaw law = build_motion_law(skel.mechanism.cam.motion_law, file_);
  const int n = config_.control_points + 6;
  std::vector<Levels> out;
  for (const Designed& d : designed_) {
    const auto [head, tail] = end_coefficients(*law.pieces()[d.index].shape, config_.degree, n);
    out.push_back({head[2], tail[2]});
  }
  return out;
}

std::vector<double> DesignSpace::control_points(const Designed& d, const Levels& lv,
                                                const std::vector<double>& x) const {
  std::vector<double> c(static_cast<std::size_t>(config_.control_points));
  double prev = lv.low;
  for (std::size_t j = 0; j < c.size(); ++j) {
    const double v = x[d.first_variable + static_cast<int>(j)];
    if (config_.monotone) {
      prev += v * (lv.high - prev);
      c[j] = prev;
    } else {
      c[j] = v;
    }
  }
  return c;
}

std::vector<std::pair<double, double>> DesignSpace::control_point_levels() const {
  if (event_) return {{0.0, 1.0}};
  const std::vector<Levels> lv = levels_vary_ ? levels(skeleton(initial_)) : fixed_levels_;
  std::vector<std::pair<double, double>> out;
  for (const Levels& l : lv) out.emplace_back(l.low, l.high);
  return out;
}

SceneConfig DesignSpace::scene_with_control_points(const std::vector<double>& c) const {
  if (event_) {
    std::vector<double> metres(c.size());
    for (std::size_t j = 0; j < c.size(); ++j) metres[j] = c[j] * event_->scale;
    return event_scene(metres);
  }
  SceneConfig scene = skeleton(initial_);
  std::vector<SegmentConfig>& segs = scene.mechanism.cam.motion_law.segments;
  const auto m = static_cast<std::size_t>(config_.control_points);
  for (std::size_t k = 0; k < designed_.size(); ++k)
    segs[designed_[k].index].control_points.assign(c.begin() + static_cast<std::ptrdiff_t>(k * m),
                                                   c.begin() + static_cast<std::ptrdiff_t>((k + 1) * m));
  return scene;
}

std::vector<double> DesignSpace::design_from_control_points(const std::vector<double>& c) const {
  if (event_) {
    std::vector<double> x(c.size());
    for (std::size_t j = 0; j < c.size(); ++j) x[j] = std::clamp(c[j], variables_[j].lower, variables_[j].upper);
    return x;
  }
  const std::vector<Levels> lv = levels_vary_ ? levels(skeleton(initial_)) : fixed_levels_;
  std::vector<double> x = initial_;
  const auto m = static_cast<std::size_t>(config_.control_points);
  for (std::size_t k = 0; k < designed_.size(); ++k)
    set_initial_control_points(designed_[k], lv[k],
                               std::vector<double>(c.begin() + static_cast<std::ptrdiff_t>(k * m),
                                                   c.begin() + static_cast<std::ptrdiff_t>((k + 1) * m)),
                               x);
  return x;
}

SceneConfig DesignSpace::scene(const std::vector<double>& x) const {
  if (event_) {
    std::vector<double> c(x.size());
    for (std::size_t j = 0; j < x.size(); ++j) c[j] = x[j] * event_->scale;
    return event_scene(c);
  }
  SceneConfig scene = skeleton(x);
  const std::vector<Levels> lv = levels_vary_ ? levels(scene) : fixed_levels_;
  std::vector<SegmentConfig>& segs = scene.mechanism.cam.motion_law.segments;
  for (std::size_t k = 0; k < designed_.size(); ++k)
    segs[designed_[k].index].control_points = control_points(designed_[k], lv[k], x);
  return scene;
}

// ---------------------------------------------------------------- event design

namespace {

/// Least-squares free control points of `basis` so that the event spline
/// follows `target` on the span in value, slope and curvature (each order
/// weighted by the inverse of its peak).
std::vector<double> fit_event(const MotionLaw& target, const EventSplineBasis& basis) {
  const int m = basis.free, p = basis.degree, n = basis.count();
  const double beta = basis.span();
  const std::vector<double> fixed = basis.coefficients(std::vector<double>(static_cast<std::size_t>(m), 0.0));
  const ClampedBSpline f0(p, basis.knots, fixed);
  std::array<double, 3> peak{1e-300, 1e-300, 1e-300};
  std::vector<std::array<double, 3>> t(kFitSamples);
  for (int i = 0; i < kFitSamples; ++i) {
    const double xi = static_cast<double>(i) / (kFitSamples - 1);
    const LawSample s = target.eval(basis.from + xi * beta);
    t[i] = {s.s, s.ds * beta, s.d2s * beta * beta};  // in x = (θ − from) / β
    for (int k = 0; k < 3; ++k) peak[k] = std::max(peak[k], std::abs(t[i][k]));
  }
  constexpr Eigen::Index kRows = 3 * Eigen::Index{kFitSamples};
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(kRows, m);
  Eigen::VectorXd b(kRows);
  for (int i = 0; i < kFitSamples; ++i) {
    const double xi = static_cast<double>(i) / (kFitSamples - 1);
    const int span = find_span(n, p, xi, basis.knots);
    const BasisDerivatives bd = basis_derivatives(span, xi, p, basis.knots);
    const Derivatives3 z = f0.eval(xi);
    for (int order = 0; order < 3; ++order) {
      const int row = 3 * i + order;
      const double w = 1.0 / peak[order];
      b(row) = w * (t[i][order] - z[order]);
      for (int r = 0; r <= p; ++r) {
        const int j = span - p + r - basis.first_free();
        if (j >= 0 && j < m) a(row, j) = w * bd.ders[order][r];
      }
    }
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  return {c.data(), c.data() + c.size()};
}

}  // namespace

void DesignSpace::make_event(const SceneConfig& baseline) {
  const DesignEventConfig& ev = *config_.event;
  const std::string at = "design.event";
  const MotionLawConfig& law_config = baseline.mechanism.cam.motion_law;
  if (law_config.contour)
    throw InputError(file_, "mechanism.cam.motion_law",
                     "an event design needs the baseline as a motion law (segments, spline or table), not a contour");
  auto e = std::make_shared<Event>();
  e->base_config = law_config;
  e->base_config.source.clear();
  if (law_config.event) {
    if (law_config.event->from_deg != ev.from_deg || law_config.event->to_deg != ev.to_deg)
      throw InputError(file_, at,
                       "the baseline law already has an event over a different span (" +
                           format_shortest(law_config.event->from_deg) + " to " +
                           format_shortest(law_config.event->to_deg) + " deg)");
    e->base_config.event.reset();  // the same span: designed anew over the same kept law
  }
  const MotionLaw base = build_motion_law(e->base_config, file_);
  const int order = event_join_order(config_.degree);
  if (config_.control_points + 2 * (order + 1) < config_.degree + 1)
    throw InputError(file_, "design.control_points",
                     "too few for a degree-" + std::to_string(config_.degree) + " event spline");
  const double to = ev.to_deg == 360.0 ? 2.0 * std::numbers::pi : ev.to_deg * kDegToRad;
  e->basis = event_spline_basis(base, ev.from_deg * kDegToRad, to, config_.degree, config_.control_points);
  e->scale = std::max(base.max_s() - base.min_s(), 1e-9);
  const std::vector<double> fitted = fit_event(base, e->basis);
  const MotionLaw fitted_law = splice_event(base, e->basis, fitted);
  e->piece = event_piece_index(fitted_law, e->basis);
  event_ = e;
  for (int j = 0; j < config_.control_points; ++j)
    variables_.push_back({"event.control_points[" + std::to_string(j) + "]", -0.5, 1.5});
  std::vector<double> normalised(fitted.size());
  for (std::size_t j = 0; j < fitted.size(); ++j) normalised[j] = fitted[j] / e->scale;
  initial_ = design_from_control_points(normalised);
  // How well the fit reproduces the baseline over the event.
  double peak_acc = 1e-300;
  for (int i = 0; i < kFitSamples; ++i) {
    const double th = e->basis.from + e->basis.span() * i / (kFitSamples - 1.0);
    const LawSample a = base.eval(th), b = fitted_law.eval(th);
    peak_acc = std::max(peak_acc, std::abs(a.d2s));
    fit_.max_lift_error = std::max(fit_.max_lift_error, std::abs(a.s - b.s) / e->scale);
    fit_.max_acceleration_error = std::max(fit_.max_acceleration_error, std::abs(a.d2s - b.d2s));
  }
  fit_.max_acceleration_error /= peak_acc;
}

SceneConfig DesignSpace::event_scene(const std::vector<double>& c) const {
  SceneConfig scene = baseline_;
  MotionLawConfig& law = scene.mechanism.cam.motion_law;
  law = event_->base_config;
  EventSplineConfig ev;
  ev.from_deg = config_.event->from_deg;
  ev.to_deg = config_.event->to_deg;
  ev.degree = config_.degree;
  ev.control_points = c;
  law.event = ev;
  return scene;
}

const EventSplineBasis& DesignSpace::event_basis() const { return event_->basis; }

double DesignSpace::event_scale() const { return event_->scale; }

int DesignSpace::free_offset() const { return event_ ? event_->basis.first_free() : 3; }

int DesignSpace::spline_size() const { return event_ ? event_->basis.count() : config_.control_points + 6; }

}  // namespace camdyn::optim
