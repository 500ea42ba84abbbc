// report.html of an optimize study: the baseline against the optimised design
// (the optimised cam to scale with the baseline's contour, pressure angle and
// radius of curvature with the constraints' limits, lift, velocity,
// acceleration and jerk against cam angle, output/cam_plots.h; contact force and
// gap against cam angle at each operating speed), the convergence history and
// tables of constraints with their margins, objective terms, metrics per speed,
// segment coefficients, starts and design variables.
#pragma once

#include <string>

#include "optim/optimize/optimize.h"
#include "output/report.h"

namespace camdyn::optim {

Report optimize_report(const OptimizeOutcome& outcome, const std::string& name);

}  // namespace camdyn::optim
