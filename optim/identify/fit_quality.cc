#include "optim/identify/fit_quality.h"

#include <algorithm>
#include <cmath>

namespace camdyn::optim {

double critical_variance_ratio(std::size_t samples) {
  // ln F is about normal with variance 2/ν₁ + 2/ν₂ (ν₁ = ν₂ = N); z = 3.09 at 0.1 %.
  constexpr double kZ = 3.09, kFloor = 1.5;
  const double n = std::max<double>(2.0, static_cast<double>(samples));
  return std::max(kFloor, std::exp(kZ * std::sqrt(4.0 / n)));
}

FitQuality assess_fit(const std::vector<ExperimentFit>& fits) {
  FitQuality q;
  double worst_excess = 0.0;  // ratio / critical of the worst signal
  for (const ExperimentFit& fit : fits)
    for (std::size_t s = 0; s < fit.signals.size(); ++s) {
      if (!(fit.noise[s] > 0.0) || !std::isfinite(fit.rms_error[s])) continue;
      const double ratio = std::pow(fit.rms_error[s] / fit.noise[s], 2);
      const double critical = critical_variance_ratio(fit.time.size());
      if (ratio / critical <= worst_excess && !q.where.empty()) continue;
      worst_excess = ratio / critical;
      q.worst_ratio = ratio;
      q.critical = critical;
      q.where = "experiment '" + fit.name + "', " + fit.signals[s];
    }
  q.poor = worst_excess > 1.0;
  return q;
}

}  // namespace camdyn::optim
