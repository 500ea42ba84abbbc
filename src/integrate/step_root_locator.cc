#include "integrate/step_root_locator.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace camdyn {

StepRootLocator::StepRootLocator(OdeSystem& system, int state_size)
    : system_(system),
      roots_(system.root_count()),
      g_start_(roots_, 0.0),
      g_end_(roots_, 0.0),
      g_probe_(roots_, 0.0),
      state_(state_size, 0.0),
      directions_(roots_, 0) {}

void StepRootLocator::restart(double t, const double* y) {
  if (roots_ > 0) system_.roots(t, y, g_start_.data());
  restarted_ = true;
}

void StepRootLocator::roots_at(const Integrator& integrator, double t, std::vector<double>& g) {
  integrator.dense(t, state_.data());
  system_.roots(t, state_.data(), g.data());
}

double StepRootLocator::earliest_root(const Integrator& integrator, double t0, double t1) {
  const double tolerance = 100.0 * std::numeric_limits<double>::epsilon() * (std::abs(t1) + std::abs(t1 - t0));
  double earliest = t1 + 1.0;
  for (int k = 0; k < roots_; ++k) {
    if ((g_start_[k] > 0.0) == (g_end_[k] > 0.0) || g_start_[k] == 0.0) continue;
    double lo = t0, hi = t1, g_lo = g_start_[k], g_hi = g_end_[k];
    int kept = 0;  // −1: lo was kept at the last probe, +1: hi
    for (int it = 0; it < 200 && hi - lo > tolerance; ++it) {
      double t = hi - g_hi * (hi - lo) / (g_hi - g_lo);
      if (!(t > lo + 0.25 * tolerance && t < hi - 0.25 * tolerance)) t = 0.5 * (lo + hi);
      roots_at(integrator, t, g_probe_);
      if ((g_probe_[k] > 0.0) == (g_start_[k] > 0.0)) {
        lo = t;
        g_lo = g_probe_[k];
        if (kept == -1) g_hi *= 0.5;
        kept = -1;
      } else {
        hi = t;
        g_hi = g_probe_[k];
        if (kept == +1) g_lo *= 0.5;
        kept = +1;
      }
    }
    earliest = std::min(earliest, hi);
  }
  return earliest;
}

bool StepRootLocator::locate(const Integrator& integrator, double t0, double t1, const double* y1, double& t_root) {
  if (roots_ == 0) return false;
  if (restarted_) roots_at(integrator, t0 + 1e-9 * (t1 - t0), g_start_);
  system_.roots(t1, y1, g_end_.data());
  const double t = earliest_root(integrator, t0, t1);
  if (t > t1) {
    g_start_ = g_end_;
    restarted_ = false;
    return false;
  }
  roots_at(integrator, t, g_probe_);
  for (int k = 0; k < roots_; ++k)
    directions_[k] = (g_probe_[k] > 0.0) != (g_start_[k] > 0.0) ? (g_start_[k] > 0.0 ? -1 : +1) : 0;
  g_start_ = g_probe_;
  restarted_ = true;
  t_root = t;
  return true;
}

void StepRootLocator::directions(int* out) const { std::copy(directions_.begin(), directions_.end(), out); }

}  // namespace camdyn
