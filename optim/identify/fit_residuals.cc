#include "optim/identify/fit_residuals.h"

#include <algorithm>
#include <cassert>

namespace camdyn::optim {

void smooth(const std::vector<double>& t, double* d, double width, std::vector<double>& prefix) {
  const std::size_t n = t.size();
  assert(prefix.size() >= n + 1);
  for (int pass = 0; pass < 2; ++pass) {
    prefix[0] = 0.0;
    for (std::size_t i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + d[i];
    std::size_t lo = 0, hi = 0;
    for (std::size_t i = 0; i < n; ++i) {
      while (t[lo] < t[i] - 0.5 * width) ++lo;
      while (hi + 1 < n && t[hi + 1] <= t[i] + 0.5 * width) ++hi;
      d[i] = (prefix[hi + 1] - prefix[lo]) / static_cast<double>(hi - lo + 1);
    }
  }
}

ResidualAssembler::ResidualAssembler(const IdentifyProblem& problem) : problem_(problem) {
  std::size_t longest = 0;
  for (const FitExperiment& e : problem.experiments) longest = std::max(longest, e.record.time.size());
  prefix_.assign(longest + 1, 0.0);
}

void ResidualAssembler::assemble(const std::vector<FitRun>& runs, double smoothing, double* r) {
  std::size_t row = 0;
  for (std::size_t k = 0; k < problem_.experiments.size(); ++k) {
    const MeasuredRecord& rec = problem_.experiments[k].record;
    for (std::size_t s = 0; s < rec.signals.size(); ++s) {
      const std::vector<double>& sim = runs[k].signals[s];
      double* group = r + row;
      for (std::size_t i = 0; i < rec.time.size(); ++i) r[row++] = rec.weights[s] * (sim[i] - rec.values[s][i]);
      if (smoothing > 0.0) smooth(rec.time, group, smoothing, prefix_);
    }
  }
}

}  // namespace camdyn::optim
