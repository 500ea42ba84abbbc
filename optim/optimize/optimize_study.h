// The `optimize` study (docs/optimize.md): NLopt shapes the spline cam so that
// the follower neither jumps nor hammers over its operating speeds.
#pragma once

#include "io/config.h"
#include "study/study.h"

namespace camdyn::optim {

/// Runs (or, with ctx.validate_only, checks) an optimize study; returns the exit code.
int run_optimize_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn::optim
