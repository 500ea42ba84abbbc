#include "study/periodic_orbit.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>

#include "common/errors.h"
#include "common/parallel.h"
#include "dynamics/map_sensitivity.h"

namespace camdyn {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

std::string printf_format(const char* fmt, auto... args) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, fmt, args...);
  return buffer;
}

// The map evaluations of one analysis: a workspace per thread, the count of
// revolutions integrated, and the failures' messages.
class Shooter {
 public:
  Shooter(const PoincareMap& map, const PeriodicOptions& options)
      : map_(map), options_(options), scales_(to_vector(map.scales())) {
    const int threads = std::max(1, options.threads);
    for (int i = 0; i < threads; ++i) workspaces_.push_back(make_workspace(map.model()));
  }

  // P^k(p) on worker w's workspace; nullopt when the run failed.
  std::optional<SectionPoint> apply(const SectionPoint& p, int k, int w = 0, long* impacts = nullptr) {
    const MapResult r = map_.apply(p, k, workspaces_[static_cast<std::size_t>(w)]);
    revolutions_ += k;
    ++evaluations_;
    if (impacts) *impacts = r.impacts;
    if (!r.ok) {
      const std::lock_guard<std::mutex> lock(mutex_);
      failure_ = r.message;
      return std::nullopt;
    }
    return r.end;
  }

  // Max |a_j| / scale_j.
  double scaled_norm(const VectorXd& a) const {
    return camdyn::scaled_norm({a.data(), static_cast<std::size_t>(a.size())}, map_.scales());
  }

  // ∂P^k/∂x at p, and how it was taken: by forward sensitivities where the
  // options allow and the run can be trusted — its end agrees with `image`,
  // P^k(p) as the map's own run found it with `impacts` impacts — else by
  // central differences; nullopt when those failed.
  std::optional<std::pair<MatrixXd, JacobianMethod>> jacobian(const SectionPoint& p, int k, const SectionPoint& image,
                                                              long impacts) {
    const bool sensitivities_pay = map_.dimension() >= options_.sensitivity_min_coordinates;
    if (options_.jacobian == JacobianMethod::sensitivity ||
        (options_.jacobian == JacobianMethod::automatic && sensitivities_pay)) {
      if (std::optional<MatrixXd> J = sensitivity(p, k, image, impacts)) {
        ++sensitivity_jacobians_;
        return std::pair{std::move(*J), JacobianMethod::sensitivity};
      }
      if (options_.jacobian == JacobianMethod::sensitivity)
        throw NumericalError(
            "the sensitivity Jacobian of the Poincaré map cannot be trusted (periodic.jacobian = "
            "\"sensitivity\"): " +
            fallback_);
    }
    std::optional<MatrixXd> J = finite_difference_jacobian(p, k);
    if (!J) return std::nullopt;
    ++finite_difference_jacobians_;
    return std::pair{std::move(*J), JacobianMethod::finite_difference};
  }

  // ∂P^k/∂x at p by central differences, the 2n evaluations in parallel;
  // nullopt when one failed.
  std::optional<MatrixXd> finite_difference_jacobian(const SectionPoint& p, int k) {
    const int n = map_.dimension();
    const double h_rel = 10.0 * std::sqrt(std::max(map_.scene().integrator.rtol, 1e-14));
    std::vector<std::optional<SectionPoint>> ends(2 * static_cast<std::size_t>(n));
    parallel_for_workers(ends.size(), static_cast<int>(workspaces_.size()), [&](int w, std::size_t i) {
      SectionPoint q = p;
      const std::size_t j = i / 2;
      q.x[j] += (i % 2 == 0 ? 1.0 : -1.0) * h_rel * scales_[static_cast<Eigen::Index>(j)];
      ends[i] = apply(q, k, w);
    });
    MatrixXd J(n, n);
    for (int j = 0; j < n; ++j) {
      const auto& plus = ends[2 * static_cast<std::size_t>(j)];
      const auto& minus = ends[2 * static_cast<std::size_t>(j) + 1];
      if (!plus || !minus) return std::nullopt;
      J.col(j) = (to_vector(plus->x) - to_vector(minus->x)) / (2.0 * h_rel * scales_[j]);
    }
    return J;
  }

