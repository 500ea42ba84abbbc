#include "optim/simulation_pool.h"

#include <algorithm>
#include <exception>
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

void SimulationPool::run_job(Worker& worker, std::size_t job) {
  SimulationOutcome& out = outcomes_[job];
  const SceneConfig& scene = scenes_[job];
  try {
    worker.model = build_model(geometry_, scene, file_);
    out.result = simulate(scene, worker.model, worker.ws, options_);
    throw_if_failed(out.result);
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
                            SimulationOptions options) {
  if (pending_) throw std::logic_error("SimulationPool: a batch is already pending");
  pending_ = true;
  geometry_ = std::move(geometry);
  scenes_ = std::move(scenes);
  options_ = std::move(options);
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
