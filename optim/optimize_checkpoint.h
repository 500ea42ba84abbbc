// What an optimize run keeps on disk while it runs, so that a run killed
// part-way (even by SIGKILL) loses nothing: history.csv rewritten as it goes,
// best_design.json (a `simulate` config of the best design so far) and
// checkpoint.json (that design's vector and the study it belongs to). Every
// file is replaced atomically, so whatever is on disk parses. A re-run of the
// same study into the same folder starts its search from the checkpoint;
// a run that completes removes checkpoint.json (result.json is its record).
#pragma once

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "optim/optimize.h"

namespace camdyn::optim {

class CheckpointWriter {
 public:
  /// Writes nothing when `dir` is empty. `top_rpm` and `name` make the
  /// best design's `simulate` config as optimized.json will be.
  CheckpointWriter(std::filesystem::path dir, const OptimizeStudyConfig& config, std::string name, double top_rpm,
                   std::string file);

  /// After each evaluation of the search: history.csv at most every
  /// `min_interval` (and always when the best design changed), with the
  /// best design and the checkpoint when it changed.
  void evaluated(const OptimizeOutcome& out, const DesignSpace& space, const std::vector<double>& x,
                 const DesignEvaluation& e, bool best_changed);

  std::chrono::duration<double> min_interval{0.5};

 private:
  std::filesystem::path dir_;
  Json study_;  ///< the study fields, to recognise the study on a re-run
  std::string name_, file_;
  double top_rpm_ = 0.0;
  std::chrono::steady_clock::time_point last_write_{};
};

/// The run's outputs are written: checkpoint.json and best_design.json in
/// `dir` are removed.
void remove_checkpoint(const std::filesystem::path& dir);

/// The best design vector of an earlier, killed run of the same study in
/// `dir` (same study fields, `dimension` variables), if there is one.
std::optional<std::vector<double>> read_checkpoint(const std::filesystem::path& dir, const OptimizeStudyConfig& config,
                                                   int dimension);

}  // namespace camdyn::optim
