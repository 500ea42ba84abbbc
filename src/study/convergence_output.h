// Outputs of a convergence study: work_precision.csv (one row per run),
// report.html (work-precision plots per scene, the cam and the table of runs)
// and the resolved config.json.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "output/report.h"
#include "study/convergence.h"
#include "study/convergence_config.h"

namespace camdyn {

/// report.html: the reference, run counts and wall time [s], the
/// work-precision plots of each scene (the position error in the unit of its
/// follower coordinate: m, or rad for an arm), the cam of the first scene and
/// the table of runs; `file` names the study's config in messages.
Report convergence_report(const ConvergenceStudy& study, const std::vector<ConvergenceRun>& runs, long failed,
                          double wall, const std::string& file, const std::vector<std::string>& reference_missing = {});

/// Writes work_precision.csv, report.html and config.json into out_dir;
/// returns the wall time [s] from result.started to the report.
/// `config_file` names the study's config in messages.
double write_convergence_outputs(const std::filesystem::path& out_dir, const ConvergenceStudy& study,
                                 const ConvergenceResult& result, const std::string& config_file);

}  // namespace camdyn
