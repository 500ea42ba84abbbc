#include "optim/optimize_checkpoint.h"

#include <fstream>
#include <system_error>
#include <utility>

#include "io/json_writer.h"
#include "optim/optimize_output.h"

namespace camdyn::optim {

namespace {

constexpr const char* kCheckpoint = "checkpoint.json";
constexpr const char* kBestDesign = "best_design.json";

}  // namespace

CheckpointWriter::CheckpointWriter(std::filesystem::path dir, const OptimizeStudyConfig& config, std::string name,
                                   double top_rpm, std::string file)
    : dir_(std::move(dir)), study_(to_json(config)), name_(std::move(name)), file_(std::move(file)), top_rpm_(top_rpm) {
  if (!dir_.empty()) std::filesystem::create_directories(dir_);
}

void CheckpointWriter::evaluated(const OptimizeOutcome& out, const DesignSpace& space, const std::vector<double>& x,
                                 const DesignEvaluation& e, bool best_changed) {
  if (dir_.empty()) return;
  const auto now = std::chrono::steady_clock::now();
  if (best_changed) {
    SceneConfig scene = space.scene(x);
    scene.name = name_ + "-best-so-far";
    scene.study = "simulate";
    scene.mechanism.cam.rpm = top_rpm_;
    write_json_atomic(dir_ / kBestDesign, to_json(scene));
    write_json_atomic(dir_ / kCheckpoint, Json{{"study", study_},
                                               {"x", x},
                                               {"objective", e.objective},
                                               {"feasible", e.feasible},
                                               {"evaluation", out.history.size()}});
  }
  if (best_changed || now - last_write_ >= min_interval) {
    write_history_csv(dir_ / "history.csv", out);
    last_write_ = now;
  }
}

void remove_checkpoint(const std::filesystem::path& dir) {
  if (dir.empty()) return;
  std::error_code ec;  // already gone is fine
  std::filesystem::remove(dir / kCheckpoint, ec);
  std::filesystem::remove(dir / kBestDesign, ec);
}

std::optional<std::vector<double>> read_checkpoint(const std::filesystem::path& dir, const OptimizeStudyConfig& config,
                                                   int dimension) {
  if (dir.empty()) return std::nullopt;
  std::ifstream in(dir / kCheckpoint);
  if (!in) return std::nullopt;
  const Json doc = Json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.is_object() || doc.value("study", Json()) != to_json(config)) return std::nullopt;
  const auto x = doc.find("x");
  if (x == doc.end() || !x->is_array() || static_cast<int>(x->size()) != dimension) return std::nullopt;
  std::vector<double> out;
  for (const Json& v : *x) {
    if (!v.is_number()) return std::nullopt;
    out.push_back(v.get<double>());
  }
  return out;
}

}  // namespace camdyn::optim
