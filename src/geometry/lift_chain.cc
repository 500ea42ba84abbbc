#include "geometry/lift_chain.h"

#include <algorithm>

namespace camdyn {

double LiftStep::carry(double previous) const {
  const double s = ratio * previous - lash;
  return seat ? std::max(s, *seat) : s;
}

bool LiftStep::lifted(double previous) const { return !seat || ratio * previous - lash > *seat; }

double LiftChain::at(double s) const {
  for (const LiftStep& step : steps) s = step.carry(s);
  return s;
}

double LiftChain::slope(double s) const {
  double slope = 1.0;
  for (const LiftStep& step : steps) {
    if (!step.lifted(s)) return 0.0;
    slope *= step.ratio;
    s = step.carry(s);
  }
  return slope;
}

double LiftChain::datum(double min_s) const {
  if (!steps.empty() && steps.back().seat) return *steps.back().seat;
  return at(min_s);
}

}  // namespace camdyn