  long sensitivity_jacobians() const { return sensitivity_jacobians_; }
  long finite_difference_jacobians() const { return finite_difference_jacobians_; }
  const std::string& fallback() const { return fallback_; }

  void log(const std::string& line) const {
    if (options_.log) options_.log(line);
  }
  const VectorXd& scales() const { return scales_; }
  long revolutions() const { return revolutions_; }
  long evaluations() const { return evaluations_; }
  const std::string& failure() const { return failure_; }

 private:
  const PoincareMap& map_;
  const PeriodicOptions& options_;
  const VectorXd scales_;
  std::vector<Workspace> workspaces_;
  std::atomic<long> revolutions_{0}, evaluations_{0};
  long sensitivity_jacobians_ = 0, finite_difference_jacobians_ = 0;
  std::mutex mutex_;
  std::string failure_;
  std::string fallback_;  // why the last sensitivity run was not used

  // The sensitivity Jacobian on worker 0's workspace, when its run can be
  // trusted: it covers the model, ran to the end, and found the map's own end
  // (within 1e4 rtol of the scales: the two runs differ only by their
  // integration errors, closed-form against integrated flights) with as many
  // impacts; otherwise nullopt with the reason in fallback_ (logged when it
  // changes).
  std::optional<MatrixXd> sensitivity(const SectionPoint& p, int k, const SectionPoint& image, long impacts) {
    const MapJacobian r = sensitivity_jacobian(map_, p, k, workspaces_.front());
    revolutions_ += k;
    std::string why = r.reason;
    if (r.ok && r.impacts != impacts)
      why = printf_format("the sensitivity run found %ld impacts, the map's run %ld", r.impacts, impacts);
    const double agreement = std::max(1e-6, 1e4 * map_.scene().integrator.rtol);
    if (r.ok && why.empty()) {
      const double d = scaled_norm(to_vector(r.end.x) - to_vector(image.x));
      if (!(d <= agreement))
        why = printf_format("the sensitivity run ended %.3g (scaled) from the map's run, more than %.3g", d, agreement);
    }
    if (why.empty()) return r.jacobian;
    if (why != fallback_) log("Jacobian by finite differences: " + why);
    fallback_ = why;
    return std::nullopt;
  }
};

// Iterations without a new least residual after which the shooting of a
// period gives up: Newton converging (or a stable orbit followed) lowers its
// best residual every iteration or two; on a chaotic motion it wanders, and
// each further iteration costs a Jacobian (2n map runs).
constexpr int kStagnantIterations = 4;

// Within this many shooting tolerances (scaled) of an orbit a point is near
// it: Newton's tolerance on P^k allows |P^d(x) − x| a few times larger when a
// multiplier of P^d is near −1, and a point stopped that close is the orbit's.
constexpr double kNearTolerances = 1e3;

// The largest |multiplier| above which an orbit Newton is near (residual
// within kNearTolerances) is unstable beyond doubt: a multiplier moves by
// about the distance to the orbit times the map's curvature, orders of
// magnitude less than this margin on a smooth map
// (PeriodicOptions::stable_orbits_only).
constexpr double kClearlyUnstableRadius = 1.2;

