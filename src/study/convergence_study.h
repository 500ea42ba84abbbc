// The `convergence` study (docs/config.md, "convergence"): error against run time for each
// integration method, tracking mode and tolerance, against a tight reference.
#pragma once

#include "io/config.h"
#include "study/study.h"

namespace camdyn {

/// Runs (or, with ctx.validate_only, checks) a convergence study; returns the exit code.
int run_convergence_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
