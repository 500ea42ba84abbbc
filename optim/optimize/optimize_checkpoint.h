// What an optimize run keeps on disk while its search loop runs, so that a
// run killed part-way (even by SIGKILL) loses nothing: the journal of every
// evaluation (optim/optimize/optimize_journal.h), history.csv rewritten as it goes
// and best_design.json (a `simulate` config of the best design so far).
// Every file is replaced atomically or appended and fsynced, so whatever is
// on disk parses. A re-run of the same study into the same folder replays
// the journal and ends with the uninterrupted run's result; a run that
// completes removes best_design.json (optimized.json is its record) and
// keeps the journal.
#pragma once

#include <chrono>
#include <cstddef>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "optim/optimize/optimize.h"
#include "optim/optimize/optimize_journal.h"

namespace camdyn::optim {

class LoopRecorder {
 public:
  /// Records nothing when `dir` is empty. Opens the journal of the study
  /// (baseline and config; `constraints` constraints) in `dir`: InputError
  /// when the folder holds another study's journal.
  LoopRecorder(std::filesystem::path dir, const SceneConfig& baseline, const OptimizeStudyConfig& config,
               const DesignSpace& space, std::size_t constraints, std::string file);

  /// Fills e from the journal when it has design x (asked by `start`:
  /// journals of warm-started searches are per start) and counts its
  /// simulations; false otherwise.
  bool replay(const std::vector<double>& x, int start, DesignEvaluation& e);
  /// Journals the evaluation of x by `start`, which took `simulations` simulations.
  void journal(const std::vector<double>& x, int start, const DesignEvaluation& e, long simulations);
  /// After each evaluation of the search: history.csv at most every
  /// `min_interval` (and always when the best design changed), with the
  /// best design when it changed.
  void evaluated(const OptimizeOutcome& out, const DesignSpace& space, const std::vector<double>& x, bool best_changed);

  /// A file could not be written (the search must stop); rethrow() throws that error.
  bool failed() const { return static_cast<bool>(error_); }
  void rethrow() const;

  std::size_t resumed_evaluations() const { return journal_ ? journal_->resumed() : 0; }
  long replayed_simulations() const { return replayed_simulations_; }
  std::filesystem::path journal_path() const { return journal_ ? journal_->path() : std::filesystem::path(); }

  std::chrono::duration<double> min_interval{0.5};

 private:
  std::filesystem::path dir_;
  std::optional<OptimizeJournal> journal_;
  std::string name_, file_;
  double top_rpm_ = 0.0;
  std::chrono::steady_clock::time_point last_write_{};
  long replayed_simulations_ = 0;
  std::exception_ptr error_;
};

/// The run's outputs are written: best_design.json in `dir` is removed (and
/// the checkpoint.json of an older camdyn).
void remove_checkpoint(const std::filesystem::path& dir);

}  // namespace camdyn::optim
