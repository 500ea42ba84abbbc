// Output files of the `identify` study (docs/config.md, "identify"): identified.json (the
// estimates with standard errors, correlation, identifiability verdict and
// solver summary), fit.csv (measured and fitted signals at the record's times),
// identified_scene.json (a `simulate` config with the identified values, which
// `camdyn run` accepts as it is) and report.html. All written atomically;
// undefined numbers (a standard error the data do not determine) are null.
#pragma once

#include <filesystem>

#include "io/config.h"
#include "optim/identify/identify.h"
#include "output/report.h"

namespace camdyn::optim {

/// identified.json; `resolved_config` is the study's resolved config.
Json identified_json(const IdentifyProblem& problem, const IdentifyResult& result, const Json& resolved_config);

/// identified_scene.json: the study's scene with the identified values, as a simulate config.
Json identified_scene_json(const IdentifyProblem& problem, const IdentifyResult& result);

/// The report page: parameter table with uncertainties, measured against
/// fitted signals, residuals, the identified scene's cam (output/cam_plots.h).
Report identify_report(const IdentifyProblem& problem, const IdentifyResult& result);

/// Writes the four files into `out_dir` (created if missing).
void write_identify_outputs(const std::filesystem::path& out_dir, const IdentifyProblem& problem,
                            const IdentifyResult& result, const Json& resolved_config);

}  // namespace camdyn::optim
