// The `simulate` study: one run of the scene. Its config is the scene itself
// (io/config.h), the run is dynamics/simulation.h's simulate() with the error
// estimate and the steady-state search, and its outputs are
// study/simulation_output.h's summary.json, the time series and report.html,
// plus the cam profile files when `outputs.profile` asks for them. `camdyn
// validate` prints the resolved scene and the design check instead.
#pragma once

#include "io/json_archive.h"
#include "study/study.h"

namespace camdyn {

/// Runs (or, with ctx.validate_only, checks) the scene and writes its outputs;
/// returns the exit code: 0, or 3 under ctx.strict when the run's results
/// carry plausibility warnings (docs/warnings.md).
int run_simulate_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
