#include "optim/identify/identify_journal.h"

#include <camdyn/version.h>

#include <cstdio>
#include <iostream>
#include <string_view>
#include <utility>

#include "io/hex_doubles.h"
#include "optim/identify/identify_config.h"

namespace camdyn::optim {

namespace {

constexpr const char* kIdentifyJournalFile = "journal.jsonl";
/// The journal's record count bound (study/journal.h checks indices against it).
constexpr std::size_t kIdentifyMaxRecords = std::size_t{1} << 40;

std::string bytes_of(const std::vector<double>& values) {
  return {reinterpret_cast<const char*>(values.data()), values.size() * sizeof(double)};
}

/// The runs of a point record, checked against the problem's records; nothing if they do not fit.
std::optional<std::vector<FitRun>> runs_of(const Json& record, const IdentifyProblem& problem) {
  const Json& runs = record["runs"];
  if (!runs.is_array() || runs.size() != problem.experiments.size()) return std::nullopt;
  std::vector<FitRun> out(runs.size());
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const MeasuredRecord& rec = problem.experiments[k].record;
    if (!runs[k].is_array() || runs[k].size() != rec.signals.size()) return std::nullopt;
    out[k].ok = true;
    for (const Json& signal : runs[k]) {
      if (!signal.is_string()) return std::nullopt;
      auto values = doubles_from_hex(signal.get_ref<const std::string&>(), rec.time.size());
      if (!values) return std::nullopt;
      out[k].signals.push_back(std::move(*values));
    }
  }
  return out;
}

/// `<dir>/journal.jsonl`, the folder created if missing.
std::filesystem::path identify_journal_path(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  return dir / kIdentifyJournalFile;
}

}  // namespace

std::string identify_fingerprint(const SceneConfig& scene, const IdentifySpec& spec,
                                 const std::vector<FitExperiment>& experiments) {
  Json identity = Json::object();
  identity["camdyn_version"] = CAMDYN_VERSION;
  identity["scene"] = to_json(scene);
  identity["identify"] = to_json(spec);
  Json records = Json::array();
  for (const FitExperiment& e : experiments) {
    std::string samples = bytes_of(e.record.time);
    for (const std::vector<double>& y : e.record.values) samples += bytes_of(y);
    records.push_back(Json{{"scene", e.scene_json}, {"samples", fingerprint(samples)}});
  }
  identity["records"] = records;
  return fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));
}

IdentifyJournal::IdentifyJournal(const std::filesystem::path& dir, const IdentifyProblem& problem)
    : journal_(identify_journal_path(dir), "identify", problem.fingerprint, kIdentifyMaxRecords) {
  read_records(problem);
}

void IdentifyJournal::read_records(const IdentifyProblem& problem) {
  for (const auto& [index, record] : journal_.done()) {
    next_index_ = index + 1;
    const std::string kind = record.value("kind", std::string());
    if (kind == "point") {
      const Json& point = record["point"];
      auto values = point.is_string() ? doubles_from_hex(point.get_ref<const std::string&>(), problem.parameters.size())
                                      : std::nullopt;
      auto runs = runs_of(record, problem);
      if (!values || !runs) {
        std::cerr << "camdyn: warning: " << path().string() << ": record " << index
                  << " is not a simulated point of this study; it is simulated again\n";
        continue;
      }
      for (const FitRun& run : *runs)
        for (const auto& signal : run.signals) bytes_ += signal.size() * sizeof(double);
      journaled_.insert(key_of(*values));
      if (points_.emplace(key_of(*values), std::move(*runs)).second) ++resumed_.points;
    } else if (kind == "iterate") {
      resumed_.stage = record.value("stage", std::size_t{0});
      resumed_.iteration = record.value("iteration", -1);
      resumed_.cost = record.value("cost", 0.0);
    } else if (kind == "stage") {
      resumed_.stages = record.value("stage", std::size_t{0}) + 1;
    }
  }
}

IdentifyJournal::Key IdentifyJournal::key_of(const std::vector<double>& point) { return double_bits(point); }

const std::vector<FitRun>* IdentifyJournal::find(const std::vector<double>& point) const {
  const auto hit = points_.find(key_of(point));
  return hit == points_.end() ? nullptr : &hit->second;
}

void IdentifyJournal::add_point(const std::vector<double>& point, const std::vector<FitRun>& runs) {
  std::size_t bytes = 0;
  for (const FitRun& run : runs) {
    if (!run.ok) return;
    for (const auto& signal : run.signals) bytes += signal.size() * sizeof(double);
  }
  Key key = key_of(point);
  if (bytes_ + bytes > kBudgetBytes || journaled_.contains(key)) return;
  Json record = Json::object();
  record["kind"] = "point";
  record["point"] = doubles_to_hex(point);
  Json all = Json::array();
  for (const FitRun& run : runs) {
    Json signals = Json::array();
    for (const auto& signal : run.signals) signals.push_back(doubles_to_hex(signal));
    all.push_back(std::move(signals));
  }
  record["runs"] = std::move(all);
  append(std::move(record));
  bytes_ += bytes;
  journaled_.insert(std::move(key));
}

void IdentifyJournal::add_iterate(std::size_t stage, double smoothing_s, int iteration, double cost,
                                  const std::vector<double>& values) {
  // A replay passes the iterates of the killed run again: they are in already.
  if (resumed_.stage && std::pair(stage, iteration) <= std::pair(*resumed_.stage, resumed_.iteration)) return;
  append(Json{{"kind", "iterate"},
              {"stage", stage},
              {"smoothing_s", smoothing_s},
              {"iteration", iteration},
              {"cost", cost},
              {"values", values}});
}

void IdentifyJournal::add_stage(std::size_t stage, const StageSummary& summary) {
  if (stage < resumed_.stages) return;  // journaled by the killed run
  append(Json{{"kind", "stage"},
              {"stage", stage},
              {"smoothing_s", summary.smoothing_s},
              {"iterations", summary.iterations},
              {"initial_cost", summary.initial_cost},
              {"final_cost", summary.final_cost},
              {"termination", summary.termination},
              {"values", summary.values}});
}

void IdentifyJournal::append(Json record) {
  Json line = Json::object();
  line["index"] = next_index_++;
  for (auto& item : record.items()) line[item.key()] = std::move(item.value());
  journal_.append(line);
}

}  // namespace camdyn::optim