// Newton on P^k(x) − x = 0 from `start`, damped by step halving and, where
// no step helps, by following the motion; the converged orbit, or nullopt
// (also when the residual stagnates, kStagnantIterations, and, with
// options.stable_orbits_only, near a clearly unstable orbit: then its last
// iterate goes to `unstable_near` when given).
std::optional<Orbit> shoot(Shooter& shooter, const SectionPoint& start, int k, const PeriodicOptions& options,
                           std::vector<NewtonStep>& trace, SectionPoint* unstable_near = nullptr) {
  SectionPoint x = start;
  long impacts = 0;  // of the run that gave `image`
  std::optional<SectionPoint> image = shooter.apply(x, k, 0, &impacts);
  const int n = static_cast<int>(x.x.size());
  double least = std::numeric_limits<double>::infinity();  // least residual so far [-]
  int least_at = 0;                                        // its iteration
  for (int it = 0; image; ++it) {
    const VectorXd residual = to_vector(image->x) - to_vector(x.x);
    const double norm = shooter.scaled_norm(residual);
    trace.push_back({k, it, norm});
    shooter.log(printf_format("period %d: Newton iteration %d, residual %.3e", k, it, norm));
    if (norm < least) {
      least = norm;
      least_at = it;
    } else if (it - least_at >= kStagnantIterations) {
      shooter.log(printf_format("period %d: the residual has not fallen below %.3e in %d iterations: giving up", k,
                                least, kStagnantIterations));
      return std::nullopt;
    }
    std::optional<std::pair<MatrixXd, JacobianMethod>> jacobian = shooter.jacobian(x, k, *image, impacts);
    if (!jacobian) return std::nullopt;
    const MatrixXd* J = &jacobian->first;
    if (norm <= options.tolerance) {
      Orbit orbit{k, x, *J, jacobian->second, floquet_multipliers(*J), false, it, norm};
      orbit.stable = orbit.spectral_radius() < 1.0;
      return orbit;
    }
    if (it >= options.max_newton_iterations || !std::isfinite(norm)) return std::nullopt;
    if (options.stable_orbits_only && norm <= kNearTolerances * options.tolerance && J->allFinite()) {
      const double radius = std::abs(floquet_multipliers(*J).front());
      if (radius > kClearlyUnstableRadius) {
        shooter.log(
            printf_format("period %d: within %.3e of an orbit whose largest |multiplier| is %.4g: unstable, not "
                          "refined further",
                          k, norm, radius));
        if (unstable_near) *unstable_near = x;
        return std::nullopt;
      }
    }
    const VectorXd step = (*J - MatrixXd::Identity(n, n)).fullPivLu().solve(-residual);
    if (!step.allFinite()) return std::nullopt;
    // Halve the step until the residual falls (at most twice), keeping the
    // trial's image for the next iteration. When no step lowers it (the
    // Jacobian is poor, e.g. the number of impacts changes nearby), follow
    // the motion k revolutions instead: x ← P^k(x), which a stable orbit
    // attracts, and try Newton again from there.
    bool accepted = false;
    for (double t = 1.0; t > 0.2 && !accepted; t *= 0.5) {
      SectionPoint trial = x;
      for (int j = 0; j < n; ++j) trial.x[static_cast<std::size_t>(j)] += t * step[j];
      long trial_impacts = 0;
      std::optional<SectionPoint> trial_image = shooter.apply(trial, k, 0, &trial_impacts);
      if (!trial_image) continue;
      const double trial_norm = shooter.scaled_norm(to_vector(trial_image->x) - to_vector(trial.x));
      if (trial_norm < norm) {
        x = trial;
        x.approach_speed = trial_image->approach_speed;  // the episode the orbit closes on
        image = trial_image;
        impacts = trial_impacts;
        accepted = true;
      }
    }
    if (!accepted) {
      x = *image;
      image = shooter.apply(x, k, 0, &impacts);
    }
  }
  return std::nullopt;
}

// P^d(x) when it returns within `near` of x (and that run's impacts in
// `impacts`), else nullopt.
std::optional<SectionPoint> image_near(Shooter& shooter, const SectionPoint& x, int d, double near,
                                       long* impacts = nullptr) {
  std::optional<SectionPoint> image = shooter.apply(x, d, 0, impacts);
  if (!image || shooter.scaled_norm(to_vector(image->x) - to_vector(x.x)) > near) return std::nullopt;
  return image;
}

