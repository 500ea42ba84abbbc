// The journal of an optimize run, so that a run killed part-way (even by
// SIGKILL) resumes where it stopped and ends with the same result, to the
// bit. It is `<out>/journal.jsonl`, the journal of study/journal.h (one JSON
// line per record, fsynced; a line cut by a kill is dropped), one record per
// distinct design the search loop evaluated:
//   {"index", "kind": "evaluation", "x": hex, "valid", "error", "objective": hex,
//    "feasible", "constraints": hex (value, margin, residual per constraint),
//    "holds": [bool per constraint], "simulations"}
// with every double as the 16 hex digits of its bits (io/hex_doubles.h).
// With optimizer.warm_start an evaluation depends on where the start's
// previous evaluations ended as well as on its design, so each record also
// carries "start" (the index of the start that asked) and "warm_end" (per
// operating speed, hex of the section point its run ended on,
// PoincareMap::coordinate_names() then approach speed and motor phase, or ""),
// and a design is looked up per start: the replay restores the warm states
// the uninterrupted run had, and the starts never share an evaluation.
// Resuming is a replay: the search runs again from its start, and every
// design found in the journal takes its evaluation from there instead of
// being simulated. The evaluations are deterministic and so is the search
// (seeded starts, NLopt's seeded stochastic algorithms), so it asks for the
// same designs and ends at the same optimum, the simulation counters
// included; only the run time differs. The journal is kept after the run
// (like compare's and identify's): a re-run of a finished study replays its
// loop without simulating. A journal of another study (baseline, study
// fields or camdyn version changed) is refused: InputError, exit 2.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dynamics/poincare_map.h"
#include "io/config.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize_config.h"
#include "study/journal.h"

namespace camdyn::optim {

/// The study's fingerprint: the resolved baseline, the study fields and the
/// camdyn version (what decides every evaluation of the search).
std::string optimize_fingerprint(const SceneConfig& baseline, const OptimizeStudyConfig& config);

/// What the search loop uses of one evaluation, and the simulations it took.
struct JournaledEvaluation {
  bool valid = false;
  std::string error;
  double objective = 0.0;
  bool feasible = false;
  std::vector<ConstraintValue> constraints;
  long simulations = 0;
  int start = 0;                                        ///< the start that asked (journaled with warm starts)
  std::vector<std::optional<SectionPoint>> end_points;  ///< warm starts: where each speed's run ended
};

/// What the search loop uses of a journaled evaluation, into `e` (its runs left as they are).
void fill_evaluation(const JournaledEvaluation& j, DesignEvaluation& e);

/// The journal record of the evaluation of design `x` (without its "index");
/// `per_start`: with "start" and "warm_end". Also what a rank sends rank 0 of
/// each evaluation of its starts (optim/optimize/optimize.cc, MPI ranks).
Json evaluation_record(const std::vector<double>& x, const JournaledEvaluation& e, bool per_start);

/// The design and evaluation of a record of evaluation_record, checked
/// against the study's sizes; nothing if it does not fit.
std::optional<std::pair<std::vector<double>, JournaledEvaluation>> evaluation_from_record(const Json& record,
                                                                                          std::size_t dimension,
                                                                                          std::size_t constraints);

class OptimizeJournal {
 public:
  /// Opens (or creates) `<dir>/journal.jsonl` for a study with `fingerprint`,
  /// `dimension` design variables and `constraints` constraints, and reads
  /// the evaluations already done. Throws InputError(journal, "hash", ...)
  /// when it belongs to another study, std::runtime_error on I/O errors.
  /// `per_start`: designs are looked up per start (warm starts).
  OptimizeJournal(const std::filesystem::path& dir, const std::string& fingerprint, std::size_t dimension,
                  std::size_t constraints, bool per_start = false);

  /// The evaluation of design `x` (the same values to the bit) by `start`
  /// (any start unless per_start) if the journal has it, or null.
  const JournaledEvaluation* find(const std::vector<double>& x, int start = 0) const;
  /// Journals the evaluation of `x` (by e.start) unless the journal has it already.
  void add(const std::vector<double>& x, const JournaledEvaluation& e);

  /// Designs the journal held when it was opened.
  std::size_t resumed() const { return resumed_; }
  const std::filesystem::path& path() const { return journal_.path(); }

 private:
  using Key = std::vector<std::uint64_t>;
  Key key(const std::vector<double>& x, int start) const;

  Journal journal_;
  std::size_t dimension_ = 0, constraint_count_ = 0;
  bool per_start_ = false;
  std::map<Key, JournaledEvaluation> evaluations_;
  std::size_t resumed_ = 0;
  std::size_t next_index_ = 0;
};

}  // namespace camdyn::optim
