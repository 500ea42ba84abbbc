// Runs the simulations of one design evaluation (one per operating speed) in
// parallel, on common/parallel.h's parallel_for while the caller goes on with
// its own work. Each worker number keeps its own Model and Workspace
// (Pinocchio style: the batch's model is copied and set to each job's speed,
// or built for each scene it is handed; the workspace is reused from batch to
// batch), so workers share nothing but the
// job list. Failures are caught per job and returned, so one speed that
// cannot be simulated never loses the others.
//
// Warm starts (optimizer.warm_start, docs/optimize.md "Warm starts"): a job
// may be handed a point of the once-per-revolution section
// (dynamics/poincare_map.h) where an earlier run of a nearby design ended.
// The job then integrates only the evaluated window from there and keeps it
// when the window returns to its start within kWarmStartTolerance: the
// motion had settled, and the window is one revolution of (nearly) the
// periodic orbit a cold run's window approaches. Otherwise the job runs cold,
// as without the warm start, so that a warm start never changes more than
// the settling of the metrics.
#pragma once

#include <atomic>
#include <cstddef>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/poincare_map.h"
#include "dynamics/simulation.h"
#include "io/config.h"

namespace camdyn::optim {

struct SimulationOutcome {
  enum class Status { ok, input_error, numerical_error, other_error };
  Status status = Status::ok;
  std::string error;        ///< what went wrong (empty when ok)
  SimulationResult result;  ///< valid when ok
  /// Where the run ended on the section (a whole number of revolutions of a
  /// drive that sets the speed), when end points were asked for; a later
  /// job of a nearby design may start there.
  std::optional<SectionPoint> end_point;
  bool warm = false;  ///< the metrics are over the window run from the warm start (not cold)
};

/// Largest scaled distance max_j |x_j(end) − x_j(start)| / scale_j
/// (PoincareMap::scales: the lift, its rate at speed, …) between the start
/// and the end of a warm window for its metrics to be kept [-]. The shooting
/// calls an orbit converged at 1e-7 (study/periodic_orbit.h); a loop
/// evaluation needs its objective only to the study's settling criterion,
/// 1e-3 relative (optimize.h WindowCheck::kTolerance), and with 1e-4 the kept
/// windows' objectives are the orbits' within it
/// (WarmStart.AWarmEvaluationEqualsTheSteadyStateWithinTheSettlingTolerance)
/// while most windows of a search are kept (design_loop_bench).
inline constexpr double kWarmStartTolerance = 1e-4;

/// Per job of a batch: the warm start, if any, and whether to report the end point.
struct JobStarts {
  std::vector<std::optional<SectionPoint>> warm;  ///< empty, or one per scene
  bool end_points = false;                        ///< fill SimulationOutcome::end_point
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
  /// With `model` (assembled on that geometry from a scene that differs from
  /// each job's only in the cam speed), each job copies it and sets its speed
  /// in place (set_cam_speed): the model is built once per batch.
  void submit(std::shared_ptr<const CamGeometry> geometry, std::vector<SceneConfig> scenes, SimulationOptions options,
              JobStarts starts = {}, std::shared_ptr<const Model> model = nullptr);
  std::vector<SimulationOutcome> collect();

  int threads() const { return threads_; }
  long simulations() const { return simulations_ + warm_rejected_; }
  /// Jobs whose warm window was kept, and those whose warm window was run
  /// and thrown away (they ran cold after it; simulations() counts both runs).
  long warm_kept() const { return warm_kept_; }
  long warm_rejected() const { return warm_rejected_; }

 private:
  struct Worker {
    Model model;   ///< per job: the batch's model with the job's speed, or built (the law changes with the design)
    Workspace ws;  ///< reused between jobs
  };
  void run_batch();
  void run_job(Worker& worker, std::size_t job);
  enum class Warm { not_run, kept, rejected };
  /// The warm window of `job` from `warm` into `out` when kept; not_run (the
  /// scene has no section or its window is not whole revolutions) and
  /// rejected (it did not return to its start, or failed) leave out untouched.
  Warm run_warm(Worker& worker, std::size_t job, const SectionPoint& warm, SimulationOutcome& out);

  int threads_;
  std::string file_;
  long simulations_ = 0;
  std::atomic<long> warm_kept_{0}, warm_rejected_{0};
  std::vector<std::unique_ptr<Worker>> workers_;  ///< one per worker number of parallel_for_workers

  std::vector<SceneConfig> scenes_;              ///< the current batch
  std::shared_ptr<const CamGeometry> geometry_;  ///< of every scene of the batch; null: built per job
  std::shared_ptr<const Model> model_;           ///< of the batch at another speed; null: assembled per job
  SimulationOptions options_;
  JobStarts starts_;
  std::vector<SimulationOutcome> outcomes_;
  bool pending_ = false;        ///< a batch was submitted and not collected
  std::thread batch_;           ///< runs the batch (more than one thread)
  std::exception_ptr failure_;  ///< what escaped the batch (not a simulation failure: those are outcomes)
};

}  // namespace camdyn::optim
