// The files an optimize study writes (docs/config.md, section `optimize`):
// result.json, history.csv, optimized.json and report.html, each atomically
// and without NaN.
#pragma once

#include <filesystem>
#include <string>

#include "io/config.h"
#include "optim/optimize/optimize.h"

namespace camdyn::optim {

/// result.json: `baseline` and `optimized` (each with `metrics` per operating
/// speed, `objective`, `constraints` with value, limit, margin and `holds`,
/// kinematics, geometry and the motion law), `evaluations`, `run_time_s`,
/// `algorithm`, `stop_reason`, the starts and the design variables. `file`
/// names the config in messages.
Json result_json(const OptimizeOutcome& outcome, const std::string& name, const std::string& file);

/// optimized.json: the complete `simulate` config of the optimised design at
/// the top operating speed, as `camdyn run` accepts it.
Json optimized_config_json(const OptimizeOutcome& outcome, const std::string& config_file);

/// Writes history.csv: `evaluation, objective, <each constraint>, feasible`,
/// then `start, kind, valid, best_objective, error`. Constraint cells of an
/// invalid design are empty (there is no value to report).
void write_history_csv(const std::filesystem::path& path, const OptimizeOutcome& outcome);

/// Writes all four files into `dir` (created if missing).
void write_optimize_outputs(const std::filesystem::path& dir, const OptimizeOutcome& outcome, const std::string& name,
                            const std::string& config_file);

}  // namespace camdyn::optim
