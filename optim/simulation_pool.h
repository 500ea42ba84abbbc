// Runs the simulations of one design evaluation (one per operating speed) in
// parallel, on common/parallel.h's parallel_for while the caller goes on with
// its own work. Each worker number keeps its own Model and Workspace
// (Pinocchio style: the model is rebuilt for each scene it is handed, the
// workspace is reused from batch to batch), so workers share nothing but the
// job list. Failures are caught per job and returned, so one speed that
// cannot be simulated never loses the others.
#pragma once

#include <cstddef>
#include <exception>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"

namespace camdyn::optim {

struct SimulationOutcome {
  enum class Status { ok, input_error, numerical_error, other_error };
  Status status = Status::ok;
  std::string error;        ///< what went wrong (empty when ok)
  SimulationResult result;  ///< valid when ok
};

class SimulationPool {
 public:
  /// `threads` workers (at least 1; with 1 the jobs run on the calling
  /// thread). `file` names the config in error messages.
  SimulationPool(int threads, std::string file);
  ~SimulationPool();
  SimulationPool(const SimulationPool&) = delete;
  SimulationPool& operator=(const SimulationPool&) = delete;

  /// Simulates every scene (in parallel) and returns the outcomes in order.
  /// Not reentrant: one batch at a time.
  std::vector<SimulationOutcome> run(const std::vector<SceneConfig>& scenes, const SimulationOptions& options);

  /// run() in two halves, so the caller can work while the workers simulate:
  /// submit() hands the batch to the workers (copied; with one thread it
  /// only stores it) and collect() waits for it (with one thread: runs it on
  /// the calling thread).
  void submit(std::vector<SceneConfig> scenes, SimulationOptions options);
  /// The same for scenes that share one geometry (the operating speeds of
  /// one design): each job assembles its model on it instead of building it.
  void submit(std::shared_ptr<const CamGeometry> geometry, std::vector<SceneConfig> scenes, SimulationOptions options);
  std::vector<SimulationOutcome> collect();

  int threads() const { return threads_; }
  long simulations() const { return simulations_; }

 private:
  struct Worker {
    Model model;   ///< rebuilt per job (the law changes with the design)
    Workspace ws;  ///< reused between jobs
  };
  void run_batch();
  void run_job(Worker& worker, std::size_t job);

  int threads_;
  std::string file_;
  long simulations_ = 0;
  std::vector<std::unique_ptr<Worker>> workers_;  ///< one per worker number of parallel_for_workers

  std::vector<SceneConfig> scenes_;              ///< the current batch
  std::shared_ptr<const CamGeometry> geometry_;  ///< of every scene of the batch; null: built per job
  SimulationOptions options_;
  std::vector<SimulationOutcome> outcomes_;
  bool pending_ = false;        ///< a batch was submitted and not collected
  std::thread batch_;           ///< runs the batch (more than one thread)
  std::exception_ptr failure_;  ///< what escaped the batch (not a simulation failure: those are outcomes)
};

}  // namespace camdyn::optim
