// Outputs of a convergence study: work_precision.csv (one row per run),
// report.html (work-precision plots per scene, the cam and the table of runs)
// and the resolved config.json.
#pragma once

#include <filesystem>
#include <string>

#include "study/convergence.h"
#include "study/convergence_config.h"

namespace camdyn {

/// Writes work_precision.csv, report.html and config.json into out_dir;
/// returns the wall time [s] from result.started to the report.
/// `config_file` names the study's config in messages.
double write_convergence_outputs(const std::filesystem::path& out_dir, const ConvergenceStudy& study,
                                 const ConvergenceResult& result, const std::string& config_file);

}  // namespace camdyn