// The orbit of period k as one of period d when each of its k/d phases
// x, P^d(x), P^2d(x), … returns within `near` after d revolutions: the same
// motion seen through the map's noise (a chattering motion's map is rough on
// the scale of the shooting tolerance, and Newton on P^d may wander there).
// Its monodromy is the Jacobian of P^d at x. Kept only when it says what the
// period-k orbit says about stability; nullopt otherwise.
// `first_image` is P^d of the fixed point, within `near` of it, and
// `first_impacts` that run's impacts (at_minimal_period has them).
std::optional<Orbit> repeating_every(Shooter& shooter, const Orbit& orbit, int d, double near,
                                     const SectionPoint& first_image, long first_impacts) {
  SectionPoint x = first_image;
  for (int j = 1; j < orbit.period / d; ++j) {
    const std::optional<SectionPoint> image = image_near(shooter, x, d, near);
    if (!image) return std::nullopt;
    x = *image;
  }
  const std::optional<std::pair<MatrixXd, JacobianMethod>> jacobian =
      shooter.jacobian(orbit.fixed_point, d, first_image, first_impacts);
  if (!jacobian) return std::nullopt;
  const double residual = shooter.scaled_norm(to_vector(first_image.x) - to_vector(orbit.fixed_point.x));
  Orbit o{d,     orbit.fixed_point,       jacobian->first, jacobian->second, floquet_multipliers(jacobian->first),
          false, orbit.newton_iterations, residual};
  o.stable = o.spectral_radius() < 1.0;
  if (o.stable != orbit.stable) return std::nullopt;
  return o;
}

// The orbit at its minimal period: for every divisor d of k, smallest first,
// where P^d nearly returns the fixed point of P^k (within kNearTolerances
// shooting tolerances), Newton on P^d from
// there; when it converges to the same point, the orbit is reported at period
// d with that map's monodromy and multipliers (those of P^k are their k/d-th
// powers). When Newton on P^d does not get there but every phase of the
// orbit repeats every d revolutions (repeating_every), it is reported at
// period d too.
Orbit at_minimal_period(Shooter& shooter, Orbit orbit, const PeriodicOptions& options, std::vector<NewtonStep>& trace) {
  const double near = kNearTolerances * options.tolerance;
  for (int d = 1; d < orbit.period; ++d) {
    if (orbit.period % d != 0) continue;
    long impacts = 0;
    const std::optional<SectionPoint> image = image_near(shooter, orbit.fixed_point, d, near, &impacts);
    if (!image) continue;
    std::optional<Orbit> minimal = shoot(shooter, orbit.fixed_point, d, options, trace);
    if (!minimal || shooter.scaled_norm(to_vector(minimal->fixed_point.x) - to_vector(orbit.fixed_point.x)) > near)
      minimal = repeating_every(shooter, orbit, d, near, *image, impacts);
    if (!minimal) continue;
    shooter.log(printf_format("period %d: the orbit repeats every %d revolution%s: reported at period %d", orbit.period,
                              d, d == 1 ? "" : "s", d));
    return *minimal;
  }
  return orbit;
}

// Whether `orbit` is one already found (a fixed point of a period dividing its own).
bool known(const Shooter& shooter, const Orbit& orbit, const std::vector<Orbit>& found, double tolerance) {
  for (const Orbit& o : found) {
    if (orbit.period % o.period != 0) continue;
    const double d = shooter.scaled_norm(to_vector(orbit.fixed_point.x) - to_vector(o.fixed_point.x));
    if (d < kNearTolerances * tolerance) return true;
  }
  return false;
}

