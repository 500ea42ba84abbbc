#include "optim/simulation_pool.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/errors.h"
#include "common/parallel.h"
#include "study/steady_state.h"

namespace camdyn::optim {

SimulationPool::SimulationPool(int threads, std::string file) : threads_(std::max(1, threads)), file_(std::move(file)) {
  for (int i = 0; i < threads_; ++i) workers_.push_back(std::make_unique<Worker>());
}

SimulationPool::~SimulationPool() {
  if (batch_.joinable()) batch_.join();
}

namespace {

/// The evaluated window of a scene run in whole revolutions [rev]; 0 when it is not.
int window_revolutions(const SceneConfig& scene) {
  const SimulationConfig& sim = scene.simulation;
  if (!sim.cycles || sim.duration) return 0;
  const double window = *sim.cycles - sim.discard_cycles;
  const double whole = std::round(window);
  return whole >= 1.0 && std::abs(window - whole) < 1e-9 && std::abs(*sim.cycles - std::round(*sim.cycles)) < 1e-9
             ? static_cast<int>(whole)
             : 0;
}

/// max_j |a_j − b_j| / scale_j [-].
double scaled_distance(const PoincareMap& map, const SectionPoint& a, const SectionPoint& b) {
  if (a.x.size() != b.x.size()) return std::numeric_limits<double>::infinity();
  double d = 0.0;
  for (std::size_t j = 0; j < a.x.size(); ++j) d = std::max(d, std::abs(a.x[j] - b.x[j]) / map.scales()[j]);
  return d;
}

/// Where a converged run of `scene` on `model` ended on the section, if it did.
std::optional<SectionPoint> end_point_of(const SceneConfig& scene, const Model& model, const SimulationResult& r) {
  if (window_revolutions(scene) == 0 || r.final_state.empty() || !r.solver.converged()) return std::nullopt;
  try {
    const PoincareMap map(scene, model, "");
    return map.point(r);
  } catch (const InputError&) {  // a drive that does not set the speed: no section
    return std::nullopt;
  }
}

}  // namespace

SimulationPool::Warm SimulationPool::run_warm(Worker& worker, std::size_t job, const SectionPoint& warm,
                                              SimulationOutcome& out) {
  const SceneConfig& scene = scenes_[job];
  const int window = window_revolutions(scene);
  if (window == 0) return Warm::not_run;
  std::optional<PoincareMap> map;
  try {
    map.emplace(scene, worker.model, "");
  } catch (const InputError&) {
    return Warm::not_run;
  }
  if (static_cast<int>(warm.x.size()) != map->dimension()) return Warm::not_run;
  SimulationOptions options = options_;
  options.start = std::make_shared<const StartState>(map->start(warm));
  const SceneConfig window_scene = map->scene_for(window);
  SimulationResult result;
  try {
    result = simulate(window_scene, worker.model, worker.ws, options);
  } catch (const std::exception&) {  // no contact pair at the warm start, …: the cold run decides
    return Warm::rejected;
  }
  if (!result.solver.converged()) return Warm::rejected;
  const SectionPoint end = map->point(result);
  if (!(scaled_distance(*map, warm, end) <= kWarmStartTolerance)) return Warm::rejected;
  apply_steady_state(scene, worker.model, result, SteadyStateSearch::evaluation);
  out.result = std::move(result);
  if (starts_.end_points) out.end_point = end;
  out.warm = true;
  return Warm::kept;
}

void SimulationPool::run_job(Worker& worker, std::size_t job) {
  SimulationOutcome& out = outcomes_[job];
  const SceneConfig& scene = scenes_[job];
  try {
    if (model_) {
      worker.model = *model_;
      set_cam_speed(worker.model, scene, file_);
    } else {
      worker.model = build_model(geometry_, scene, file_);
    }
    const std::optional<SectionPoint>* warm = job < starts_.warm.size() ? &starts_.warm[job] : nullptr;
    if (warm != nullptr && warm->has_value()) {
      const Warm tried = run_warm(worker, job, **warm, out);
      if (tried == Warm::kept) {
        ++warm_kept_;
        out.status = SimulationOutcome::Status::ok;
        return;
      }
      if (tried == Warm::rejected) ++warm_rejected_;
    }
    out.result = simulate(scene, worker.model, worker.ws, options_);
    throw_if_failed(out.result);
    if (starts_.end_points) out.end_point = end_point_of(scene, worker.model, out.result);
    apply_steady_state(scene, worker.model, out.result, SteadyStateSearch::evaluation);
    out.status = SimulationOutcome::Status::ok;
  } catch (const InputError& e) {
    out.status = SimulationOutcome::Status::input_error;
    out.error = e.what();
  } catch (const NumericalError& e) {
    out.status = SimulationOutcome::Status::numerical_error;
    out.error = e.what();
  } catch (const std::exception& e) {
    out.status = SimulationOutcome::Status::other_error;
    out.error = e.what();
  }
}

void SimulationPool::run_batch() {
  try {
    parallel_for_workers(scenes_.size(), threads_, [this](int worker, std::size_t job) {
      run_job(*workers_[static_cast<std::size_t>(worker)], job);
    });
  } catch (...) {
    failure_ = std::current_exception();
  }
}

void SimulationPool::submit(std::vector<SceneConfig> scenes, SimulationOptions options) {
  submit(nullptr, std::move(scenes), std::move(options));
}

void SimulationPool::submit(std::shared_ptr<const CamGeometry> geometry, std::vector<SceneConfig> scenes,
                            SimulationOptions options, JobStarts starts, std::shared_ptr<const Model> model) {
  if (pending_) throw std::logic_error("SimulationPool: a batch is already pending");
  pending_ = true;
  geometry_ = std::move(geometry);
  model_ = std::move(model);
  scenes_ = std::move(scenes);
  options_ = std::move(options);
  starts_ = std::move(starts);
  outcomes_.assign(scenes_.size(), SimulationOutcome{});
  simulations_ += static_cast<long>(scenes_.size());
  failure_ = nullptr;
  if (threads_ == 1) return;  // collect() runs it
  batch_ = std::thread([this] { run_batch(); });
}

std::vector<SimulationOutcome> SimulationPool::collect() {
  if (!pending_) throw std::logic_error("SimulationPool: nothing submitted");
  if (batch_.joinable()) {
    batch_.join();
  } else {
    run_batch();
  }
  pending_ = false;
  if (failure_) std::rethrow_exception(failure_);
  return std::move(outcomes_);
}

std::vector<SimulationOutcome> SimulationPool::run(const std::vector<SceneConfig>& scenes,
                                                   const SimulationOptions& options) {
  submit(scenes, options);
  return collect();
}

}  // namespace camdyn::optim
