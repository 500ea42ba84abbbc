#include "optim/simulation_pool.h"

#include <algorithm>
#include <exception>
#include <stdexcept>
#include <utility>

#include "common/errors.h"

namespace camdyn::optim {

SimulationPool::SimulationPool(int threads, std::string file) : threads_(std::max(1, threads)), file_(std::move(file)) {
  for (int i = 0; i < threads_; ++i) workers_.push_back(std::make_unique<Worker>());
  if (threads_ == 1) return;  // run() works on the calling thread
  for (int i = 0; i < threads_; ++i) threads_list_.emplace_back([this, i] { work(*workers_[i]); });
}

SimulationPool::~SimulationPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_list_) t.join();
}

void SimulationPool::run_job(Worker& worker, std::size_t job) {
  SimulationOutcome& out = outcomes_[job];
  const SceneConfig& scene = scenes_[job];
  try {
    worker.model = build_model(scene, file_);
    out.result = simulate(scene, worker.model, worker.ws, options_);
    throw_if_failed(out.result);
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

void SimulationPool::work(Worker& worker) {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || next_ < count_; });
    if (stop_) return;
    const std::size_t job = next_++;
    lock.unlock();
    run_job(worker, job);
    lock.lock();
    if (++finished_ == count_) done_.notify_all();
  }
}

void SimulationPool::submit(std::vector<SceneConfig> scenes, SimulationOptions options) {
  std::unique_lock lock(mutex_);
  if (pending_) throw std::logic_error("SimulationPool: a batch is already pending");
  pending_ = true;
  scenes_ = std::move(scenes);
  options_ = std::move(options);
  outcomes_.assign(scenes_.size(), SimulationOutcome{});
  simulations_ += static_cast<long>(scenes_.size());
  next_ = 0;
  finished_ = 0;
  if (threads_list_.empty()) return;  // collect() runs it
  count_ = scenes_.size();
  wake_.notify_all();
}

std::vector<SimulationOutcome> SimulationPool::collect() {
  std::unique_lock lock(mutex_);
  if (!pending_) throw std::logic_error("SimulationPool: nothing submitted");
  if (threads_list_.empty()) {
    for (std::size_t j = 0; j < scenes_.size(); ++j) run_job(*workers_[0], j);
  } else {
    done_.wait(lock, [&] { return finished_ == count_; });
  }
  count_ = 0;
  next_ = 0;
  pending_ = false;
  return std::move(outcomes_);
}

std::vector<SimulationOutcome> SimulationPool::run(const std::vector<SceneConfig>& scenes,
                                                   const SimulationOptions& options) {
  submit(scenes, options);
  return collect();
}

}  // namespace camdyn::optim