// Whether P^d returns x within kNearTolerances shooting tolerances for a
// divisor d < k of k: x is near an orbit of the shorter period d (as in
// at_minimal_period).
bool of_shorter_period(Shooter& shooter, const SectionPoint& x, int k, const PeriodicOptions& options) {
  for (int d = 1; d < k; ++d)
    if (k % d == 0 && image_near(shooter, x, d, kNearTolerances * options.tolerance)) return true;
  return false;
}

// The k section points of a period-k orbit, its fixed point first; empty
// when a run failed.
std::vector<VectorXd> shot_orbit_phases(Shooter& shooter, const Orbit& orbit) {
  std::vector<VectorXd> phases{to_vector(orbit.fixed_point.x)};
  SectionPoint p = orbit.fixed_point;
  for (int j = 1; j < orbit.period; ++j) {
    const std::optional<SectionPoint> next = shooter.apply(p, 1);
    if (!next) return {};
    p = *next;
    phases.push_back(to_vector(p.x));
  }
  return phases;
}

// Whether x lies within kNearTolerances shooting tolerances of one of `phases`.
bool near_a_phase(const Shooter& shooter, const VectorXd& x, const std::vector<VectorXd>& phases,
                  const PeriodicOptions& options) {
  return std::ranges::any_of(phases, [&](const VectorXd& phase) {
    return shooter.scaled_norm(x - phase) <= kNearTolerances * options.tolerance;
  });
}

// Periods in a row over which a motion that follows an orbit's
// linearisation (kLinearAgreement) is taken to be in its basin.
constexpr int kLinearPeriods = 3;
// A period's error e' from the orbit's fixed point agrees with the
// linearisation when |e' − M e| ≤ kLinearAgreement |e| (M the monodromy,
// scaled max norms): the motion then contracts as the multipliers say.
constexpr double kLinearAgreement = 0.1;

// Whether the motion went from `before` to `now` over one period as the
// orbit's linearisation about its fixed point x0 says, closer than it was.
bool follows_linearisation(const Shooter& shooter, const Orbit& orbit, const VectorXd& x0, const VectorXd& before,
                           const VectorXd& now) {
  const VectorXd e = before - x0, e_next = now - x0;
  const double size = shooter.scaled_norm(e);
  return shooter.scaled_norm(e_next) < size &&
         shooter.scaled_norm(e_next - orbit.monodromy * e) <= kLinearAgreement * size;
}

// The revolutions the motion from `start` takes to reach `orbit` (0 when it
// starts there): to come within kNearTolerances shooting tolerances of one
// of its phases, or to follow its linearisation about the fixed point for
// kLinearPeriods periods in a row (a slowly contracting orbit, |μ| near 1,
// is reached long before it is near). nullopt when it does not within
// options.reach_revolutions, or a run failed. Newton's iterates are not the
// motion: its steps may cross into the basin of another attractor than the
// one the motion goes to (docs/periodic.md "Reached orbits").
std::optional<long> revolutions_to_reach(Shooter& shooter, const SectionPoint& start, const Orbit& orbit,
                                         const PeriodicOptions& options) {
  const std::vector<VectorXd> phases = shot_orbit_phases(shooter, orbit);
  if (phases.empty()) return std::nullopt;
  const std::size_t k = phases.size();
  const bool linearised = orbit.monodromy.rows() == std::ssize(start.x) && orbit.monodromy.allFinite();
  std::vector<VectorXd> motion;  // the section point of every revolution so far
  int agreeing = 0;              // periods in a row that followed the linearisation
  SectionPoint x = start;
  for (long m = 0;; ++m) {
    motion.push_back(to_vector(x.x));
    if (near_a_phase(shooter, motion.back(), phases, options)) return m;
    if (linearised && motion.size() > k) {
      const VectorXd& before = motion[motion.size() - 1 - k];
      // Only a period that starts nearest the fixed point (the monodromy's phase) is tested.
      const auto nearest = std::ranges::min_element(
          phases, {}, [&](const VectorXd& phase) { return shooter.scaled_norm(before - phase); });
      if (nearest == phases.begin()) {
        agreeing = follows_linearisation(shooter, orbit, phases.front(), before, motion.back()) ? agreeing + 1 : 0;
        if (agreeing >= kLinearPeriods) return m;
      }
    }
    if (m >= options.reach_revolutions) return std::nullopt;
    const std::optional<SectionPoint> next = shooter.apply(x, 1);
    if (!next) return std::nullopt;
    x = *next;
  }
}

