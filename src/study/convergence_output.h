// Outputs of a convergence study: work_precision.csv (one row per run),
// report.html (work-precision plots per scene and the table of runs) and the
// resolved config.json.
#pragma once

#include <filesystem>

#include "study/convergence.h"
#include "study/convergence_config.h"

namespace camdyn {

/// Writes work_precision.csv, report.html and config.json into out_dir;
/// returns the wall time [s] from result.started to the report.
double write_convergence_outputs(const std::filesystem::path& out_dir, const ConvergenceStudy& study,
                                 const ConvergenceResult& result);

}  // namespace camdyn
