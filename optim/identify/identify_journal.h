// The journal of an identify run, so that a run killed part-way (even by
// SIGKILL) resumes where it stopped and ends with the same result, to the
// bit. It is `<out>/journal.jsonl`, the journal of study/journal.h (one JSON
// line per record, fsynced; a line cut by a kill is dropped), with records:
//   {"index", "kind": "point", "point": [hex], "runs": [[hex per signal] per experiment]}
//       the simulated signals of every experiment at one parameter point,
//       each double as the 16 hex digits of its bits (exact, and quick to read);
//   {"index", "kind": "iterate", "stage", "smoothing_s", "iteration", "cost", "values"}
//       an accepted iterate of the least-squares solver;
//   {"index", "kind": "stage", "stage", "smoothing_s", "iterations", "initial_cost", "final_cost", "termination",
//   "values"}
//       a finished continuation stage.
// Resuming is a replay: the fit runs again from its start, and every
// simulation found in the journal is taken from there instead of being run.
// Simulations are deterministic and so is Ceres (one thread), so the solver
// takes the same steps and ends at the same optimum, the simulation counters
// included; only the run time differs. The iterates and stages say how far
// the killed run got. The journal is kept after the run (like compare's); a
// re-run of a finished study replays it without simulating. A journal of
// another study (config, records or camdyn version changed) is refused:
// InputError, exit 2.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "optim/identify/fit_scene.h"
#include "optim/identify/identify.h"
#include "study/journal.h"

namespace camdyn::optim {

/// The study's fingerprint: the resolved scene and identify fields, the
/// records' samples and the camdyn version (what decides every simulation).
std::string identify_fingerprint(const SceneConfig& scene, const IdentifySpec& spec,
                                 const std::vector<FitExperiment>& experiments);

class IdentifyJournal {
 public:
  /// Simulated signals journaled at most (raw doubles; about twice as much
  /// text): beyond, points are still simulated but no longer journaled, so a
  /// resumed run simulates them again (same result, more time).
  static constexpr std::size_t kBudgetBytes = std::size_t{64} << 20;

  /// Opens (or creates) `<dir>/journal.jsonl` for `problem` and reads the
  /// points already simulated. Throws InputError(journal, "hash", ...) when
  /// it belongs to another study, std::runtime_error on I/O errors.
  IdentifyJournal(const std::filesystem::path& dir, const IdentifyProblem& problem);

  /// The runs of `point` (the same values to the bit) if the journal held
  /// them when it was opened, or null. Points added since are not kept here
  /// (the caller keeps what it needs): the memory stays that of the old journal.
  const std::vector<FitRun>* find(const std::vector<double>& point) const;
  /// Journals a point whose runs all succeeded (failed runs are simulated again on resume).
  void add_point(const std::vector<double>& point, const std::vector<FitRun>& runs);
  void add_iterate(std::size_t stage, double smoothing_s, int iteration, double cost,
                   const std::vector<double>& values);
  void add_stage(std::size_t stage, const StageSummary& summary);

  /// What the journal held when it was opened.
  struct Resumed {
    std::size_t points = 0;  ///< parameter points simulated
    std::size_t stages = 0;  ///< continuation stages finished
    std::optional<std::size_t> stage;
    int iteration = -1;  ///< the last accepted iterate (-1: none)
    double cost = 0.0;
  };
  const Resumed& resumed() const { return resumed_; }
  const std::filesystem::path& path() const { return journal_.path(); }

 private:
  using Key = std::vector<std::uint64_t>;
  static Key key_of(const std::vector<double>& point);
  void read_records(const IdentifyProblem& problem);
  void append(Json record);

  Journal journal_;
  std::map<Key, std::vector<FitRun>> points_;  ///< read from the journal when it was opened
  std::set<Key> journaled_;                    ///< every point in the journal (read or added)
  std::size_t next_index_ = 0;
  std::size_t bytes_ = 0;  ///< simulated signals journaled [bytes of doubles]
  Resumed resumed_;
};

}  // namespace camdyn::optim
