#include "optim/optimize/optimize_checkpoint.h"

#include <algorithm>
#include <system_error>
#include <utility>

#include "common/study_budget.h"
#include "io/json_writer.h"
#include "optim/optimize/optimize_output.h"

namespace camdyn::optim {

namespace {

constexpr const char* kBestDesign = "best_design.json";

}  // namespace

LoopRecorder::LoopRecorder(std::filesystem::path dir, const SceneConfig& baseline, const OptimizeStudyConfig& config,
                           const DesignSpace& space, std::size_t constraints, std::string file)
    : dir_(std::move(dir)), name_(baseline.name), file_(std::move(file)) {
  if (!config.operating_rpm.empty())
    top_rpm_ = *std::max_element(config.operating_rpm.begin(), config.operating_rpm.end());
  if (dir_.empty()) return;
  journal_.emplace(dir_, optimize_fingerprint(baseline, config), static_cast<std::size_t>(space.dimension()),
                   constraints, config.optimizer.warm_start);
}

bool LoopRecorder::replay(const std::vector<double>& x, int start, DesignEvaluation& e) {
  const JournaledEvaluation* j = journal_ ? journal_->find(x, start) : nullptr;
  if (j == nullptr) return false;
  fill_evaluation(*j, e);
  replayed_simulations_ += j->simulations;
  return true;
}

void LoopRecorder::journal(const std::vector<double>& x, int start, const DesignEvaluation& e, long simulations) {
  // An evaluation the study's budget cut short is not a result: a re-run evaluates it.
  if (!journal_ || error_ || study_budget_exhausted()) return;
  try {
    journal_->add(x, JournaledEvaluation{e.valid, e.error, e.objective, e.feasible, e.constraints, simulations, start,
                                         e.end_points});
  } catch (...) {
    error_ = std::current_exception();
  }
}

void LoopRecorder::evaluated(const OptimizeOutcome& out, const DesignSpace& space, const std::vector<double>& x,
                             bool best_changed) {
  if (dir_.empty() || error_) return;
  const auto now = std::chrono::steady_clock::now();
  try {
    if (best_changed) {
      SceneConfig scene = space.scene(x);
      scene.name = name_ + "-best-so-far";
      scene.study = "simulate";
      scene.mechanism.cam.rpm = top_rpm_;
      write_json_atomic(dir_ / kBestDesign, to_json(scene));
    }
    if (best_changed || now - last_write_ >= min_interval) {
      write_history_csv(dir_ / "history.csv", out);
      last_write_ = now;
    }
  } catch (...) {
    error_ = std::current_exception();
  }
}

void LoopRecorder::rethrow() const {
  if (error_) std::rethrow_exception(error_);
}

void remove_checkpoint(const std::filesystem::path& dir) {
  if (dir.empty()) return;
  std::error_code ec;  // already gone is fine
  std::filesystem::remove(dir / kBestDesign, ec);
  std::filesystem::remove(dir / "checkpoint.json", ec);
}

}  // namespace camdyn::optim
