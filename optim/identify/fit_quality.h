// Whether a fit reproduces its records to their noise (docs/config.md
// `identify`): per signal, the ratio of the misfit's variance to the noise
// variance estimated from the record, against the critical value of the F
// test at the 0.1 % level for that many samples (both variances have about N
// degrees of freedom), and never below 1.5, which leaves room for the bias of
// the noise estimate and the integrator's error. A fit above it is poor: the
// model cannot reproduce the record there, most often because the solver
// stopped in a local minimum.
#pragma once

#include <string>
#include <vector>

#include "optim/identify/identify.h"

namespace camdyn::optim {

struct FitQuality {
  bool poor = false;
  double worst_ratio = 0.0;  ///< the largest (RMS misfit / noise)² over the signals [-]
  double critical = 0.0;     ///< its critical value [-]
  std::string where;         ///< "experiment 'h005', contact_force"
};

/// The critical variance ratio for N samples [-].
double critical_variance_ratio(std::size_t samples);

/// The quality of the fits at an optimum (signals without a noise estimate are left out).
FitQuality assess_fit(const std::vector<ExperimentFit>& fits);

}  // namespace camdyn::optim
