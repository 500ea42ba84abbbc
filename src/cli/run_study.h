// Running one study config, as `camdyn run` and `camdyn validate` do: read
// the config (a file with `extends` and `--set` overrides, or JSON text),
// dispatch on its `study` to the study's runner, which writes its outputs.
// The CLI and the Python module (python/) both call this, so a study gives
// the same outputs from either. Plain standard types only, so the module
// needs none of the private headers.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace camdyn {

struct StudyRequest {
  std::string config_file;             ///< the config file; empty when json_text is given
  std::string json_text;               ///< a config's JSON text (no `extends`) instead of a file
  std::string base_dir;                ///< where json_text's relative file names resolve (empty: the current directory)
  std::vector<std::string> overrides;  ///< "dotted.path=VALUE", as --set takes them
  std::string out_dir;                 ///< output folder; empty: out/<name>
  int jobs = 0;                        ///< parallel jobs; 0 = one per core
  bool progress = false;               ///< draw progress on stderr
  bool validate_only = false;          ///< check, print the resolved config, do not run
  bool strict = false;                 ///< a run with plausibility warnings exits 3 (docs/warnings.md)
  /// Print the study's summary on stdout (the lines that name its report).
  /// Off for a caller that deletes the output folder afterwards (the Python
  /// module's run_study without `out`): a path to a folder that is gone
  /// would mislead.
  bool summary = true;
  double max_study_time_s = 86400.0;  ///< the whole study's wall-time budget [s] (common/study_budget.h)
  double max_memory_mb = 2048.0;      ///< the memory budget [MB] (common/study_budget.h)
};

struct StudyOutcome {
  int exit_code = 0;  ///< 0, or the code a study stopped with before its runs (MPI)
  std::string study;  ///< the config's `study` (one of the registry's, scene/study_kind.h)
  std::filesystem::path out_dir;
  /// The study's main result in out_dir (summary.json for simulate,
  /// result.json for optimize, ...: its registry entry's main_output).
  std::filesystem::path main_output;
};

/// The file name of a study's main result (StudyOutcome::main_output);
/// summary.json for a word the registry does not know (it runs as simulate,
/// whose loader refuses it).
std::string main_output_name(const std::string& study);

/// Reads the config and runs its study. Throws InputError (naming the file
/// when the error came from below the config layer and did not) and
/// NumericalError, as the study runners do.
StudyOutcome run_study(const StudyRequest& request);

}  // namespace camdyn
