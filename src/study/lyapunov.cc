// The largest Lyapunov exponent of the Poincaré map (docs/periodic.md, "How",
// the Lyapunov exponent): a tangent w of unit scaled norm (max |w_j| / scale_j)
// carried along the motion one revolution at a time, and λ the mean of
// ln |P′(x) w| per revolution, w renormalised each revolution. Each
// revolution stretches w either
// * by forward sensitivities (dynamics/map_sensitivity.h, sensitivity_product):
//   one run with a single sensitivity column gives both P(x) and P′(x) w,
//   with the saltation matrices at the events — the tangent-linear form of
//   Benettin's method for motions with impacts (Müller 1995); or
// * by a neighbour trajectory (Benettin et al. 1980): P(x) and P(x + d₀ w)
//   by two map runs (in parallel when two threads are allowed), their
//   difference over d₀ for P′(x) w.
// The sensitivities are taken where lyapunov_by_sensitivities says so (only
// when `periodic.jacobian` is "sensitivity": they cost more); a revolution whose sensitivity run
// cannot be trusted (a grazing event, accumulating impacts, …) is stretched
// by the neighbour instead, and counted.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <string>

#include "common/constants.h"
#include "common/errors.h"
#include "common/parallel.h"
#include "dynamics/map_sensitivity.h"
#include "study/periodic_orbit.h"

namespace camdyn {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

// The neighbour trajectory's least scaled distance d₀ [-]. A stiff contact
// amplifies the two runs' integration errors far beyond rtol: on the
// bouncing ball (contact stiffness 1e12, rtol 1e-10) contracting with the
// multiplier 0.9954 (λ = −0.0046), d₀ = 1e-7 gave stretches scattered by
// ±0.3 and λ = −0.033 ± 0.016; 1e-6 gave −0.0026 ± 0.0030, 1e-5
// −0.0048 ± 0.0003. Scenes at rtol ≥ 1e-8 had d₀ = 1e3·rtol ≥ 1e-5 already.
constexpr double kLeastNeighbourDistance = 1e-5;

// The run's state between revolutions, and its bookkeeping.
class TangentRun {
 public:
  TangentRun(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options, bool sensitivities)
      : map_(map),
        options_(options),
        threads_(std::min(2, std::max(1, options.threads))),
        sensitivities_(sensitivities),
        scales_(to_vector(map.scales())),
        d0_(std::max(kLeastNeighbourDistance, 1e3 * map.scene().integrator.rtol)),
        x_(start),
        w_(scales_),
        neighbour_speed_(start.approach_speed) {
    for (int i = 0; i < threads_; ++i) workspaces_.push_back(make_workspace(map.model()));
  }

  // One revolution: its stretch added to the estimate, x and w moved on.
  void advance(LyapunovEstimate& e) {
    const std::optional<double> by_tangent = sensitivities_ ? tangent_step(e) : std::nullopt;
    const double stretch = by_tangent ? *by_tangent : neighbour_step(e);
    e.stretches.push_back(stretch);
    ++e.revolutions;
    e.section_points.push_back(x_.x);
    e.last = x_;
  }

  long revolutions() const { return revolutions_; }

 private:
  // ln |P′(x) w| by one sensitivity run, or nullopt (counted as a fallback)
  // when it cannot be trusted.
  std::optional<double> tangent_step(LyapunovEstimate& e) {
    const MapJacobian r = sensitivity_product(map_, x_, 1, w_, workspaces_.front());
    ++revolutions_;
    const double d = r.ok ? scaled_norm(r.jacobian.col(0)) : 0.0;
    if (!(d > 0.0 && std::isfinite(d))) {
      const std::string why = r.ok ? "the tangent vanished" : r.reason;
      if (why != e.fallback_reason && options_.log)
        options_.log("Lyapunov: a revolution by a neighbour trajectory: " + why);
      e.fallback_reason = why;
      ++e.fallback_revolutions;
      return std::nullopt;
    }
    w_ = r.jacobian.col(0) / d;
    x_ = r.end;
    neighbour_speed_ = x_.approach_speed;
    e.impacts += r.impacts;
    ++e.sensitivity_revolutions;
    return std::log(d);
  }

  // ln(d / d₀) of the neighbour x + d₀ w after one revolution.
  double neighbour_step(LyapunovEstimate& e) {
    SectionPoint neighbour = x_;
    neighbour.approach_speed = neighbour_speed_;
    for (std::size_t j = 0; j < neighbour.x.size(); ++j) neighbour.x[j] += d0_ * w_[static_cast<Eigen::Index>(j)];
    MapResult ends[2];
    parallel_for_workers(2, threads_, [&](int w, std::size_t i) {
      ends[i] = map_.apply(i == 0 ? x_ : neighbour, 1, workspaces_[static_cast<std::size_t>(w)]);
    });
    revolutions_ += 2;
    for (const MapResult& end : ends)
      if (!end.ok)
        throw NumericalError("the Lyapunov run failed after " + std::to_string(e.revolutions) +
                             " revolutions: " + end.message);
    const VectorXd difference = to_vector(ends[1].end.x) - to_vector(ends[0].end.x);
    const double d = std::max(scaled_norm(difference), 1e-300);
    w_ = difference / d;
    x_ = ends[0].end;
    neighbour_speed_ = ends[1].end.approach_speed;
    e.impacts += ends[0].impacts;
    return std::log(d / d0_);
  }