// The smallest period d ≤ options.max_period with which the last sampled
// states repeat (every |x_n − x_{n−d}| within the shooting tolerance over the
// last 2d + 2 samples), and in `since` the first sample from which they do;
// 0 when they do not.
int recurrence_period(const Shooter& shooter, const std::vector<VectorXd>& x, const PeriodicOptions& options,
                      std::size_t& since) {
  const std::size_t n = x.size();
  for (int d = 1; d <= options.max_period; ++d) {
    const std::size_t du = static_cast<std::size_t>(d);
    if (n < 3 * du + 2) break;
    auto repeats = [&](std::size_t i) { return shooter.scaled_norm(x[i] - x[i - du]) <= options.tolerance; };
    bool holds = true;
    for (std::size_t i = n - 2 * du - 2; i < n && holds; ++i) holds = repeats(i);
    if (!holds) continue;
    since = n - 2 * du - 2;
    while (since > du && repeats(since - 1)) --since;
    since -= du;
    return d;
  }
  return 0;
}

// Follows the motion from the last of `points` (the section points so far,
// once a revolution), up to options.settle_revolutions in all, until the
// sampled states repeat; then shoots the orbit from there at that period and
// keeps it when it is stable (at its minimal period).
void settle_and_shoot(const PoincareMap& map, const std::vector<std::vector<double>>& points, SectionPoint last,
                      const PeriodicOptions& options, PeriodicAnalysis& a) {
  Shooter shooter(map, options);
  std::vector<VectorXd> x;
  for (const std::vector<double>& p : points) x.push_back(to_vector(p));
  std::size_t since = 0;
  int d = recurrence_period(shooter, x, options, since);
  while (d == 0 && std::ssize(x) < options.settle_revolutions) {
    const std::optional<SectionPoint> next = shooter.apply(last, 1);
    if (!next) break;
    last = *next;
    x.push_back(to_vector(last.x));
    d = recurrence_period(shooter, x, options, since);
  }
  if (d == 0) {
    a.revolutions += shooter.revolutions();
    return;
  }
  const auto count_jacobians = [&] {
    a.sensitivity_jacobians += shooter.sensitivity_jacobians();
    a.finite_difference_jacobians += shooter.finite_difference_jacobians();
    if (!shooter.fallback().empty()) a.jacobian_fallback = shooter.fallback();
  };
  shooter.log(
      printf_format("the motion settled after %zu revolutions and repeats every %d: shooting from there", since, d));
  std::optional<Orbit> orbit = shoot(shooter, last, d, options, a.newton);
  if (orbit) orbit = at_minimal_period(shooter, std::move(*orbit), options, a.newton);
  if (orbit && orbit->stable && !a.unreached_orbits.empty()) {
    // The motion went there: an orbit found unreached before (within
    // reach_revolutions) is this one, reached later.
    const std::vector<VectorXd> phases = shot_orbit_phases(shooter, *orbit);
    std::erase_if(a.unreached_orbits, [&](const Orbit& u) {
      return u.period == orbit->period && near_a_phase(shooter, to_vector(u.fixed_point.x), phases, options);
    });
  }
  a.revolutions += shooter.revolutions();
  count_jacobians();
  if (!orbit || !orbit->stable) return;
  a.orbit = std::move(*orbit);
  a.motion = MotionKind::periodic;
  a.settled_after = static_cast<long>(since);
}

}  // namespace

