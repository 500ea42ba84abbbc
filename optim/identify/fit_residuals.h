// The weighted residuals of an identification: simulated minus measured
// signals times the signal weights, in the order (experiment, signal, sample),
// optionally smoothed for the continuation stages. Assembled without heap
// allocation (the scratch is sized once), as often as the solver asks.
#pragma once

#include <vector>

#include "optim/identify/fit_scene.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {

/// Moving average of d over the samples within ±width/2 [s] of each sample
/// time t [s], applied twice (a triangular kernel, so the result has a
/// continuous derivative in a time shift). `prefix`: scratch of at least
/// t.size() + 1 values.
void smooth(const std::vector<double>& t, double* d, double width, std::vector<double>& prefix);

class ResidualAssembler {
 public:
  explicit ResidualAssembler(const IdentifyProblem& problem);

  /// r[0, problem.residual_count()): the weighted residuals of runs[k]
  /// (experiment k), smoothed over `smoothing` [s] when > 0. Allocates nothing.
  void assemble(const std::vector<FitRun>& runs, double smoothing, double* r);

 private:
  const IdentifyProblem& problem_;
  std::vector<double> prefix_;
};

}  // namespace camdyn::optim