  double scaled_norm(const VectorXd& a) const {
    return camdyn::scaled_norm({a.data(), static_cast<std::size_t>(a.size())}, map_.scales());
  }

  const PoincareMap& map_;
  const PeriodicOptions& options_;
  const int threads_;
  const bool sensitivities_;
  const VectorXd scales_;
  const double d0_;  // the neighbour's scaled distance [-]
  std::vector<Workspace> workspaces_;
  SectionPoint x_;
  VectorXd w_;              // the tangent [SI], scaled norm 1
  double neighbour_speed_;  // the neighbour's approach speed [m/s]
  long revolutions_ = 0;    // integrated, both trajectories'
};

// The first revolutions, at most, whose stretches say how the tangent turns
// from its start along the scales towards the most expanding direction, not
// how the motion stretches: left out of λ. With the ball contracting onto its
// orbit at 603 rpm (multipliers −0.995 and −0.44) they added 2.1 to the sum,
// +0.01 a revolution over 200: as much as the chaos threshold.
constexpr int kAligningRevolutions = 10;

}  // namespace

std::optional<double> lyapunov_standard_error(std::span<const double> stretches) {
  constexpr std::size_t kBatches = 10, kLeast = 2 * kBatches;
  if (stretches.size() < kLeast) return std::nullopt;
  const std::size_t per = stretches.size() / kBatches;
  std::array<double, kBatches> means{};
  for (std::size_t b = 0; b < kBatches; ++b) {
    for (std::size_t i = 0; i < per; ++i) means[b] += stretches[b * per + i];
    means[b] /= static_cast<double>(per);
  }
  double mean = 0.0, variance = 0.0;
  for (const double m : means) mean += m / kBatches;
  for (const double m : means) variance += (m - mean) * (m - mean) / (kBatches - 1);
  return std::sqrt(variance / kBatches);
}

bool section_points_recur(const std::vector<std::vector<double>>& points, std::span<const double> scales) {
  constexpr std::size_t kLeast = 8;
  constexpr double kReach = 2.0;  // [spacings]
  if (points.size() < kLeast) return false;
  const std::size_t half = points.size() / 2;
  // The distance from `p` to the nearest first-half sample other than the i-th.
  const auto nearest_earlier = [&](const std::vector<double>& p, std::size_t skip) {
    double d = kInf;
    for (std::size_t i = 0; i < half; ++i)
      if (i != skip) d = std::min(d, scaled_distance(p, points[i], scales));
    return d;
  };
  double spacing = 0.0;  // the widest nearest-neighbour spacing of the first half
  for (std::size_t i = 0; i < half; ++i) spacing = std::max(spacing, nearest_earlier(points[i], i));
  for (std::size_t i = half; i < points.size(); ++i)
    if (nearest_earlier(points[i], half) > kReach * spacing) return false;
  return true;
}

bool lyapunov_by_sensitivities(const PoincareMap& /*map*/, const PeriodicOptions& options) {
  return options.jacobian == JacobianMethod::sensitivity;
}

LyapunovEstimate estimate_lyapunov(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options,
                                   long* revolutions) {
  LyapunovEstimate e;
  e.method = lyapunov_by_sensitivities(map, options) ? JacobianMethod::sensitivity : JacobianMethod::finite_difference;
  TangentRun run(map, start, options, e.method == JacobianMethod::sensitivity);
  e.aligning_revolutions = std::min(kAligningRevolutions, options.lyapunov_revolutions / 10);
  long aligning_impacts = 0;
  for (int r = 0; r < options.lyapunov_revolutions; ++r) {
    if (r == e.aligning_revolutions) aligning_impacts = e.impacts;
    run.advance(e);
  }
  const std::span<const double> counted =
      std::span<const double>(e.stretches)
          .subspan(std::min(e.stretches.size(), static_cast<std::size_t>(e.aligning_revolutions)));
  double sum = 0.0;
  for (const double s : counted) sum += s;
  const long impacts = e.impacts - aligning_impacts;
  e.per_revolution = counted.empty() ? 0.0 : sum / static_cast<double>(counted.size());
  e.per_impact = impacts > 0 ? sum / static_cast<double>(impacts) : 0.0;
  e.standard_error = lyapunov_standard_error(counted);
  e.samples_recur = section_points_recur(e.section_points, map.scales());
  if (revolutions) *revolutions += run.revolutions();
  return e;
}

}  // namespace camdyn
