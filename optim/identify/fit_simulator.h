// The simulations of an identification (optim/identify/identify.h): the
// experiments simulated at parameter points in parallel, and the run cache,
// which keeps the runs of the last points so that a point asked for again
// (the next continuation stage's start, the optimum's covariance and final
// check) is not simulated twice (docs/architecture.md, "Model, parameters
// and workspaces").
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "optim/identify/fit_scene.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {

/// Simulates the experiments at parameter vectors, in parallel (parallel_for).
/// Each run takes an idle FitScene of its experiment (built on first use, one
/// per worker at most), sets the values in place and simulates: nothing is
/// rebuilt from JSON, and threads share nothing but the read-only problem.
/// The runs of the last points evaluated are kept (kept_points()): a continuation stage starts
/// where the last one stopped, and the covariance and the final check are at
/// the optimum, so their points (centre and difference steps) were simulated
/// already. A point is the same when its values are the same to the bit; the
/// simulation is deterministic, so a kept run is the run.
class FitSimulator {
 public:
  FitSimulator(const IdentifyProblem& problem, int threads, IdentifyJournal* journal)
      : problem_(problem),
        threads_(std::max(1, threads)),
        journal_(journal),
        kept_(kept_points(problem)),
        idle_(problem.experiments.size()) {}

  /// runs[j][k]: experiment k at parameter vector points[j]. A point the
  /// journal of a killed run holds is taken from there and counted as
  /// simulated, so the counters of a resumed run are those of an uninterrupted one.
  std::vector<std::vector<FitRun>> run(const std::vector<std::vector<double>>& points);

  IdentifyJournal* journal() const { return journal_; }
  long simulations() const { return simulations_; }
  /// Simulations taken from the journal of a killed run.
  long resumed_simulations() const { return resumed_; }
  /// Points whose runs were kept from an earlier call.
  long reused_points() const { return reused_; }

 private:
  std::unique_ptr<FitScene> acquire(std::size_t experiment);

  void release(std::size_t experiment, std::unique_ptr<FitScene> scene);

  /// Points kept: two Jacobians' worth (centre and 2p difference points),
  /// within 256 MB of simulated signals.
  static std::size_t kept_points(const IdentifyProblem& problem);

  struct KeptRun {
    std::vector<double> point;
    std::vector<FitRun> runs;  ///< per experiment
  };

  static bool same_bits(const std::vector<double>& a, const std::vector<double>& b);

  // Keeps a point's runs if they all succeeded, the oldest dropped beyond kept_.
  void keep(const std::vector<double>& point, const std::vector<FitRun>& runs);

  const IdentifyProblem& problem_;
  int threads_;
  IdentifyJournal* journal_;                                  ///< null: none
  std::size_t kept_;                                          ///< points whose runs are kept
  std::mutex run_mutex_;                                      ///< one run() at a time: it owns kept_runs_
  std::mutex mutex_;                                          ///< guards idle_
  std::vector<std::vector<std::unique_ptr<FitScene>>> idle_;  ///< per experiment
  std::vector<KeptRun> kept_runs_;                            ///< oldest first
  long simulations_ = 0;
  long reused_ = 0;
  long resumed_ = 0;
};

}  // namespace camdyn::optim
