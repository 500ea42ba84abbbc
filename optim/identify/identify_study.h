// The `identify` study (docs/config.md, "identify"): Ceres fits contact parameters to
// measured records.
#pragma once

#include "io/config.h"
#include "study/study.h"

namespace camdyn::optim {

/// Runs (or, with ctx.validate_only, checks) an identify study; returns the exit code.
int run_identify_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn::optim