std::vector<std::complex<double>> floquet_multipliers(const MatrixXd& monodromy) {
  const Eigen::EigenSolver<MatrixXd> solver(monodromy, false);
  if (solver.info() != Eigen::Success) throw NumericalError("the Floquet multipliers did not converge");
  std::vector<std::complex<double>> mu(solver.eigenvalues().begin(), solver.eigenvalues().end());
  std::stable_sort(mu.begin(), mu.end(), [](const auto& a, const auto& b) { return std::abs(a) > std::abs(b); });
  return mu;
}

PeriodicAnalysis find_periodic_orbit(const PoincareMap& map, const SectionPoint& start,
                                     const PeriodicOptions& options) {
  Shooter shooter(map, options);
  PeriodicAnalysis a;
  a.transient_end = start;
  std::vector<Orbit> found;
  SectionPoint from = start;
  bool moved_on = false;  // the start was moved once already
  for (int k = std::max(1, options.min_period); k <= options.max_period && !a.orbit; ++k) {
    SectionPoint unstable_near;
    std::optional<Orbit> orbit = shoot(shooter, from, k, options, a.newton, &unstable_near);
    if (orbit) orbit = at_minimal_period(shooter, std::move(*orbit), options, a.newton);
    // Newton went back to a repelling orbit found before (or, stopped near a
    // clearly unstable orbit, to one of a shorter period): the start is still
    // near it. Follow the motion further, away from it, and try k again.
    const bool returned =
        !moved_on && (orbit ? known(shooter, *orbit, found, options.tolerance)
                            : !unstable_near.x.empty() && of_shorter_period(shooter, unstable_near, k, options));
    if (returned) {
      const int revolutions = 4 * options.transient_revolutions;
      shooter.log(printf_format("period %d: %s; following the motion %d more revolutions and trying again", k,
                                orbit ? "converged to the orbit found before" : "near an orbit of a shorter period",
                                revolutions));
      moved_on = true;
      if (std::optional<SectionPoint> later = shooter.apply(from, revolutions)) from = *later;
      --k;
      continue;
    }
    if (!orbit || known(shooter, *orbit, found, options.tolerance)) continue;
    found.push_back(*orbit);
    shooter.log(printf_format("period %d: orbit found, largest |multiplier| %.4g: %s", k, orbit->spectral_radius(),
                              orbit->stable ? "stable" : "unstable"));
    if (orbit->stable && options.reach_revolutions > 0) {
      const std::optional<long> reached = revolutions_to_reach(shooter, start, *orbit, options);
      if (!reached) {
        shooter.log(
            printf_format("period %d: the motion from the start does not come near this orbit in %d revolutions: "
                          "it coexists with the motion, which goes elsewhere",
                          k, options.reach_revolutions));
        a.unreached_orbits.push_back(std::move(*orbit));
        continue;
      }
      a.reached_after = *reached;
    }
    if (orbit->stable) {
      a.orbit = std::move(orbit);
      a.motion = MotionKind::periodic;
    } else {
      a.unstable_orbits.push_back(std::move(*orbit));
    }
  }
  a.revolutions = shooter.revolutions();
  a.map_evaluations = shooter.evaluations();
  a.sensitivity_jacobians = shooter.sensitivity_jacobians();
  a.finite_difference_jacobians = shooter.finite_difference_jacobians();
  a.jacobian_fallback = shooter.fallback();
  a.failure = shooter.failure();
  return a;
}

namespace {

// λ + 2 standard errors below 0: the motion contracts (with a standard
// error, beyond doubt; without one, by λ alone).
bool contracts_beyond_doubt(const LyapunovEstimate& e) {
  return e.per_revolution + 2.0 * e.standard_error.value_or(0.0) < 0.0;
}

}  // namespace

