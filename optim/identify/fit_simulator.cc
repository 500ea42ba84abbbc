#include "optim/identify/fit_simulator.h"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <utility>

#include "common/parallel.h"
#include "optim/identify/identify_journal.h"

namespace camdyn::optim {

std::vector<std::vector<FitRun>> FitSimulator::run(const std::vector<std::vector<double>>& points) {
  const std::lock_guard<std::mutex> calls(run_mutex_);
  const std::size_t experiments = problem_.experiments.size();
  std::vector<std::vector<FitRun>> runs(points.size());
  std::vector<std::size_t> missing, simulate;  // indices into points: not kept; of those, not journaled
  for (std::size_t j = 0; j < points.size(); ++j) {
    const auto hit = std::find_if(kept_runs_.begin(), kept_runs_.end(),
                                  [&](const KeptRun& k) { return same_bits(k.point, points[j]); });
    if (hit != kept_runs_.end()) {
      runs[j] = hit->runs;
      ++reused_;
      continue;
    }
    missing.push_back(j);
    if (const std::vector<FitRun>* journaled = journal_ != nullptr ? journal_->find(points[j]) : nullptr) {
      runs[j] = *journaled;
      resumed_ += static_cast<long>(experiments);
    } else {
      runs[j].resize(experiments);
      simulate.push_back(j);
    }
  }
  const std::size_t tasks = simulate.size() * experiments;
  parallel_for(tasks, threads_, [&](std::size_t task) {
    const std::size_t j = simulate[task / experiments], k = task % experiments;
    std::unique_ptr<FitScene> scene = acquire(k);
    runs[j][k] = scene->run(points[j]);
    release(k, std::move(scene));
  });
  simulations_ += static_cast<long>(missing.size() * experiments);
  if (journal_ != nullptr)
    for (const std::size_t j : simulate) journal_->add_point(points[j], runs[j]);
  for (const std::size_t j : missing) keep(points[j], runs[j]);
  return runs;
}

std::unique_ptr<FitScene> FitSimulator::acquire(std::size_t experiment) {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::unique_ptr<FitScene>>& idle = idle_[experiment];
    if (!idle.empty()) {
      std::unique_ptr<FitScene> scene = std::move(idle.back());
      idle.pop_back();
      return scene;
    }
  }
  return std::make_unique<FitScene>(problem_.experiments[experiment], problem_.parameters, problem_.source);
}

void FitSimulator::release(std::size_t experiment, std::unique_ptr<FitScene> scene) {
  const std::lock_guard<std::mutex> lock(mutex_);
  idle_[experiment].push_back(std::move(scene));
}

std::size_t FitSimulator::kept_points(const IdentifyProblem& problem) {
  std::size_t bytes = 0;  // one point's runs
  for (const FitExperiment& e : problem.experiments)
    bytes += e.record.signals.size() * e.record.time.size() * sizeof(double);
  const std::size_t budget = std::size_t{256} << 20;
  return std::min(4 * (2 * problem.parameters.size() + 1), budget / std::max<std::size_t>(bytes, 1));
}

bool FitSimulator::same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](double x, double y) {
    return std::bit_cast<std::uint64_t>(x) == std::bit_cast<std::uint64_t>(y);
  });
}

void FitSimulator::keep(const std::vector<double>& point, const std::vector<FitRun>& runs) {
  if (kept_ == 0 || !std::all_of(runs.begin(), runs.end(), [](const FitRun& r) { return r.ok; })) return;
  if (kept_runs_.size() == kept_) kept_runs_.erase(kept_runs_.begin());
  kept_runs_.push_back({point, runs});
}

}  // namespace camdyn::optim
