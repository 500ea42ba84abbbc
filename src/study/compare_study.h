// The `compare` study (docs/config.md, "compare"): every case at every grid point
// (cartesian product of `grid`, paired lists of `zip`), each a simulate run;
// a failed run is recorded with its status and error and never stops the
// others. Outputs comparison.csv, comparison.json and report.html.
#pragma once

#include "io/config.h"
#include "study/study.h"

namespace camdyn {

/// Runs (or, with ctx.validate_only, checks) a compare study; returns the exit code.
int run_compare_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