MotionKind lyapunov_class(const LyapunovEstimate& e, double chaos_threshold) {
  const double lambda = e.per_revolution, margin = 2.0 * e.standard_error.value_or(0.0);
  if (lambda - margin > chaos_threshold) return MotionKind::chaotic;
  // A motion contracting beyond doubt (a stable orbit not yet reached, its
  // multiplier just inside the unit circle) is not a torus, however small λ.
  const bool contracting = e.standard_error && contracts_beyond_doubt(e);
  if (!contracting && e.samples_recur && lambda + margin <= chaos_threshold && lambda - margin > -chaos_threshold)
    return MotionKind::quasi_periodic;
  return MotionKind::unresolved;
}

UnresolvedReason unresolved_reason(const LyapunovEstimate& e) {
  if (contracts_beyond_doubt(e)) return UnresolvedReason::contracts;
  return e.samples_recur ? UnresolvedReason::straddles : UnresolvedReason::drifts;
}

namespace {

// Classifies the motion by a.lyapunov (set), then looks for it settling
// (settle_and_shoot): a motion that does not clearly expand is followed up to
// options.settle_revolutions; one that expanded over the Lyapunov run (it
// may be transient chaos) up to options.reach_revolutions, the horizon
// within which a stable orbit counts as reached.
void classify_and_settle(const PoincareMap& map, const PeriodicOptions& options, PeriodicAnalysis& a) {
  a.motion = lyapunov_class(*a.lyapunov, options.chaos_threshold);
  if (a.lyapunov->section_points.empty()) return;
  PeriodicOptions settle = options;
  if (a.motion == MotionKind::chaotic)
    settle.settle_revolutions = std::max(options.reach_revolutions, options.lyapunov_revolutions);
  settle_and_shoot(map, a.lyapunov->section_points, a.lyapunov->last, settle, a);
}

}  // namespace

PeriodicAnalysis analyse_from(const PoincareMap& map, const SectionPoint& start, const PeriodicOptions& options) {
  std::optional<PeriodicAnalysis> first;  // the Lyapunov run made first, when it found no chaos
  if (options.lyapunov_first && options.lyapunov_revolutions > 0) {
    if (options.log)
      options.log(printf_format("Lyapunov exponent first, over %d revolutions: the motion is expected aperiodic",
                                options.lyapunov_revolutions));
    PeriodicAnalysis l;
    l.transient_end = start;
    l.lyapunov = estimate_lyapunov(map, start, options, &l.revolutions);
    if (lyapunov_class(*l.lyapunov, options.chaos_threshold) == MotionKind::chaotic) {
      classify_and_settle(map, options, l);
      return l;
    }
    first = std::move(l);
  }
  PeriodicAnalysis a = find_periodic_orbit(map, start, options);
  if (first) a.revolutions += first->revolutions;
  if (a.orbit || options.lyapunov_revolutions <= 0) return a;
  if (first) {
    a.lyapunov = std::move(first->lyapunov);
  } else {
    if (options.log)
      options.log(printf_format("no stable orbit up to period %d: estimating the Lyapunov exponent over %d revolutions",
                                options.max_period, options.lyapunov_revolutions));
    a.lyapunov = estimate_lyapunov(map, start, options, &a.revolutions);
  }
  classify_and_settle(map, options, a);
  return a;
}

PeriodicAnalysis analyse_steady_state(const PoincareMap& map, const PeriodicOptions& options) {
  Workspace ws = make_workspace(map.model());
  SimulationOptions run;
  run.record_series = false;
  run.step_metrics = false;
  run.quadratures = false;  // the transient's end state is all it gives
  const SimulationResult transient = simulate(map.scene_for(options.transient_revolutions), map.model(), ws, run);
  throw_if_failed(transient);
  if (options.log) options.log(printf_format("transient: %d revolutions", options.transient_revolutions));
  PeriodicAnalysis a = analyse_from(map, map.point(transient), options);
  a.revolutions += options.transient_revolutions;
  return a;
}

}  // namespace camdyn
